#include "msdeform/energies/gauge_cost.h"

#include <cmath>
#include <memory>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

const Eigen::Vector3d kAxis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();

std::vector<std::vector<double>> RotationBlock(const Eigen::Matrix3d& R) {
  return {std::vector<double>(R.data(), R.data() + 9)};
}

// A unit vector perpendicular to kAxis, turned by `angle` within that plane.
Eigen::Vector3d Perpendicular(double angle) {
  const Eigen::Vector3d u = kAxis.unitOrthogonal();
  return Eigen::AngleAxisd(angle, kAxis) * u;
}

TEST(GaugeCostTest, ZeroAtIdentityAndForRotationsAboutPerpendicularAxes) {
  std::unique_ptr<ceres::CostFunction> autodiff(GaugeCost::Create(kAxis, 2.0));
  GaugeCostAnalytic analytic(kAxis, 2.0);
  for (const ceres::CostFunction* cost :
       {autodiff.get(), static_cast<ceres::CostFunction*>(&analytic)}) {
    EXPECT_EQ(Residuals(*cost, RotationBlock(Eigen::Matrix3d::Identity()))[0], 0.0);
    for (double direction : {0.0, 0.7, 2.0, 4.5}) {
      for (double theta : {0.3, -1.2, 2.9}) {
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(theta, Perpendicular(direction)).toRotationMatrix();
        EXPECT_NEAR(Residuals(*cost, RotationBlock(R))[0], 0.0, 1e-15) << direction << " " << theta;
      }
    }
  }
}

TEST(GaugeCostTest, SpinAboutTheAxisGivesSinTheta) {
  // omega(Q_n(theta)) = sin(theta) n, so the residual is s sin(theta): s theta
  // to first order.
  const double s = 3.0;
  GaugeCostAnalytic cost(kAxis, s);
  for (double theta : {1e-6, 0.1, 1.0, -2.5, 3.0}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(theta, kAxis).toRotationMatrix();
    EXPECT_NEAR(Residuals(cost, RotationBlock(R))[0], s * std::sin(theta), 1e-14) << theta;
  }
  const double small = 1e-6;
  EXPECT_NEAR(
      Residuals(cost, RotationBlock(Eigen::AngleAxisd(small, kAxis).toRotationMatrix()))[0],
      s * small, 1e-17);
  // And for R = I + [w]x (not a rotation) it is s n.w exactly.
  const Eigen::Vector3d w(0.2, 0.5, -0.3);
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R(2, 1) += w.x(); R(1, 2) -= w.x();
  R(0, 2) += w.y(); R(2, 0) -= w.y();
  R(1, 0) += w.z(); R(0, 1) -= w.z();
  EXPECT_NEAR(Residuals(cost, RotationBlock(R))[0], s * kAxis.dot(w), 1e-15);
}

TEST(GaugeCostTest, HandCheckedResidual) {
  // n = z: 1/2 (R(1,0) - R(0,1)) = 1/2 (4 - 1) = 1.5, times 2.
  Eigen::Matrix3d R;
  R << 1, 1, 7, 4, 1, 8, 9, 6, 1;
  GaugeCostAnalytic analytic(Eigen::Vector3d::UnitZ(), 2.0);
  std::unique_ptr<ceres::CostFunction> autodiff(GaugeCost::Create(Eigen::Vector3d::UnitZ(), 2.0));
  EXPECT_EQ(Residuals(analytic, RotationBlock(R))[0], 3.0);
  EXPECT_EQ(Residuals(*autodiff, RotationBlock(R))[0], 3.0);
}

TEST(GaugeCostTest, JacobiansMatchNumericAndAnalyticMatchesAutodiff) {
  std::unique_ptr<ceres::CostFunction> autodiff(GaugeCost::Create(kAxis, 1.5));
  GaugeCostAnalytic analytic(kAxis, 1.5);
  std::mt19937 random(13);
  ExpectAnalyticMatchesAutodiff(analytic, *autodiff, /*trials=*/5, /*tolerance=*/1e-12, &random);
}

}  // namespace
}  // namespace msdeform
