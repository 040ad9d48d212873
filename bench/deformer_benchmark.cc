// The deformer end to end on the default edit (data/scenarios/armadillo_claw.json:
// feet fixed, a claw dragged over 30 frames) applied to the 26K, 104K and
// 416K armadillo: precompute (Init), handle-layout change (SetHandles), and
// the drag with the default solver and a few others (the _eigen_llt rows: the
// Cholesky before the supernodal default, for a before/after in one run),
// reporting median frame / solve / skin milliseconds and the median iteration
// and factorisation counts as counters.
//
//   build/bench/deformer_benchmark --benchmark_filter=104k
//
// Targets: median frame at most 2 ms at 104K and 4 ms at 416K on a 2-core
// machine with the default (Gauss-Newton) backend (issue 14; issue 7 asked
// 5 ms and 20 ms); handle-layout change < 100 ms; precompute < 1 s at 104K.
// The subspace ARAP energy (--energy=arap, issue 29): frame at most 2 ms at
// 104K, layout change at most 2x the Eq. 17 one (_arap, _arap_budget5).
// Every solver variant against every scenario, with energy gaps to a
// converged reference, is the solver lab (experiments/solver_lab.h); the
// whole-process table (peak memory, baselines) is bench/performance_table.sh.
// A missing mesh stops the benchmark with the path and what to run.

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>
#include <glog/logging.h>

#include "bench/bench_data.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/scenario.h"
#include "msdeform/core/timing.h"
#include "msdeform/methods/graph_method.h"

