// GraphMethod's contract with its caller: calls out of order are
// refused with a message, a failed call leaves the object as it was or with
// no layout (never a stale one), every combination of the backends' enum
// options either runs or is refused by Check, the node classes are decided
// once, and const readers are thread safe.

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/handles.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/graph_method.h"
#include "tests/scales/deformer_test_util.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

// The deformed mesh of a fresh GraphMethod: Init, SetHandles, Drag(Lift(z)).
Eigen::Matrix3Xd FreshResult(const Mesh& mesh, const DeformerOptions& options,
                             const HandleLayout& layout, double z) {
  GraphMethod graph_method(options.method);
  std::string error;
  EXPECT_TRUE(graph_method.Precompute(mesh, options, &error)) << error;
  EXPECT_TRUE(graph_method.SetHandles(layout, &error)) << error;
  EXPECT_TRUE(graph_method.Drag(Lift(z), nullptr, &error)) << error;
  return graph_method.deformed_vertices();
}

TEST(GraphMethodCallOrderTest, CallsBeforePrecomputeAreRefused) {
  const BarEdit bar(8, 2);
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  EXPECT_FALSE(graph_method.SetHandles(bar.layout, &error));
  EXPECT_NE(error.find("Precompute"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(graph_method.Drag(Lift(1.0), nullptr, &error));
  EXPECT_NE(error.find("SetHandles"), std::string::npos) << error;
}

TEST(GraphMethodCallOrderTest, DragBeforeSetHandlesIsRefused) {
  const BarEdit bar(8, 2);
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  EXPECT_FALSE(graph_method.Drag(Lift(1.0), nullptr, &error));
  EXPECT_NE(error.find("SetHandles"), std::string::npos) << error;
  EXPECT_EQ(graph_method.deformed_vertices(), bar.mesh.vertices);
}

// Init, SetHandles, Init again (another mesh, another method), Drag: the
// second Init drops the layout, so Drag is refused; after SetHandles the
// result is a fresh GraphMethod's, bit for bit.
TEST(GraphMethodCallOrderTest, RePrecomputeDropsTheLayout) {
  const BarEdit bar(8, 2);
  const Mesh longer = MakeBar(12, 1.0, 2);
  HandleLayout longer_layout;
  for (int v = 0; v < longer.num_vertices(); ++v) {
    if (longer.vertices(0, v) <= 1.0) longer_layout.fixed.push_back(v);
    if (longer.vertices(0, v) >= 11.0) longer_layout.moveable.push_back(v);
  }
  for (Method first : kAllMethods) {
    // A method is fixed when it is made: another method's options are
    // refused with one line, its own on another mesh start over.
    for (Method second : {first}) {
      GraphMethod graph_method(first);
      std::string error;
      DeformerOptions other = OptionsFor(first == Method::kStatic ? Method::kMultiScale
                                                                  : Method::kStatic);
      EXPECT_FALSE(graph_method.Precompute(bar.mesh, other, &error));
      EXPECT_NE(error.find("the options name the method"), std::string::npos) << error;
      ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(first), &error)) << error;
      ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
      ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
      ASSERT_TRUE(graph_method.Precompute(longer, OptionsFor(second), &error)) << error;
      EXPECT_EQ(graph_method.deformed_vertices(), longer.vertices);
      EXPECT_TRUE(graph_method.node_classes().empty());
      EXPECT_EQ(graph_method.variables(), 0);
      EXPECT_FALSE(graph_method.Drag(Lift(2.0), nullptr, &error)) << MethodName(second);
      ASSERT_TRUE(graph_method.SetHandles(longer_layout, &error)) << error;
      ASSERT_TRUE(graph_method.Drag(Lift(2.0), nullptr, &error)) << error;
      EXPECT_EQ(graph_method.deformed_vertices(),
                FreshResult(longer, OptionsFor(second), longer_layout, 2.0))
          << MethodName(first) << " then " << MethodName(second);
    }
  }
}

