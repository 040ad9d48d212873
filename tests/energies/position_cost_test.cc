#include "msdeform/energies/position_cost.h"

#include <memory>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

// A vertex at v skinned by three nodes with weights 0.5, 0.3, 0.2.
std::vector<SkinningTerm> Terms(const Eigen::Vector3d& v) {
  const Eigen::Vector3d g[3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 1}};
  const double w[3] = {0.5, 0.3, 0.2};
  std::vector<SkinningTerm> terms;
  for (int i = 0; i < 3; ++i) terms.push_back({w[i], v - g[i], g[i]});
  return terms;
}

std::vector<std::vector<double>> IdentityBlocks(int num_nodes) {
  std::vector<std::vector<double>> blocks;
  for (int i = 0; i < num_nodes; ++i) {
    blocks.push_back({1, 0, 0, 0, 1, 0, 0, 0, 1});
    blocks.push_back({0, 0, 0});
  }
  return blocks;
}

TEST(PositionCostTest, ZeroAtRestWhenTargetIsTheVertex) {
  const Eigen::Vector3d v(0.2, 0.4, -0.3);
  std::unique_ptr<ceres::CostFunction> cost(PositionCost::Create(Terms(v), v, 10.0));
  for (double r : Residuals(*cost, IdentityBlocks(3))) EXPECT_NEAR(r, 0.0, 1e-15);
}

TEST(PositionCostTest, CommonTranslationMovesTheSkinnedVertex) {
  // Every node translated by u: the skinned vertex is v + u, so the residual
  // against target q is sqrt(w) (v + u - q).
  const Eigen::Vector3d v(0.2, 0.4, -0.3), u(1, -2, 0.5), q(0, 0, 0);
  auto blocks = IdentityBlocks(3);
  for (int i = 0; i < 3; ++i) blocks[2 * i + 1] = {u.x(), u.y(), u.z()};
  std::unique_ptr<ceres::CostFunction> cost(PositionCost::Create(Terms(v), q, 10.0));
  const std::vector<double> r = Residuals(*cost, blocks);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(r[a], 10.0 * (v + u - q)[a], 1e-13);
}

TEST(PositionCostTest, ZeroWeightTermsAreDropped) {
  auto terms = Terms(Eigen::Vector3d::Zero());
  terms.push_back({0.0, Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones()});
  PositionCostAnalytic analytic(terms, Eigen::Vector3d::Zero(), 1.0);
  EXPECT_EQ(analytic.parameter_block_sizes().size(), 6u);
}

TEST(PositionCostTest, JacobiansMatchNumericAndAnalyticMatchesAutodiff) {
  const Eigen::Vector3d v(0.2, 0.4, -0.3), q(1, 1, 1);
  std::unique_ptr<ceres::CostFunction> autodiff(PositionCost::Create(Terms(v), q, 10.0));
  PositionCostAnalytic analytic(Terms(v), q, 10.0);
  std::mt19937 random(5);
  ExpectAnalyticMatchesAutodiff(analytic, *autodiff, /*trials=*/5, /*tolerance=*/1e-11, &random);
}

TEST(PositionCostTest, SetTargetMovesTheResidual) {
  const Eigen::Vector3d v(0.2, 0.4, -0.3);
  PositionCostAnalytic analytic(Terms(v), v, 1.0);
  analytic.set_target(v + Eigen::Vector3d(0, 0, 1));
  const std::vector<double> r = Residuals(analytic, IdentityBlocks(3));
  EXPECT_NEAR(r[0], 0.0, 1e-15);
  EXPECT_NEAR(r[1], 0.0, 1e-15);
  EXPECT_NEAR(r[2], -1.0, 1e-15);
}

}  // namespace
}  // namespace msdeform
