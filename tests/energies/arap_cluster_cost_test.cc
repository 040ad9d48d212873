// ArapClusterCost and RotationMatrixManifold (energies/arap_cluster_cost.h):
// residuals A z_d with z read from the blocks as documented, the analytic
// Jacobian against numeric differences, the manifold's Plus and its
// Jacobian, and the PSD factor.

#include "msdeform/energies/arap_cluster_cost.h"

#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

ArapClusterCost MakeCost(std::mt19937* random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd factor(4, 6);
  for (int i = 0; i < factor.size(); ++i) factor.data()[i] = uniform(*random);
  // Columns: R_0(:, 1), t_0 + g, the handle's t, a constant, R_c(:, 0), R_c(:, 2).
  std::vector<ArapClusterCost::Column> columns(6);
  columns[0] = {0, 3, Eigen::Vector3d::Zero()};
  columns[1] = {1, 0, Eigen::Vector3d(0.5, -1.0, 2.0)};
  columns[2] = {2, 9, Eigen::Vector3d::Zero()};
  columns[3] = {-1, 0, Eigen::Vector3d(0.0, 1.0, 0.0)};
  columns[4] = {3, 0, Eigen::Vector3d::Zero()};
  columns[5] = {3, 6, Eigen::Vector3d::Zero()};
  return ArapClusterCost(factor, columns, {9, 3, 12, 9});
}

TEST(ArapClusterCostTest, ResidualsReadTheBlocksAsDocumented) {
  std::mt19937 random(3);
  const ArapClusterCost cost = MakeCost(&random);
  std::mt19937 values(5);
  const std::vector<std::vector<double>> blocks = RandomBlocks(cost, &values);
  ASSERT_EQ(cost.num_residuals(), 12);
  std::mt19937 again(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::MatrixXd factor(4, 6);
  for (int i = 0; i < factor.size(); ++i) factor.data()[i] = uniform(again);
  const std::vector<double> residuals = Residuals(cost, blocks);
  for (int d = 0; d < 3; ++d) {
    Eigen::VectorXd z(6);
    z << blocks[0][3 + d], blocks[1][d] + Eigen::Vector3d(0.5, -1.0, 2.0)[d], blocks[2][9 + d],
        d == 1 ? 1.0 : 0.0, blocks[3][d], blocks[3][6 + d];
    const Eigen::VectorXd expected = factor * z;
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(residuals[4 * d + i], expected[i], 1e-14);
  }
}

TEST(ArapClusterCostTest, JacobianMatchesNumeric) {
  std::mt19937 random(3);
  const ArapClusterCost cost = MakeCost(&random);
  for (int trial = 0; trial < 3; ++trial) ExpectJacobianMatchesNumeric(cost, RandomBlocks(cost, &random));
}

TEST(ArapClusterCostTest, ManifoldPlusIsARotationAndItsJacobianMatches) {
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  const RotationMatrixManifold manifold;
  const Eigen::Vector3d delta(0.1, -0.2, 0.05);
  Eigen::Matrix3d plus;
  ASSERT_TRUE(manifold.Plus(r.data(), delta.data(), plus.data()));
  EXPECT_LT((plus.transpose() * plus - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_NEAR(plus.determinant(), 1.0, 1e-14);
  Eigen::Vector3d back;
  ASSERT_TRUE(manifold.Minus(plus.data(), r.data(), back.data()));
  EXPECT_LT((back - delta).norm(), 1e-12);
  Eigen::Matrix<double, 9, 3, Eigen::RowMajor> jacobian;
  ASSERT_TRUE(manifold.PlusJacobian(r.data(), jacobian.data()));
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Eigen::Matrix3d forward, backward;
    const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(k);
    const Eigen::Vector3d back_step = -step;
    manifold.Plus(r.data(), step.data(), forward.data());
    manifold.Plus(r.data(), back_step.data(), backward.data());
    const Eigen::Matrix3d numeric = (forward - backward) / (2.0 * h);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(jacobian(i, k), numeric.data()[i], 1e-8);
  }
  Eigen::Matrix<double, 3, 9, Eigen::RowMajor> minus;
  ASSERT_TRUE(manifold.MinusJacobian(r.data(), minus.data()));
  EXPECT_LT((minus * jacobian - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

TEST(ArapClusterCostTest, PsdFactorReproducesTheGramMatrix) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(3, 5);
  const Eigen::MatrixXd gram = a.transpose() * a;  // rank 3
  const Eigen::MatrixXd factor = PsdFactor(gram);
  EXPECT_EQ(factor.rows(), 3);
  EXPECT_LT((factor.transpose() * factor - gram).norm(), 1e-12 * gram.norm());
}

}  // namespace
}  // namespace msdeform
