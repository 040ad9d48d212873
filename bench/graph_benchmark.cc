// Building the deformation graphs of all scales, with nearest nodes, weights
// and edges (core/deformation_graph.h), for the 26K and 104K armadillo.
// Target (issue 4): the 104K armadillo in under 1 s.
//
//   build/bench/graph_benchmark --benchmark_repetitions=5
//
// The meshes come from data/fetch_meshes.sh and msdeform_make_large; a
// missing mesh stops the benchmark with the path and what to run.

#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glog/logging.h>

#include "bench/bench_data.h"
#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh_io.h"

namespace msdeform {
namespace {

struct Input {
  Mesh mesh;
  Lattice lattice;
};

const Input& LoadInput(const std::string& name) {
  static std::map<std::string, Input>* inputs = new std::map<std::string, Input>;
  auto found = inputs->find(name);
  if (found != inputs->end()) return found->second;
  Input& input = (*inputs)[name];
  input.mesh = ReadBenchMeshOrDie(name);
  std::string error;
  CHECK(Lattice::Build(input.mesh, LatticeOptions(), &input.lattice, &error)) << error;
  return input;
}

void BM_BuildAllScales(benchmark::State& state, const std::string& name) {
  const Input& input = LoadInput(name);
  GraphOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  int num_scales = 0;
  for (auto _ : state) {
    std::vector<DeformationGraph> graphs;
    std::string error;
    CHECK(BuildMultiScaleGraphs(input.mesh, input.lattice, options, &graphs, &error)) << error;
    num_scales = static_cast<int>(graphs.size());
    benchmark::DoNotOptimize(graphs.data());
  }
  state.counters["V"] = input.mesh.num_vertices();
  state.counters["D1"] = input.lattice.num_surface_particles();
  state.counters["N"] = num_scales;
}

BENCHMARK_CAPTURE(BM_BuildAllScales, armadillo_26k, std::string("armadillo"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_BuildAllScales, armadillo_104k, std::string("armadillo_104k"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace msdeform

BENCHMARK_MAIN();
