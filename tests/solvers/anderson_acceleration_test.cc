#include "msdeform/solvers/anderson_acceleration.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace msdeform {
namespace {

// A linear contraction G(x) = A x + b with fixed point x* = (I - A)^-1 b.
struct LinearMap {
  Eigen::Matrix3d a;
  Eigen::Vector3d b;
  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const { return a * x + b; }
  Eigen::Vector3d fixed_point() const { return (Eigen::Matrix3d::Identity() - a).lu().solve(b); }
};

LinearMap SlowContraction() {
  LinearMap map;
  // Eigenvalues 0.99, 0.9 and 0.5 in a rotated basis: plain iteration needs
  // about 2,000 steps to reach 1e-9.
  const Eigen::Matrix3d basis =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  map.a = basis * Eigen::Vector3d(0.99, 0.9, 0.5).asDiagonal() * basis.transpose();
  map.b = Eigen::Vector3d(1.0, -2.0, 0.5);
  return map;
}

TEST(AndersonAccelerationTest, WindowZeroIsThePlainIteration) {
  const LinearMap map = SlowContraction();
  AndersonAcceleration anderson(3, 0);
  Eigen::VectorXd x = Eigen::Vector3d::Zero(), plain = x;
  for (int k = 0; k < 10; ++k) {
    anderson.Compute(x, map(x), &x);
    plain = map(plain);
    EXPECT_EQ(x, plain);
  }
}

// On a linear map in n dimensions Anderson acceleration with a window of at
// least n is GMRES in disguise (Walker & Ni 2011): the fixed point after at
// most n + 1 differences, up to rounding.
TEST(AndersonAccelerationTest, LinearMapSolvedInDimensionPlusTwoSteps) {
  const LinearMap map = SlowContraction();
  AndersonAcceleration anderson(3, 3);
  Eigen::VectorXd x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 5; ++k) anderson.Compute(x, map(x), &x);
  EXPECT_LT((x - map.fixed_point()).norm(), 1e-9 * map.fixed_point().norm());

  Eigen::VectorXd plain = Eigen::Vector3d::Zero();
  for (int k = 0; k < 5; ++k) plain = map(plain);
  EXPECT_GT((plain - map.fixed_point()).norm(), 0.1 * map.fixed_point().norm());
}

TEST(AndersonAccelerationTest, ResetForgetsTheHistory) {
  const LinearMap map = SlowContraction();
  AndersonAcceleration anderson(3, 2);
  Eigen::VectorXd x = Eigen::Vector3d::Zero();
  anderson.Compute(x, map(x), &x);
  anderson.Compute(x, map(x), &x);
  EXPECT_EQ(anderson.history(), 1);
  anderson.Reset();
  EXPECT_EQ(anderson.history(), 0);
  const Eigen::VectorXd g = map(x);
  Eigen::VectorXd next;
  anderson.Compute(x, g, &next);
  EXPECT_EQ(next, g);  // nothing to combine with after a reset
}

TEST(AndersonAccelerationTest, WindowBoundsTheHistory) {
  const LinearMap map = SlowContraction();
  AndersonAcceleration anderson(3, 2);
  Eigen::VectorXd x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 6; ++k) anderson.Compute(x, map(x), &x);
  EXPECT_EQ(anderson.history(), 2);
}

}  // namespace
}  // namespace msdeform
