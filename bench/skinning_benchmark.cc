// Skinning (Eq. 9, and normals with R^{-T}; core/skinning.h) of the 26K and
// 104K armadillo by random rigid node transforms of DG1, the finest graph and
// so the one with the most nodes. Target (issue 4): the 104K armadillo in
// under 2 ms with 2 threads.
//
//   build/bench/skinning_benchmark --benchmark_repetitions=5
//
// The meshes come from data/fetch_meshes.sh and msdeform_make_large; a
// missing mesh stops the benchmark with the path and what to run.

#include <map>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>
#include <glog/logging.h>

#include "bench/bench_data.h"
#include "core/deformation_graph.h"
#include "core/lattice.h"
#include "core/mesh_io.h"
#include "core/skinning.h"

namespace msdeform {
namespace {

struct Input {
  Mesh mesh;
  Eigen::Matrix3Xd normals;
  DeformationGraph dg1;
  NodeTransforms transforms;
};

const Input& LoadInput(const std::string& name) {
  static std::map<std::string, Input>* inputs = new std::map<std::string, Input>;
  auto found = inputs->find(name);
  if (found != inputs->end()) return found->second;
  Input& input = (*inputs)[name];
  input.mesh = ReadBenchMeshOrDie(name);
  std::string error;
  input.normals = VertexNormals(input.mesh);
  Lattice lattice;
  CHECK(Lattice::Build(input.mesh, LatticeOptions(), &lattice, &error)) << error;
  GraphOptions options;
  std::vector<DeformationGraph> graphs;
  CHECK(BuildCollapsedGraphs(input.mesh, lattice, options, {}, &graphs, &error)) << error;
  input.dg1 = std::move(graphs[0]);
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  input.transforms = NodeTransforms::Identity(input.dg1.num_nodes());
  for (int j = 0; j < input.dg1.num_nodes(); ++j) {
    input.transforms.rotation(j) =
        Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng))
            .normalized()
            .toRotationMatrix();
    input.transforms.translations.col(j) << normal(rng), normal(rng), normal(rng);
  }
  return input;
}

void BM_SkinPositions(benchmark::State& state, const std::string& name) {
  const Input& input = LoadInput(name);
  SkinningOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  Eigen::Matrix3Xd deformed;
  for (auto _ : state) {
    SkinPositions(input.mesh.vertices, input.dg1, input.transforms, &deformed, options);
    benchmark::DoNotOptimize(deformed.data());
  }
  state.counters["V"] = input.mesh.num_vertices();
  state.counters["nodes"] = input.dg1.num_nodes();
}

void BM_SkinNormals(benchmark::State& state, const std::string& name) {
  const Input& input = LoadInput(name);
  SkinningOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  Eigen::Matrix3Xd deformed;
  for (auto _ : state) {
    SkinNormals(input.normals, input.dg1, input.transforms, &deformed, options);
    benchmark::DoNotOptimize(deformed.data());
  }
  state.counters["V"] = input.mesh.num_vertices();
  state.counters["nodes"] = input.dg1.num_nodes();
}

// The fused pass the deformer runs (positions and normals, all vertices).
void BM_SkinPositionsAndNormals(benchmark::State& state, const std::string& name) {
  const Input& input = LoadInput(name);
  SkinningOptions options;
  options.num_threads = static_cast<int>(state.range(0));
  Eigen::Matrix3Xd deformed, deformed_normals;
  for (auto _ : state) {
    SkinPositionsAndNormals(input.mesh.vertices, input.normals, input.dg1, input.transforms,
                            nullptr, &deformed, &deformed_normals, options);
    benchmark::DoNotOptimize(deformed.data());
  }
  state.counters["V"] = input.mesh.num_vertices();
  state.counters["nodes"] = input.dg1.num_nodes();
}

BENCHMARK_CAPTURE(BM_SkinPositionsAndNormals, armadillo_104k, std::string("armadillo_104k"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkinPositions, armadillo_26k, std::string("armadillo"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkinPositions, armadillo_104k, std::string("armadillo_104k"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkinNormals, armadillo_26k, std::string("armadillo"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SkinNormals, armadillo_104k, std::string("armadillo_104k"))
    ->ArgName("threads")->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace
}  // namespace msdeform

BENCHMARK_MAIN();
