// One rigidity estimation (docs/method.md §2, S = 20 steps) on the armadillo at
// 26K and 104K vertices and the default cell width (diag / 48). Issue 3's
// target: under 50 ms for the 104K armadillo on one core.
//
//   build/bench/rigidity_benchmark --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true
//
// Handles: fixed = vertices in the lowest 5% of the bounding box in y (the
// feet); moveable = vertices within 3% of the diagonal of the vertex of
// largest x (a hand). The meshes come from data/fetch_meshes.sh and
// apps/make_large_meshes; a missing mesh is an error (non-zero exit), never a
// silent skip.
//
// Estimate/*: RigidityEstimator::Estimate alone (regions precomputed once per
// lattice), per summation method (box is the default). EstimateRigidity/*:
// the one-off free function (regions + estimate, default options). The
// lattice build is not timed.

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/build_info.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/scales/rigidity.h"

namespace msdeform {
namespace {

bool g_had_error = false;

struct Scene {
  std::string error;  // non-empty when the scene could not be built
  Mesh mesh;
  Lattice lattice;
  std::vector<int> fixed, moveable;  // particles
};

Scene MakeScene(const std::string& file) {
  Scene scene;
  const std::string path = DataDir() + "/meshes/" + file;
  std::string error;
  if (!ReadMesh(path, &scene.mesh, &error)) {
    scene.error = error + " (run data/fetch_meshes.sh and apps/make_large_meshes)";
    return scene;
  }
  if (!Lattice::Build(scene.mesh, LatticeOptions(), &scene.lattice, &error)) {
    scene.error = path + ": " + error;
    return scene;
  }
  const Eigen::AlignedBox3d box = BoundingBox(scene.mesh);
  const double diagonal = box.diagonal().norm();
  const Eigen::Matrix3Xd& x = scene.mesh.vertices;
  int rightmost = 0;
  std::vector<int> fixed_vertices, moveable_vertices;
  for (int v = 0; v < scene.mesh.num_vertices(); ++v) {
    if (x(1, v) < box.min().y() + 0.05 * box.sizes().y()) fixed_vertices.push_back(v);
    if (x(0, v) > x(0, rightmost)) rightmost = v;
  }
  for (int v = 0; v < scene.mesh.num_vertices(); ++v) {
    if ((x.col(v) - x.col(rightmost)).norm() < 0.03 * diagonal) moveable_vertices.push_back(v);
  }
  if (!ParticlesOfVertices(scene.lattice, fixed_vertices, &scene.fixed, &error) ||
      !ParticlesOfVertices(scene.lattice, moveable_vertices, &scene.moveable, &error)) {
    scene.error = path + ": " + error;
  }
  return scene;
}

const Scene& GetScene(const std::string& file) {
  static std::map<std::string, Scene>* scenes = new std::map<std::string, Scene>;
  auto it = scenes->find(file);
  if (it == scenes->end()) it = scenes->emplace(file, MakeScene(file)).first;
  return it->second;
}

bool Fail(benchmark::State& state, const std::string& message) {
  g_had_error = true;
  std::fprintf(stderr, "rigidity_benchmark: ERROR: %s\n", message.c_str());
  state.SkipWithError(message.c_str());
  return false;
}

void SetCounters(benchmark::State& state, const Scene& scene, const RigidityEstimate& estimate) {
  state.counters["vertices"] = scene.mesh.num_vertices();
  state.counters["particles"] = scene.lattice.num_particles();
  state.counters["surface"] = scene.lattice.num_surface_particles();
  state.counters["fixed"] = static_cast<double>(scene.fixed.size());
  state.counters["moveable"] = static_cast<double>(scene.moveable.size());
  RigidityOptions defaults;
  state.counters["polar_updates_per_region_step"] =
      static_cast<double>(estimate.rotation_iterations) /
      (static_cast<double>(scene.lattice.num_particles()) * defaults.num_steps);
}

void BM_Estimate(benchmark::State& state, const std::string& file, RegionSummation summation) {
  const Scene& scene = GetScene(file);
  if (!scene.error.empty()) {
    Fail(state, scene.error);
    return;
  }
  RigidityOptions options;
  options.region_summation = summation;
  RigidityEstimator estimator;
  std::string error;
  if (!estimator.Init(scene.lattice, options, &error)) {
    Fail(state, error);
    return;
  }
  RigidityEstimate estimate;
  for (auto _ : state) {
    if (!estimator.Estimate(scene.fixed, scene.moveable, &estimate, &error)) {
      Fail(state, error);
      return;
    }
    benchmark::DoNotOptimize(estimate.relative_extent.data());
  }
  SetCounters(state, scene, estimate);
  state.counters["box_particles"] = estimator.num_box_particles();
}

void BM_EstimateRigidity(benchmark::State& state, const std::string& file) {
  const Scene& scene = GetScene(file);
  if (!scene.error.empty()) {
    Fail(state, scene.error);
    return;
  }
  RigidityEstimate estimate;
  std::string error;
  for (auto _ : state) {
    if (!EstimateRigidity(scene.lattice, scene.fixed, scene.moveable, RigidityOptions(),
                          &estimate, &error)) {
      Fail(state, error);
      return;
    }
    benchmark::DoNotOptimize(estimate.relative_extent.data());
  }
  SetCounters(state, scene, estimate);
}

BENCHMARK_CAPTURE(BM_Estimate, armadillo_26k/per_region, std::string("armadillo.off"),
                  RegionSummation::kPerRegion)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimate, armadillo_26k/box, std::string("armadillo.off"),
                  RegionSummation::kBox)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimate, armadillo_104k/per_region, std::string("armadillo_104k.off"),
                  RegionSummation::kPerRegion)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Estimate, armadillo_104k/box, std::string("armadillo_104k.off"),
                  RegionSummation::kBox)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EstimateRigidity, armadillo_26k, std::string("armadillo.off"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EstimateRigidity, armadillo_104k, std::string("armadillo_104k.off"))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace msdeform

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (msdeform::g_had_error) {
    std::fprintf(stderr, "rigidity_benchmark: some benchmarks failed (see above)\n");
    return 1;
  }
  return 0;
}
