// The example terms of examples/energy_terms/ driven through both backends on
// a small graph built by hand: neither solver knows them, they only read
// DeformationEnergy::terms (energies/energy_term.h).

#include "examples/energy_terms/volume_term.h"

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "examples/energy_terms/rest_pose_term.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/gauss_newton_solver.h"
#include "tests/energies/cost_test_util.h"
#include "tests/scales/deformer_test_util.h"
#include "tests/solvers/frame_solver_test_util.h"

namespace msdeform {
namespace {

// A decade tighter than TightStopping's default tolerances.
constexpr StoppingRule kTightStopping =
    TightStopping(/*max_iterations=*/500, /*tolerance=*/1e-16, /*gradient_tolerance=*/1e-14);

// Nodes on a 4 x 2 x 2 grid (spacing 1), every one Totally Free with a Rot
// term, coherence edges between grid neighbours both ways, and per node two
// vertices skinned by it and its x-neighbour. The vertices with x >= 2.5
// follow the handle; the others follow it too when `all_follow`, else stay
// at rest.
struct SmallGraph {
  DeformationEnergy energy;
  std::vector<Eigen::Vector3d> nodes;
  double diagonal = 0.0;
};

SmallGraph MakeSmallGraph(bool all_follow) {
  SmallGraph graph;
  for (int x = 0; x < 4; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z) graph.nodes.emplace_back(x, y, z);
  const int n = static_cast<int>(graph.nodes.size());
  graph.diagonal = std::sqrt(3.0 * 3.0 + 1.0 + 1.0);
  DeformationEnergy& energy = graph.energy;
  energy.node_class.assign(n, NodeClass::kTotallyFree);
  for (int j = 0; j < n; ++j) energy.rot_nodes.push_back(j);
  energy.sqrt_rot = 1.0;
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d edge = graph.nodes[k] - graph.nodes[j];
      if (std::abs(edge.norm() - 1.0) < 1e-12) energy.coherence.push_back({j, k, edge, 2.0});
    }
  }
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), weight(0.2, 0.8);
  for (int j = 0; j < n; ++j) {
    const int neighbour = graph.nodes[j].x() < 3 ? j + 4 : j - 4;  // the x-neighbour
    for (int copy = 0; copy < 2; ++copy) {
      const Eigen::Vector3d v = graph.nodes[j] + Eigen::Vector3d(jitter(random), jitter(random),
                                                                 jitter(random));
      const double w = weight(random);
      DeformationEnergy::Position position;
      position.nodes = {j, neighbour};
      position.terms = {{w, v - graph.nodes[j], graph.nodes[j]},
                        {1.0 - w, v - graph.nodes[neighbour], graph.nodes[neighbour]}};
      position.rest = v;
      position.handle_group = all_follow || v.x() >= 2.5 ? 0 : -1;
      position.sqrt_weight = 3.0;
      energy.positions.push_back(position);
    }
  }
  energy.gauge = GaugeTerms(energy);
  return graph;
}

struct Solved {
  NodeTransforms transforms;
  SolveSummary summary;
};

Solved Solve(FrameSolver* solver, const DeformationEnergy& energy, const Eigen::Affine3d& handle) {
  Solved solved{NodeTransforms::Identity(static_cast<int>(energy.node_class.size())), {}};
  std::string error;
  EXPECT_TRUE(solver->Setup(energy, solved.transforms, &error)) << error;
  solved.summary = solver->Solve(handle, &solved.transforms);
  EXPECT_FALSE(solved.summary.failed) << solved.summary.message;
  return solved;
}

// Gauss-Newton, Ceres with analytic and with autodiff Jacobians.
std::vector<Solved> SolveWithEveryBackend(const DeformationEnergy& energy,
                                          const Eigen::Affine3d& handle) {
  GaussNewtonOptions exact;  // a fresh factorisation each step: Newton's convergence to the end
  exact.factorization = GaussNewtonOptions::Factorization::kEveryIteration;
  GaussNewtonSolver gauss_newton(exact, kTightStopping);
  CeresOptions autodiff_options;
  autodiff_options.jacobians = CeresOptions::Jacobians::kAutodiff;
  CeresSolver analytic(CeresOptions(), kTightStopping, 1);
  CeresSolver autodiff(autodiff_options, kTightStopping, 1);
  return {Solve(&gauss_newton, energy, handle), Solve(&analytic, energy, handle),
          Solve(&autodiff, energy, handle)};
}