// w_con = 0 left the handle where it was and reported success; 100000
// threads crashed the skinning pool. Both are refused by Check.
TEST(GraphMethodCallOrderTest, OptionsRefuseAZeroHandleWeightAndTooManyThreads) {
  std::string error;
  DeformerOptions options;
  options.w_con = 0.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error,
            "w_con=0: expected a finite weight > 0 (at 0 the handle would not follow its target)");
  options = DeformerOptions();
  options.num_threads = kMaxThreads;
  EXPECT_TRUE(options.Check(&error)) << error;
  options.num_threads = kMaxThreads + 1;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "num_threads=1025: expected an integer in 1..1024");
}

// A failed Precompute, invalid options or a failure past the checks (the
// lattice), leaves the method empty: only Precompute is accepted.
TEST(GraphMethodCallOrderTest, FailedPrecomputeLeavesTheMethodEmpty) {
  const BarEdit bar(8, 2);
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;

  DeformerOptions invalid = OptionsFor(Method::kMultiScale);
  invalid.w_con = -1.0;
  EXPECT_FALSE(graph_method.Precompute(MakeBar(12, 1.0, 2), invalid, &error));
  EXPECT_NE(error.find("w_con"), std::string::npos) << error;
  EXPECT_EQ(graph_method.rest_mesh().num_vertices(), 0);
  EXPECT_EQ(graph_method.precompute(), nullptr);
  error.clear();
  EXPECT_FALSE(graph_method.Drag(Lift(2.0), nullptr, &error));
  EXPECT_NE(error.find("SetHandles"), std::string::npos) << error;
  EXPECT_FALSE(graph_method.SetHandles(bar.layout, &error));
  EXPECT_NE(error.find("Precompute"), std::string::npos) << error;

  // A lattice of more cells than allowed fails in Lattice::Build.
  DeformerOptions too_fine = OptionsFor(Method::kMultiScale);
  too_fine.lattice.cells_per_diagonal = 200;
  too_fine.lattice.max_grid_cells = 1000;
  EXPECT_FALSE(graph_method.Precompute(bar.mesh, too_fine, &error));
  error.clear();
  EXPECT_FALSE(graph_method.SetHandles(bar.layout, &error));
  EXPECT_NE(error.find("Precompute"), std::string::npos) << error;
  EXPECT_FALSE(graph_method.Drag(Lift(1.0), nullptr, &error));
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
  EXPECT_EQ(graph_method.deformed_vertices(),
            FreshResult(bar.mesh, OptionsFor(Method::kMultiScale), bar.layout, 1.0));
}

