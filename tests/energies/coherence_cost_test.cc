#include "msdeform/energies/coherence_cost.h"

#include <memory>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

const Eigen::Vector3d kGj(0.5, -1.0, 2.0);
const Eigen::Vector3d kGk(1.5, 0.0, 1.0);

TEST(CoherenceCostTest, ZeroAtRestAndUnderCommonRigidMotion) {
  std::unique_ptr<ceres::CostFunction> cost(CoherenceCost::Create(kGj, kGk, 1.0));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (double r : Residuals(*cost, {{I.data(), I.data() + 9}, {0, 0, 0}, {0, 0, 0}}))
    EXPECT_EQ(r, 0.0);
  // A rigid motion x -> Q x + u expressed per node: R = Q, t_j = Q g_j + u - g_j.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  const Eigen::Vector3d u(0.3, -0.2, 0.9);
  const Eigen::Vector3d t_j = Q * kGj + u - kGj, t_k = Q * kGk + u - kGk;
  for (double r : Residuals(*cost, {{Q.data(), Q.data() + 9},
                                    {t_j.data(), t_j.data() + 3},
                                    {t_k.data(), t_k.data() + 3}}))
    EXPECT_NEAR(r, 0.0, 1e-14);
}

TEST(CoherenceCostTest, HandCheckedResidual) {
  // R_j = 2 I, t_j = (1, 0, 0), t_k = 0: R_j (g_k - g_j) + g_j + t_j - g_k
  // = 2 (1, 1, -1) - (1, 1, -1) + (1, 0, 0) = (2, 1, -1); times sqrt(w) = 3.
  const Eigen::Matrix3d R = 2.0 * Eigen::Matrix3d::Identity();
  std::unique_ptr<ceres::CostFunction> cost(CoherenceCost::Create(kGj, kGk, 3.0));
  EXPECT_EQ(Residuals(*cost, {{R.data(), R.data() + 9}, {1, 0, 0}, {0, 0, 0}}),
            (std::vector<double>{6, 3, -3}));
}

TEST(CoherenceCostTest, JacobiansMatchNumericAndAnalyticMatchesAutodiff) {
  std::unique_ptr<ceres::CostFunction> autodiff(CoherenceCost::Create(kGj, kGk, 2.5));
  CoherenceCostAnalytic analytic(kGj, kGk, 2.5);
  std::mt19937 random(11);
  ExpectAnalyticMatchesAutodiff(analytic, *autodiff, /*trials=*/5, /*tolerance=*/1e-12, &random);
}

}  // namespace
}  // namespace msdeform