// Largest distance between the skinned positions of the energy's vertices
// (its Position terms) under `a` and under `b`.
double MaxVertexDistance(const DeformationEnergy& energy, const NodeTransforms& a,
                         const NodeTransforms& b) {
  double distance = 0.0;
  for (const DeformationEnergy::Position& position : energy.positions) {
    Eigen::Vector3d difference = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < position.nodes.size(); ++i) {
      const int j = position.nodes[i];
      const SkinningTerm& skin = position.terms[i];
      difference += skin.weight * ((a.rotation(j) - b.rotation(j)) * skin.offset +
                                   a.translations.col(j) - b.translations.col(j));
    }
    distance = std::max(distance, difference.norm());
  }
  return distance;
}

// The backends (Gauss-Newton, Ceres analytic, Ceres autodiff) reach the
// same minimum: energies to 1e-12, vertices to 1e-8 of the diagonal (where
// the energy is not zero a minimiser that accepts steps on a decrease of the
// cost is determined to about sqrt(1e-16) relative; measured up to 2.4e-9 here).
void ExpectSameMinimum(const DeformationEnergy& energy, const std::vector<Solved>& solved,
                       const Eigen::Affine3d& handle, double diagonal) {
  for (size_t b = 0; b < solved.size(); ++b) {
    EXPECT_LT(MaxVertexDistance(energy, solved[b].transforms, solved[0].transforms),
              1e-8 * diagonal)
        << "backend " << b;
    EXPECT_NEAR(solved[b].summary.final_cost, solved[0].summary.final_cost,
                1e-12 * solved[0].summary.final_cost)
        << "backend " << b;
    EXPECT_NEAR(solved[b].summary.final_cost, EvaluateEnergy(energy, solved[b].transforms, handle),
                1e-12 * solved[b].summary.final_cost)
        << "backend " << b;
  }
}

Eigen::Affine3d RigidHandle() {
  return Eigen::Translation3d(0.5, -1.0, 2.0) *
         Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, 2.0, -0.5).normalized());
}

TEST(VolumeTermTest, FunctorJacobiansMatchNumericAndAnalyticMatchesAutodiff) {
  const EnergyTerm term = VolumeTerm(0, 1.7);
  std::unique_ptr<ceres::CostFunction> autodiff(term.NewCostFunction(true));
  std::unique_ptr<ceres::CostFunction> analytic(term.NewCostFunction(false));
  std::mt19937 random(11);
  ExpectAnalyticMatchesAutodiff(*analytic, *autodiff, /*trials=*/5, /*tolerance=*/1e-12, &random);
  // det(diag(2, 1, 1)) - 1 = 1; zero for a rotation.
  Eigen::Matrix3d R = Eigen::Vector3d(2.0, 1.0, 1.0).asDiagonal();
  EXPECT_DOUBLE_EQ(Residuals(*analytic, {std::vector<double>(R.data(), R.data() + 9)})[0], 1.7);
  R = RigidHandle().linear();
  EXPECT_NEAR(Residuals(*autodiff, {std::vector<double>(R.data(), R.data() + 9)})[0], 0.0, 1e-15);

  const EnergyTerm rest = RestPoseTerm(0, 2.0);
  std::unique_ptr<ceres::CostFunction> rest_cost(rest.NewCostFunction(true));
  const auto blocks = RandomBlocks(*rest_cost, &random);
  ExpectJacobianMatchesNumeric(*rest_cost, blocks);
  const std::vector<double> at_identity =
      Residuals(*rest_cost, {{1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}});
  for (double r : at_identity) EXPECT_EQ(r, 0.0);
}

// Every vertex follows a rigid handle: the minimum is that motion on every
// node (R_j = Q, t_j = Q g_j + u - g_j) at energy 0, with or without the
// volume term (det Q = 1); every backend reaches it.
TEST(VolumeTermTest, RigidTargetIsReachedExactlyByBothBackends) {
  SmallGraph graph = MakeSmallGraph(/*all_follow=*/true);
  AddVolumeTerms(5.0, &graph.energy);
  ASSERT_EQ(graph.energy.terms.size(), graph.nodes.size());
  const Eigen::Affine3d handle = RigidHandle();
  for (const Solved& solved : SolveWithEveryBackend(graph.energy, handle)) {
    EXPECT_LT(solved.summary.final_cost, 1e-20);
    EXPECT_GT(solved.summary.initial_cost, 1.0);
    for (int j = 0; j < static_cast<int>(graph.nodes.size()); ++j) {
      EXPECT_LT((solved.transforms.rotation(j) - handle.linear()).cwiseAbs().maxCoeff(), 1e-9);
      const Eigen::Vector3d t = handle * graph.nodes[j] - graph.nodes[j];
      EXPECT_LT((solved.transforms.translations.col(j) - t).norm(), 1e-9 * graph.diagonal);
    }
  }
}