// A layout that fails after validation (a fixed and a moveable vertex in one
// lattice cell) leaves no layout: the next Drag is refused instead of solving
// the old one.
TEST(GraphMethodCallOrderTest, FailedSetHandlesIsNotFollowedByAStaleDrag) {
  const BarEdit bar(8, 2);
  HandleLayout conflicting = bar.layout;
  // A handle vertex that shares its lattice cell with another handle vertex
  // (cells of about one voxel), made fixed.
  DeformerOptions options = OptionsFor(Method::kMultiScale);
  options.lattice.cells_per_diagonal = 8.0;
  GraphMethod graph_method(options.method);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, options, &error)) << error;
  const int handle_vertex = bar.layout.moveable.front();
  const int cell = graph_method.lattice()->particle_of_vertex(handle_vertex);
  int neighbour = -1;
  for (int v = 0; v < bar.mesh.num_vertices() && neighbour < 0; ++v) {
    if (v != handle_vertex && graph_method.lattice()->particle_of_vertex(v) == cell) neighbour = v;
  }
  ASSERT_GE(neighbour, 0);
  conflicting.moveable.erase(
      std::find(conflicting.moveable.begin(), conflicting.moveable.end(), neighbour));
  conflicting.fixed.push_back(neighbour);
  std::sort(conflicting.fixed.begin(), conflicting.fixed.end());

  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
  EXPECT_FALSE(graph_method.SetHandles(conflicting, &error));
  EXPECT_NE(error.find("lattice cell"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(graph_method.Drag(Lift(2.0), nullptr, &error));
  EXPECT_NE(error.find("SetHandles"), std::string::npos) << error;
  EXPECT_EQ(graph_method.deformed_vertices(), bar.mesh.vertices);
  // An invalid layout (a vertex out of range) leaves no layout either.
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  HandleLayout out_of_range = bar.layout;
  out_of_range.moveable.push_back(bar.mesh.num_vertices());
  EXPECT_FALSE(graph_method.SetHandles(out_of_range, &error));
  EXPECT_FALSE(graph_method.Drag(Lift(1.0), nullptr, &error));
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
  EXPECT_EQ(graph_method.deformed_vertices(), FreshResult(bar.mesh, options, bar.layout, 1.0));
}

// Every combination of the backends' enums runs, or is refused by Check with
// one line (never a crash in Ceres's own option check).
TEST(GraphMethodCallOrderTest, EveryBackendOptionCombinationRunsOrIsRefusedByCheck) {
  BarEdit bar(8, 2);  // a coarse lattice: 186 Inits
  bar.mesh = MakeBar(8, 1.0, 1);
  bar.layout = HandleLayout();
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
    if (bar.mesh.vertices(0, v) <= 1.0) bar.layout.fixed.push_back(v);
    if (bar.mesh.vertices(0, v) >= 7.0) bar.layout.moveable.push_back(v);
  }
  int ran = 0, refused = 0;
  double reference_cost = 0.0;
  {
    GraphMethod graph_method(Method::kMultiScale);
    std::string error;
    DeformerOptions options = OptionsFor(Method::kMultiScale);
    options.lattice.cells_per_diagonal = 16.0;
    DragStats stats;
    ASSERT_TRUE(graph_method.Precompute(bar.mesh, options, &error)) << error;
    ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
    ASSERT_TRUE(graph_method.Drag(Lift(1.0), &stats, &error)) << error;
    reference_cost = stats.final_cost;
    ASSERT_GT(reference_cost, 0.0);
  }
  auto try_options = [&](const DeformerOptions& options, const std::string& name) {
    std::string error;
    if (!options.Check(&error)) {
      EXPECT_FALSE(error.empty()) << name;
      EXPECT_EQ(error.find('\n'), std::string::npos) << name << ": " << error;
      GraphMethod graph_method(options.method);
      std::string init_error;
      EXPECT_FALSE(graph_method.Precompute(bar.mesh, options, &init_error)) << name;
      EXPECT_EQ(init_error, error) << name;
      ++refused;
      return;
    }
    GraphMethod graph_method(options.method);
    DeformerOptions coarse = options;
    coarse.lattice.cells_per_diagonal = 16.0;
    ASSERT_TRUE(graph_method.Precompute(bar.mesh, coarse, &error)) << name << ": " << error;
    ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << name << ": " << error;
    DragStats stats;
    ASSERT_TRUE(graph_method.Drag(Lift(1.0), &stats, &error)) << name << ": " << error;
    // Every backend minimises the same energy: the same minimum as the
    // default's (inexact PCG and CGNR steps stop a little above it).
    EXPECT_NEAR(stats.final_cost, reference_cost, 1e-4 * reference_cost) << name;
    EXPECT_TRUE(graph_method.deformed_vertices().allFinite()) << name;
    ++ran;
  };
  for (auto trust_region : {ceres::LEVENBERG_MARQUARDT, ceres::DOGLEG}) {
    for (auto linear_solver : {ceres::SPARSE_NORMAL_CHOLESKY, ceres::CGNR}) {
      for (auto library : {ceres::EIGEN_SPARSE, ceres::SUITE_SPARSE, ceres::CX_SPARSE}) {
        for (bool grouped : {true, false}) {
          DeformerOptions options = OptionsFor(Method::kMultiScale);
          options.backend = Solver::kCeres;
          options.ceres.trust_region = trust_region;
          options.ceres.linear_solver = linear_solver;
          options.ceres.sparse_library = library;
          options.ceres.group_position_terms = grouped;
          try_options(options, "ceres " + TrustRegionName(trust_region) + " " +
                                   CeresLinearSolverName(linear_solver) + " " +
                                   SparseLibraryName(library) + (grouped ? " grouped" : ""));
        }
      }
    }
  }
  using GN = GaussNewtonOptions;
  for (auto linear_solver : {GN::LinearSolver::kCholesky, GN::LinearSolver::kPcgJacobi,
                             GN::LinearSolver::kPcgIncompleteCholesky}) {
    for (auto cholesky : {GN::Cholesky::kEigenLLT, GN::Cholesky::kEigenLDLT,
                          GN::Cholesky::kCholmod}) {
      for (auto factorization : {GN::Factorization::kEveryIteration, GN::Factorization::kPerFrame,
                                 GN::Factorization::kLagged}) {
        for (auto damping : {GN::Damping::kGaussNewton, GN::Damping::kLevenbergMarquardt}) {
          for (auto guess : {InitialGuess::kRest, InitialGuess::kPrevious,
                             InitialGuess::kExtrapolated}) {
            DeformerOptions options = OptionsFor(Method::kMultiScale);
            options.backend = Solver::kGaussNewton;
            options.gauss_newton.linear_solver = linear_solver;
            options.gauss_newton.cholesky = cholesky;
            options.gauss_newton.factorization = factorization;
            options.gauss_newton.damping = damping;
            options.initial_guess = guess;
            try_options(options, std::string("gauss_newton ") + LinearSolverName(linear_solver) +
                                     " " + CholeskyName(cholesky) + " " +
                                     FactorizationName(factorization) + " " +
                                     DampingName(damping) + " " + InitialGuessName(guess));
          }
        }
      }
    }
  }
  // Refused: the 8 combinations of each sparse library this Ceres lacks, and
  // DOGLEG with CGNR (Ceres's dogleg needs an exact factorisation) with each
  // library it has, grouped or not.
  const int available = static_cast<int>(CeresSparseLibraries().size());
  EXPECT_EQ(refused, 8 * (3 - available) + 2 * available);
  EXPECT_EQ(ran + refused, 24 + 162);
}

