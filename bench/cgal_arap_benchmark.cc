// CGAL's ARAP (methods/cgal_arap.h: Surface_mesh_deformation, cotangent
// weights) on the same handles as bench/deformer_benchmark.cc: the default
// claw edit on the 26K, 104K and 416K armadillo. Reports the milliseconds of
// one local/global iteration (a frame of `iterations` iterations divided by
// them), the frame, and Init (Laplacian assembly and factorisation), for
// the speed table in docs/performance.md (bench/performance_table.sh).
//
//   build/bench/cgal_arap_benchmark --benchmark_filter=104k
//
// The performance table runs every benchmark but the 1664k one (filter
// -1664k); bench/scaling_table.sh adds it.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glog/logging.h>

#include "bench/bench_data.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"
#include "msdeform/methods/cgal_arap.h"

namespace msdeform {
namespace {

constexpr int kIterations = 20;  // CGAL iterations per frame (issue 6)

// One benchmark iteration = Init and the first `num_frames` frames of the
// drag (3; 1 on the 1.66M-vertex mesh, where a frame takes over a minute).
void BM_CgalArapClawDrag(benchmark::State& state, const std::string& name, int num_frames = 3) {
  const ClawEdit& edit = LoadClawEdit(name);
  CgalArapOptions options;
  options.iterations = kIterations;
  std::string error;
  double init_ms = 0.0, frame_ms = 0.0;
  int frames = 0;
  for (auto _ : state) {
    CgalArap arap;
    CHECK(arap.Init(edit.mesh, edit.layout, {}, options, &error)) << error;
    init_ms = arap.convert_ms() + arap.preprocess_ms();
    for (int f = 0; f < num_frames && f < static_cast<int>(edit.path.size()); ++f) {
      CgalArapStats stats;
      CHECK(arap.Drag(edit.path[f], &stats, &error)) << error;
      frame_ms += stats.solve_ms;
      ++frames;
    }
  }
  state.counters["init_ms"] = init_ms;
  state.counters["frame_ms"] = frame_ms / frames;
  state.counters["iteration_ms"] = frame_ms / frames / kIterations;
}

BENCHMARK_CAPTURE(BM_CgalArapClawDrag, armadillo_26k, std::string("armadillo"))
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_CgalArapClawDrag, armadillo_104k, std::string("armadillo_104k"))
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_CgalArapClawDrag, armadillo_416k, std::string("armadillo_416k"))
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
// bench/scaling_table.sh only (msdeform_make_large --huge; about 3 minutes,
// 4.4 GB): --benchmark_filter=1664k.
BENCHMARK_CAPTURE(BM_CgalArapClawDrag, armadillo_1664k, std::string("armadillo_1664k.ply"), 1)
    ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace msdeform

BENCHMARK_MAIN();