// Half the vertices stretched (scale 1.4 along x, then moved), the others
// held: the volume term moves the minimum (each node's det R nearer 1), and
// Gauss-Newton and Ceres (analytic and autodiff) reach the same one, each
// reporting the energy EvaluateEnergy writes.
TEST(VolumeTermTest, NonlinearTermSameMinimumInBothBackends) {
  Eigen::Affine3d stretch = Eigen::Affine3d::Identity();
  stretch.linear() = Eigen::Vector3d(1.4, 1.0, 1.0).asDiagonal();
  const Eigen::Affine3d handle = Eigen::Translation3d(0.3, 0.2, -0.1) * stretch;
  const SmallGraph plain = MakeSmallGraph(/*all_follow=*/false);
  SmallGraph with_volume = plain;
  AddVolumeTerms(3.0, &with_volume.energy);

  auto volume_error = [](const NodeTransforms& transforms) {
    double sum = 0.0;
    for (int j = 0; j < transforms.num_nodes(); ++j)
      sum += std::abs(transforms.rotation(j).determinant() - 1.0);
    return sum;
  };
  const std::vector<Solved> without = SolveWithEveryBackend(plain.energy, handle);
  const std::vector<Solved> with = SolveWithEveryBackend(with_volume.energy, handle);
  ExpectSameMinimum(plain.energy, without, handle, plain.diagonal);
  ExpectSameMinimum(with_volume.energy, with, handle, plain.diagonal);
  EXPECT_GT(volume_error(without[0].transforms), 0.05);
  EXPECT_LT(volume_error(with[0].transforms), 0.5 * volume_error(without[0].transforms));
  // The term's own share of the energy is what EvaluateEnergy adds for it.
  DeformationEnergy only_terms;
  only_terms.node_class = with_volume.energy.node_class;
  only_terms.terms = with_volume.energy.terms;
  double volume_cost = 0.0;
  for (const EnergyTerm& term : with_volume.energy.terms)
    volume_cost += EnergyTermCost(term, with[0].transforms);
  EXPECT_GT(volume_cost, 0.0);
  EXPECT_DOUBLE_EQ(EvaluateEnergy(only_terms, with[0].transforms, handle), volume_cost);
}

// A linear term (the rest-pose regulariser) goes into the Gauss-Newton
// backend's constant part; both backends agree on the minimum it moves.
TEST(VolumeTermTest, LinearTermSameMinimumInBothBackends) {
  const Eigen::Affine3d handle =
      Eigen::Translation3d(0.0, 1.0, 0.5) * Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitZ());
  SmallGraph graph = MakeSmallGraph(/*all_follow=*/false);
  const std::vector<Solved> without = SolveWithEveryBackend(graph.energy, handle);
  for (int j = 0; j < static_cast<int>(graph.nodes.size()); ++j)
    graph.energy.terms.push_back(RestPoseTerm(j, 4.0));
  const std::vector<Solved> with = SolveWithEveryBackend(graph.energy, handle);
  ExpectSameMinimum(graph.energy, with, handle, graph.diagonal);
  // Pulled toward R = I: the last node's rotation turns less than without it.
  const int last = static_cast<int>(graph.nodes.size()) - 1;
  const double turned_without =
      (without[0].transforms.rotation(last) - Eigen::Matrix3d::Identity()).norm();
  const double turned_with =
      (with[0].transforms.rotation(last) - Eigen::Matrix3d::Identity()).norm();
  EXPECT_LT(turned_with, 0.9 * turned_without);
}

TEST(VolumeTermTest, BadTermsAreRefusedWithAMessage) {
  SmallGraph graph = MakeSmallGraph(/*all_follow=*/true);
  const NodeTransforms start = NodeTransforms::Identity(static_cast<int>(graph.nodes.size()));
  auto refused = [&](const EnergyTerm& term, const std::string& expected) {
    DeformationEnergy energy = graph.energy;
    energy.terms = {term};
    GaussNewtonSolver gauss_newton(GaussNewtonOptions(), kTightStopping);
    CeresSolver ceres(CeresOptions(), kTightStopping, 1);
    for (FrameSolver* solver : std::vector<FrameSolver*>{&gauss_newton, &ceres}) {
      std::string error;
      EXPECT_FALSE(solver->Setup(energy, start, &error));
      EXPECT_NE(error.find(expected), std::string::npos) << error;
      EXPECT_NE(error.find("'volume'"), std::string::npos) << error;
    }
  };
  refused(VolumeTerm(99, 1.0), "node 99");
  EnergyTerm twice = VolumeTerm(0, 1.0);
  twice.blocks.push_back(TermBlock::Rotation(0));
  refused(twice, "twice");
  EnergyTerm wrong_size = VolumeTerm(0, 1.0);
  wrong_size.blocks = {TermBlock::Translation(0)};
  refused(wrong_size, "parameter blocks");
}