namespace msdeform {
namespace {

// Solver settings: the default, and the changes a user is most likely to try.
enum class Backend {
  kGaussNewton,          // the defaults
  kGaussNewtonExtrapolated,  // start from the extrapolated solution
  kGaussNewtonExact,     // J^T J factorised every iteration
  kGaussNewtonEigenLLT,  // Eigen's SimplicialLLT, the Cholesky before the supernodal default
  kGaussNewtonExactEigenLLT,  // both of the above
  kGaussNewtonLevenbergMarquardt,  // Levenberg-Marquardt damping (a factorisation a step)
  kCeres,                // Ceres, Levenberg-Marquardt, EIGEN_SPARSE
  kCeresSuiteSparse,     // Ceres with CHOLMOD
  kArap,                 // --energy=arap: the subspace ARAP energy, local/global
  kArapBudget5,          // the same with at most 5 iterations a frame
};

DeformerOptions Options(Backend backend, int threads = 2) {
  DeformerOptions options;
  options.num_threads = threads;
  switch (backend) {
    case Backend::kGaussNewton:
      break;
    case Backend::kGaussNewtonExtrapolated:
      options.initial_guess = InitialGuess::kExtrapolated;
      break;
    case Backend::kGaussNewtonExact:
      options.gauss_newton.factorization = GaussNewtonOptions::Factorization::kEveryIteration;
      break;
    case Backend::kGaussNewtonExactEigenLLT:
      options.gauss_newton.factorization = GaussNewtonOptions::Factorization::kEveryIteration;
      [[fallthrough]];
    case Backend::kGaussNewtonEigenLLT:
      options.gauss_newton.cholesky = GaussNewtonOptions::Cholesky::kEigenLLT;
      break;
    case Backend::kGaussNewtonLevenbergMarquardt:
      options.gauss_newton.damping = GaussNewtonOptions::Damping::kLevenbergMarquardt;
      break;
    case Backend::kCeresSuiteSparse:
      options.ceres.sparse_library = ceres::SUITE_SPARSE;
      [[fallthrough]];
    case Backend::kCeres:
      options.backend = Solver::kCeres;
      break;
    case Backend::kArapBudget5:
      options.stopping.max_iterations = 5;
      [[fallthrough]];
    case Backend::kArap:
      options.energy = Energy::kArap;
      break;
  }
  return options;
}

void BM_Precompute(benchmark::State& state, const std::string& name) {
  const ClawEdit& edit = LoadClawEdit(name);
  std::string error;
  for (auto _ : state) {
    GraphMethod deformer(Method::kMultiScale);
    CHECK(deformer.Precompute(edit.mesh, Options(Backend::kGaussNewton), &error)) << error;
    benchmark::DoNotOptimize(deformer.graphs().data());
  }
}

GraphMethod& CachedDeformer(const std::string& name, Backend backend, int threads = 2) {
  using Key = std::tuple<std::string, Backend, int>;
  static std::map<Key, std::unique_ptr<GraphMethod>>* cache =
      new std::map<Key, std::unique_ptr<GraphMethod>>;
  std::unique_ptr<GraphMethod>& deformer = (*cache)[Key(name, backend, threads)];
  if (deformer == nullptr) {
    deformer = std::make_unique<GraphMethod>(Method::kMultiScale);
    std::string error;
    CHECK(deformer->Precompute(LoadClawEdit(name).mesh, Options(backend, threads), &error)) << error;
  }
  return *deformer;
}

void BM_SetHandles(benchmark::State& state, const std::string& name, Backend backend) {
  const ClawEdit& edit = LoadClawEdit(name);
  GraphMethod& deformer = CachedDeformer(name, backend);
  std::string error;
  for (auto _ : state) CHECK(deformer.SetHandles(edit.layout, &error)) << error;
  state.counters["rigidity_ms"] = deformer.rigidity_ms();
  state.counters["setup_ms"] = deformer.setup_ms();
}

// One benchmark iteration = the 30-frame drag from rest; the reported time is
// the median frame (solve + skin).
void BM_ClawDrag(benchmark::State& state, const std::string& name, Backend backend) {
  const ClawEdit& edit = LoadClawEdit(name);
  GraphMethod& deformer = CachedDeformer(name, backend, static_cast<int>(state.range(0)));
  std::string error;
  std::vector<double> frame, solve, skin, iterations, factorizations;
  for (auto _ : state) {
    CHECK(deformer.SetHandles(edit.layout, &error)) << error;
    std::vector<double> frame_ms;
    DragLog log;
    CHECK(DragAlong(&deformer, edit.path, DragAlongOptions(), &log, &error)) << error;
    for (const DragStats& stats : log.frames) {
      frame_ms.push_back(stats.solve_ms + stats.skin_ms);
      solve.push_back(stats.solve_ms);
      skin.push_back(stats.skin_ms);
      iterations.push_back(stats.iterations);
      factorizations.push_back(stats.factorizations);
    }
    state.SetIterationTime(Median(frame_ms) * 1e-3);
    frame.insert(frame.end(), frame_ms.begin(), frame_ms.end());
  }
  state.counters["frame_ms"] = Median(frame);
  state.counters["solve_ms"] = Median(solve);
  state.counters["skin_ms"] = Median(skin);
  state.counters["iterations"] = Median(iterations);
  state.counters["factorizations"] = Median(factorizations);
  state.counters["variables"] = deformer.variables();
  state.counters["skinned_V"] = deformer.num_skinned_vertices();
}

#define MSDEFORM_DRAG_BENCHMARK(label, file, suffix, backend)                              \
  BENCHMARK_CAPTURE(BM_ClawDrag, label##suffix, std::string(file), backend)                 \
      ->Unit(benchmark::kMillisecond)                                                      \
      ->ArgName("threads")                                                                 \
      ->Arg(1)                                                                             \
      ->Arg(2)                                                                             \
      ->UseManualTime()                                                                    \
      ->Iterations(3)

#define MSDEFORM_MESH_BENCHMARKS(label, file)                                              \
  BENCHMARK_CAPTURE(BM_Precompute, label, std::string(file))                               \
      ->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);                       \
  BENCHMARK_CAPTURE(BM_SetHandles, label##_gauss_newton, std::string(file),                \
                    Backend::kGaussNewton)                                                 \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                      \
  BENCHMARK_CAPTURE(BM_SetHandles, label##_ceres, std::string(file), Backend::kCeres)       \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                      \
  BENCHMARK_CAPTURE(BM_SetHandles, label##_arap, std::string(file), Backend::kArap)         \
      ->Unit(benchmark::kMillisecond)->UseRealTime();                                      \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton, Backend::kGaussNewton);               \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton_extrapolated,                       \
                          Backend::kGaussNewtonExtrapolated);                              \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton_exact, Backend::kGaussNewtonExact);    \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton_eigen_llt, Backend::kGaussNewtonEigenLLT); \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton_exact_eigen_llt,                      \
                          Backend::kGaussNewtonExactEigenLLT);                             \
  MSDEFORM_DRAG_BENCHMARK(label, file, _gauss_newton_lm, Backend::kGaussNewtonLevenbergMarquardt); \
  MSDEFORM_DRAG_BENCHMARK(label, file, _ceres, Backend::kCeres);                            \
  MSDEFORM_DRAG_BENCHMARK(label, file, _ceres_suite_sparse, Backend::kCeresSuiteSparse);    \
  MSDEFORM_DRAG_BENCHMARK(label, file, _arap, Backend::kArap);                              \
  MSDEFORM_DRAG_BENCHMARK(label, file, _arap_budget5, Backend::kArapBudget5)

MSDEFORM_MESH_BENCHMARKS(armadillo_26k, "armadillo");
MSDEFORM_MESH_BENCHMARKS(armadillo_104k, "armadillo_104k");
MSDEFORM_MESH_BENCHMARKS(armadillo_416k, "armadillo_416k");

}  // namespace
}  // namespace msdeform

BENCHMARK_MAIN();
