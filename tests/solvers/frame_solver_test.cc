// Both backends behind the FrameSolver seam (solvers/frame_solver.h) on an
// energy small enough to minimise by hand.

#include "msdeform/solvers/frame_solver.h"

#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/solvers/ceres_solver.h"
#include "msdeform/solvers/deformation_energy.h"
#include "msdeform/solvers/gauss_newton_solver.h"
#include "tests/solvers/frame_solver_test_util.h"

namespace msdeform {
namespace {

constexpr StoppingRule kTightStopping = TightStopping(/*max_iterations=*/200);

// Node 0 (Totally Free, at g) between two Fixed nodes at g + e and g - e,
// a coherence edge from it to each (sqrt weight a), and one Position term
// pulling it to handle * g (a vertex at the node: offset 0, weight 1, sqrt
// weight b). With d = handle * g - g and R = R_0, t = t_0 the residuals are
//   a ((R - I) e + t),  a (-(R - I) e + t),  b (t - d),  Rot(R),
// and by the parallelogram law the energy is
//   a^2 (|(R - I) e|^2 + |t|^2) + 1/2 b^2 |t - d|^2 + 1/2 |Rot(R)|^2.
// The terms in R are >= 0 and zero at R = I, where the gauge term (the spin
// about e, which no term sees) is zero too; the rest is a parabola in t:
//   t* = b^2 d / (2 a^2 + b^2),  E* = 1/2 (2 a^2 b^2 / (2 a^2 + b^2)) |d|^2.
struct HandMinimum {
  DeformationEnergy energy;
  Eigen::Affine3d handle;
  Eigen::Vector3d translation;  // t*
  double minimum;               // E*
};

HandMinimum ThreeNodes() {
  const double a = std::sqrt(10.0), b = 10.0;  // w_coh = 10, w_con = 100
  const Eigen::Vector3d g(0.3, -0.2, 0.5), e(0.4, 0.1, -0.3);
  HandMinimum hand;
  DeformationEnergy& energy = hand.energy;
  energy.node_class = {NodeClass::kTotallyFree, NodeClass::kFixed, NodeClass::kFixed};
  energy.rot_nodes = {0};
  energy.sqrt_rot = 1.0;
  energy.coherence = {{0, 1, e, a}, {0, 2, -e, a}};
  DeformationEnergy::Position position;
  position.nodes = {0};
  position.terms = {{1.0, Eigen::Vector3d::Zero(), g}};
  position.rest = g;
  position.handle_group = 0;
  position.sqrt_weight = b;
  energy.positions = {position};
  energy.gauge = GaugeTerms(energy);
  hand.handle = Eigen::Translation3d(1.0, 2.0, -0.5) *
                Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.2, -1.0, 0.4).normalized());
  const Eigen::Vector3d d = hand.handle * g - g;
  hand.translation = b * b * d / (2.0 * a * a + b * b);
  hand.minimum = 0.5 * (2.0 * a * a * b * b / (2.0 * a * a + b * b)) * d.squaredNorm();
  return hand;
}

// The Fixed nodes' transforms (identity) and node 0's start.
NodeTransforms Start() {
  NodeTransforms transforms = NodeTransforms::Identity(3);
  transforms.translations.col(0) = Eigen::Vector3d(0.1, -0.3, 0.2);
  return transforms;
}

TEST(FrameSolverTest, BothBackendsReachAMinimumComputedByHand) {
  const HandMinimum hand = ThreeNodes();
  ASSERT_EQ(hand.energy.gauge.size(), 1u);  // the spin about e
  EXPECT_NEAR(std::abs(hand.energy.gauge[0].axis.dot(hand.energy.coherence[0].edge.normalized())),
              1.0, 1e-12);
  // The hand-computed minimiser is a stationary point of the energy as
  // EvaluateEnergy writes it, and a minimum along each coordinate of t.
  NodeTransforms at_minimum = NodeTransforms::Identity(3);
  at_minimum.translations.col(0) = hand.translation;
  EXPECT_NEAR(EvaluateEnergy(hand.energy, at_minimum, hand.handle), hand.minimum,
              1e-14 * hand.minimum);
  for (int a = 0; a < 3; ++a) {
    for (double step : {-1e-3, 1e-3}) {
      NodeTransforms moved = at_minimum;
      moved.translations(a, 0) += step;
      EXPECT_GT(EvaluateEnergy(hand.energy, moved, hand.handle), hand.minimum);
    }
  }

  std::vector<std::pair<std::string, std::unique_ptr<FrameSolver>>> backends;
  backends.emplace_back("gauss_newton",
                        std::make_unique<GaussNewtonSolver>(GaussNewtonOptions(), kTightStopping));
  backends.emplace_back("ceres", std::make_unique<CeresSolver>(CeresOptions(), kTightStopping, 1));
  for (const auto& [what, solver] : backends) {
    NodeTransforms transforms = Start();
    std::string error;
    ASSERT_TRUE(solver->Setup(hand.energy, transforms, &error)) << what << ": " << error;
    EXPECT_EQ(solver->num_variables(), 12) << what;
    const SolveSummary summary = solver->Solve(hand.handle, &transforms);
    EXPECT_TRUE(summary.converged) << what << ": " << summary.message;
    EXPECT_FALSE(summary.failed) << what;
    EXPECT_LT((transforms.translations.col(0) - hand.translation).norm(), 1e-8) << what;
    EXPECT_LT((transforms.rotation(0) - Eigen::Matrix3d::Identity()).norm(), 1e-8) << what;
    EXPECT_NEAR(summary.final_cost, hand.minimum, 1e-10 * hand.minimum) << what;
    EXPECT_NEAR(solver->Cost(hand.handle, transforms), hand.minimum, 1e-10 * hand.minimum)
        << what;
    // The Fixed nodes stay where they were.
    EXPECT_EQ(transforms.translations.col(1), Eigen::Vector3d::Zero()) << what;
    EXPECT_EQ(transforms.rotation(2), Eigen::Matrix3d::Identity()) << what;
  }
}

}  // namespace
}  // namespace msdeform