// The classes are decided once, before the alpha weights: on a mesh of two
// components, the still component's nodes are Fixed in selection() as in
// node_classes(), and no coherence term to a non-Totally-Free node carries
// an alpha other than 1.
TEST(GraphMethodCallOrderTest, StillComponentNodesAreFixedBeforeTheAlphaWeights) {
  // One voxel apart, and cells of about a voxel: the two bars' cells touch,
  // so graph edges join the components.
  const Mesh mesh = MakeTwoBars(8, 1, 1.0, 2);
  HandleLayout layout;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.vertices(0, v), y = mesh.vertices(1, v);
    if (y > 1.5) continue;  // the second bar: no handle
    if (x <= 1.0) layout.fixed.push_back(v);
    if (x >= 7.0) layout.moveable.push_back(v);
  }
  for (double cells_per_diagonal : {48.0, 8.0, 4.0}) {
    for (auto border : {BorderRule::kFixed, BorderRule::kHalfFree, BorderRule::kTotallyFree}) {
      const std::string name = std::string(BorderRuleName(border)) + " " +
                               std::to_string(cells_per_diagonal) + " cells per diagonal";
      DeformerOptions options = OptionsFor(Method::kMultiScale);
      options.selection.border = border;
      options.lattice.cells_per_diagonal = cells_per_diagonal;
      GraphMethod graph_method(options.method);
      std::string error;
      ASSERT_TRUE(graph_method.Precompute(mesh, options, &error)) << error;
      ASSERT_TRUE(graph_method.SetHandles(layout, &error)) << error;
      const ScaleSelection& selection = graph_method.selection();
      EXPECT_EQ(selection.node_class, graph_method.node_classes()) << name;
      const DeformationGraph& graph = graph_method.active();
      int fixed = 0, second_bar_nodes = 0;
      for (int j = 0; j < graph.num_nodes(); ++j) {
        fixed += graph_method.node_classes()[j] == NodeClass::kFixed;
        if (mesh.vertices(1, graph.node_vertex[j]) > 1.5) {
          ++second_bar_nodes;
          EXPECT_EQ(selection.node_class[j], NodeClass::kFixed) << name << " node " << j;
        }
      }
      EXPECT_GT(second_bar_nodes, 0) << name;
      EXPECT_EQ(selection.num_fixed, fixed) << name;
      EXPECT_EQ(selection.num_variables(), graph_method.variables()) << name;
      // Alpha is 1 on every coherence term that touches a non-Totally-Free node.
      const double unit_alpha_weight = std::sqrt(options.w_coh) / graph_method.diagonal();
      for (const DeformationEnergy::Coherence& term : graph_method.energy().coherence) {
        if (graph_method.node_classes()[term.j] == NodeClass::kTotallyFree &&
            graph_method.node_classes()[term.k] == NodeClass::kTotallyFree) {
          continue;
        }
        EXPECT_DOUBLE_EQ(term.sqrt_weight, unit_alpha_weight) << name << " edge " << term.j
                                                              << " " << term.k;
      }
    }
  }
}