// The term in a Deformer solve through DeformerOptions::add_energy_terms: the
// hook adds one term per free node of each layout, and Gauss-Newton and
// Ceres reach the same minimum with it on a bar squeezed along its length.
TEST(VolumeTermTest, DeformerRunsTheTermThroughEitherBackend) {
  const BarEdit bar;  // 12 x 1 x 1
  Eigen::Affine3d squeeze = Eigen::Affine3d::Identity();
  squeeze.translation() << -2.0, 0.5, 0.0;
  std::vector<Eigen::Matrix3Xd> results;
  std::vector<double> costs;
  for (Solver backend : {Solver::kGaussNewton, Solver::kCeres}) {
    DeformerOptions options;
    options.backend = backend;
    options.stopping = kTightStopping;
    options.add_energy_terms = [](const DeformationGraph&, DeformationEnergy* energy) {
      AddVolumeTerms(3.0, energy);
    };
    GraphMethod deformer(options.method);
    std::string error;
    ASSERT_TRUE(deformer.Precompute(bar.mesh, options, &error)) << error;
    ASSERT_TRUE(deformer.SetHandles(bar.layout, &error)) << error;
    int free_nodes = 0;
    for (NodeClass c : deformer.node_classes()) free_nodes += c != NodeClass::kFixed;
    EXPECT_EQ(static_cast<int>(deformer.energy().terms.size()), free_nodes);
    DragStats stats;
    ASSERT_TRUE(deformer.Drag(squeeze, &stats, &error)) << error;
    EXPECT_NEAR(stats.final_cost,
                EvaluateEnergy(deformer.energy(), deformer.transforms(), squeeze),
                1e-12 * std::max(1.0, stats.final_cost));
    results.push_back(deformer.deformed_vertices());
    costs.push_back(stats.final_cost);
  }
  EXPECT_NEAR(costs[0], costs[1], 1e-9 * costs[0]);
  const double diagonal = std::sqrt(12.0 * 12.0 + 2.0);
  EXPECT_LT((results[0] - results[1]).colwise().norm().maxCoeff(), 1e-7 * diagonal);
}

// A term whose functor refuses a point (R_00 < 0.99, outside its domain)
// makes the cost NaN there in both backends: the steps that reach it are
// rejected, and the solve ends on a finite cost inside the domain instead of
// stopping the program.
struct DomainLimitedCost {
  template <typename T>
  bool operator()(const T* rotation, T* residual) const {
    if (rotation[0] < T(0.99)) return false;
    residual[0] = rotation[0] - T(1.0);
    return true;
  }
};

TEST(VolumeTermTest, ATermOutsideItsDomainRejectsTheStepInBothBackends) {
  SmallGraph graph = MakeSmallGraph(/*all_follow=*/true);
  const int n = static_cast<int>(graph.nodes.size());
  for (int j = 0; j < n; ++j) {
    graph.energy.terms.push_back(MakeEnergyTerm<DomainLimitedCost, 1, 9>(
        "domain_limited", {TermBlock::Rotation(j)}, /*linear=*/false, DomainLimitedCost()));
  }
  const Eigen::Affine3d handle = RigidHandle();
  GaussNewtonSolver gauss_newton(GaussNewtonOptions(), kTightStopping);
  CeresSolver ceres(CeresOptions(), kTightStopping, 1);
  for (FrameSolver* solver : std::vector<FrameSolver*>{&gauss_newton, &ceres}) {
    const Solved solved = Solve(solver, graph.energy, handle);
    ASSERT_FALSE(solved.summary.failed) << solved.summary.message;
    EXPECT_TRUE(std::isfinite(solved.summary.final_cost));
    for (int j = 0; j < n; ++j) EXPECT_GE(solved.transforms.rotation(j)(0, 0), 0.99) << j;
  }
}

}  // namespace
}  // namespace msdeform
