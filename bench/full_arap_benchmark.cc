// The converged ARAP reference (solvers/local_global_arap.h, the method
// full_arap) on the same handles as bench/cgal_arap_benchmark.cc: the default
// claw edit on the 26K, 104K and 416K armadillo, on 1 and 2 threads.
// Reports Setup (cotangent weights, the Laplacian and its factorisation), the
// mean frame, the iterations a frame takes to converge at the default
// tolerance (1e-9) warm-started along the drag, and the milliseconds of one
// iteration: to set beside bench/cgal_arap_benchmark.cc's 20-iteration frame
// run in the same session.
//
//   build/bench/full_arap_benchmark --benchmark_filter=104k
//
// The 1.66M-vertex mesh (msdeform_make_large --huge) runs one frame; the
// others three.

#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glog/logging.h>

#include "bench/bench_data.h"
#include "msdeform/core/handles.h"
#include "msdeform/solvers/local_global_arap.h"

namespace msdeform {
namespace {

// One benchmark iteration = Setup and the first `num_frames` frames of the
// drag, each solved to convergence from the last.
void BM_FullArapClawDrag(benchmark::State& state, const std::string& name, int num_frames = 3) {
  const ClawEdit& edit = LoadClawEdit(name);
  std::vector<int> constrained;
  std::vector<char> follows_handle;
  ConstrainedVertices(edit.layout, &constrained, &follows_handle);
  LocalGlobalArapOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  std::string error;
  double setup_ms = 0.0, frame_ms = 0.0, iterations = 0.0;
  int frames = 0;
  for (auto _ : state) {
    LocalGlobalArap arap;
    CHECK(arap.Setup(edit.mesh, constrained, options, &error)) << error;
    setup_ms = arap.setup_ms();
    Eigen::Matrix3Xd deformed = edit.mesh.vertices;
    for (int f = 0; f < num_frames && f < static_cast<int>(edit.path.size()); ++f) {
      const LocalGlobalArapSummary summary = arap.Solve(
          ConstrainedTargets(edit.mesh.vertices, constrained, follows_handle, edit.path[f]),
          &deformed);
      CHECK(summary.converged) << name << " frame " << f;
      frame_ms += summary.ms_trace.back();
      iterations += summary.iterations;
      ++frames;
    }
  }
  state.counters["setup_ms"] = setup_ms;
  state.counters["frame_ms"] = frame_ms / frames;
  state.counters["iterations"] = iterations / frames;
  state.counters["iteration_ms"] = frame_ms / iterations;
}

BENCHMARK_CAPTURE(BM_FullArapClawDrag, armadillo_26k, std::string("armadillo"))
    ->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_FullArapClawDrag, armadillo_104k, std::string("armadillo_104k"))
    ->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
BENCHMARK_CAPTURE(BM_FullArapClawDrag, armadillo_416k, std::string("armadillo_416k"))
    ->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
// msdeform_make_large --huge first; one frame.
BENCHMARK_CAPTURE(BM_FullArapClawDrag, armadillo_1664k, std::string("armadillo_1664k.ply"), 1)
    ->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace
}  // namespace msdeform

BENCHMARK_MAIN();