// Under the harmonic estimate every fixed particle has e' = u = 0, so Eq. 7's
// inner max is 0: T is the floor 0.1 with a fixed handle and 0.5 without one
// (docs/method.md §4).
TEST(GraphMethodCallOrderTest, HarmonicThresholdIsConstant) {
  const BarEdit bar(8, 2);
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  EXPECT_EQ(graph_method.selection().threshold, 0.1);
  for (int v : bar.layout.fixed) {
    EXPECT_EQ(
        graph_method.rigidity().relative_extent[graph_method.lattice()->particle_of_vertex(v)],
        0.0);
  }
  HandleLayout moveable_only;
  moveable_only.moveable = bar.layout.moveable;
  ASSERT_TRUE(graph_method.SetHandles(moveable_only, &error)) << error;
  EXPECT_EQ(graph_method.selection().threshold, 0.5);
}

// Two GraphMethods dragging in two threads give what each gives alone, and
// const readers of one GraphMethod (normals skinned on first use) may run
// concurrently.
TEST(GraphMethodCallOrderTest, MethodsInParallelThreadsMatchSerialRuns) {
  const BarEdit bar(8, 2);
  const DeformerOptions multiscale = OptionsFor(Method::kMultiScale);
  const DeformerOptions dense = OptionsFor(Method::kStaticDense);
  const Eigen::Matrix3Xd serial_a = FreshResult(bar.mesh, multiscale, bar.layout, 1.0);
  const Eigen::Matrix3Xd serial_b = FreshResult(bar.mesh, dense, bar.layout, 1.5);
  Eigen::Matrix3Xd parallel_a, parallel_b;
  std::thread a([&] { parallel_a = FreshResult(bar.mesh, multiscale, bar.layout, 1.0); });
  std::thread b([&] { parallel_b = FreshResult(bar.mesh, dense, bar.layout, 1.5); });
  a.join();
  b.join();
  EXPECT_EQ(parallel_a, serial_a);
  EXPECT_EQ(parallel_b, serial_b);

  GraphMethod graph_method(multiscale.method);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, multiscale, &error)) << error;
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
  GraphMethod reference(multiscale.method);
  ASSERT_TRUE(reference.Precompute(bar.mesh, multiscale, &error)) << error;
  ASSERT_TRUE(reference.SetHandles(bar.layout, &error)) << error;
  ASSERT_TRUE(reference.Drag(Lift(1.0), nullptr, &error)) << error;
  const Eigen::Matrix3Xd expected = reference.deformed_normals();
  const GraphMethod& reader = graph_method;
  std::vector<Eigen::Matrix3Xd> read(4);
  std::vector<std::thread> readers;
  for (int t = 0; t < 4; ++t) readers.emplace_back([&, t] { read[t] = reader.deformed_normals(); });
  for (std::thread& thread : readers) thread.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(read[t], expected) << "thread " << t;
}

