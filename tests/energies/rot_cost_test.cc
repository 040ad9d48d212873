#include "msdeform/energies/rot_cost.h"

#include <memory>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

std::vector<std::vector<double>> RotationBlock(const Eigen::Matrix3d& R) {
  return {std::vector<double>(R.data(), R.data() + 9)};
}

TEST(RotCostTest, ZeroForAnyRotationAtRest) {
  std::unique_ptr<ceres::CostFunction> cost(RotCost::Create(1.0));
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (const Eigen::Matrix3d& R : {Eigen::Matrix3d::Identity().eval(), rotation}) {
    for (double r : Residuals(*cost, RotationBlock(R))) EXPECT_NEAR(r, 0.0, 1e-14);
  }
}

TEST(RotCostTest, HandCheckedResiduals) {
  // Columns (2,0,0), (1,1,0), (0,0,1): c1.c2 = 2, c1.c3 = 0, c2.c3 = 0,
  // c1.c1 - 1 = 3, c2.c2 - 1 = 1, c3.c3 - 1 = 0; scaled by sqrt(w) = 2.
  Eigen::Matrix3d R;
  R.col(0) << 2, 0, 0;
  R.col(1) << 1, 1, 0;
  R.col(2) << 0, 0, 1;
  std::unique_ptr<ceres::CostFunction> cost(RotCost::Create(2.0));
  EXPECT_EQ(Residuals(*cost, RotationBlock(R)), (std::vector<double>{4, 0, 0, 6, 2, 0}));
}

TEST(RotCostTest, JacobiansMatchNumericAndAnalyticMatchesAutodiff) {
  std::unique_ptr<ceres::CostFunction> autodiff(RotCost::Create(1.0));
  RotCostAnalytic analytic(1.0);
  std::mt19937 random(7);
  ExpectAnalyticMatchesAutodiff(analytic, *autodiff, /*trials=*/5, /*tolerance=*/1e-12, &random);
}

}  // namespace
}  // namespace msdeform