// The method holds the three stages (scales/precompute.h): each exists only
// once its call succeeded, a failed SetHandles drops the layout and the
// session but keeps the precompute, and a stage made by hand from the
// method's precompute drags exactly as the method does.
TEST(GraphMethodCallOrderTest, TheMethodsStagesExistOnlyOnceMade) {
  const BarEdit bar(8, 2);
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  EXPECT_EQ(graph_method.precompute(), nullptr);
  EXPECT_EQ(graph_method.setup(), nullptr);
  EXPECT_EQ(graph_method.session(), nullptr);
  DeformerOptions coarse = OptionsFor(Method::kMultiScale);
  coarse.lattice.cells_per_diagonal = 8.0;  // cells of about a voxel
  ASSERT_TRUE(graph_method.Precompute(bar.mesh, coarse, &error)) << error;
  const std::shared_ptr<const Precompute> precompute = graph_method.precompute();
  ASSERT_NE(precompute, nullptr);
  EXPECT_EQ(graph_method.setup(), nullptr);
  EXPECT_EQ(graph_method.session(), nullptr);
  ASSERT_TRUE(graph_method.SetHandles(bar.layout, &error)) << error;
  ASSERT_NE(graph_method.setup(), nullptr);
  ASSERT_NE(graph_method.session(), nullptr);
  EXPECT_EQ(&graph_method.setup()->precompute(), precompute.get());

  std::shared_ptr<const HandleSetup> setup = HandleSetup::Create(precompute, bar.layout, &error);
  ASSERT_NE(setup, nullptr) << error;
  std::unique_ptr<Session> session = Session::Create(setup, &error);
  ASSERT_NE(session, nullptr) << error;
  ASSERT_TRUE(graph_method.Drag(Lift(1.0), nullptr, &error)) << error;
  ASSERT_TRUE(session->Drag(Lift(1.0), nullptr, &error)) << error;
  EXPECT_EQ(session->deformed_vertices(), graph_method.deformed_vertices());

  // A fixed vertex made moveable: in one lattice cell with fixed ones.
  HandleLayout conflict = bar.layout;
  const Lattice& lattice = precompute->lattice();
  for (size_t i = 1; i < conflict.fixed.size(); ++i) {
    const int v = conflict.fixed[i];
    if (lattice.particle_of_vertex(v) != lattice.particle_of_vertex(conflict.fixed[0])) continue;
    conflict.fixed.erase(conflict.fixed.begin() + i);
    conflict.moveable.insert(conflict.moveable.begin(), v);
    break;
  }
  ASSERT_LT(conflict.fixed.size(), bar.layout.fixed.size()) << "no two fixed vertices share a cell";
  EXPECT_FALSE(graph_method.SetHandles(conflict, &error));
  EXPECT_NE(error.find("lattice cell"), std::string::npos) << error;
  EXPECT_EQ(graph_method.setup(), nullptr);
  EXPECT_EQ(graph_method.session(), nullptr);
  EXPECT_EQ(graph_method.precompute(), precompute);
  EXPECT_EQ(graph_method.deformed_vertices(), bar.mesh.vertices);
  // The hand-made session lives on, its layout unaffected.
  ASSERT_TRUE(session->Drag(Lift(2.0), nullptr, &error)) << error;

  ASSERT_TRUE(graph_method.Precompute(bar.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  EXPECT_NE(graph_method.precompute(), precompute);
  EXPECT_EQ(graph_method.setup(), nullptr);
}

}  // namespace
}  // namespace msdeform
