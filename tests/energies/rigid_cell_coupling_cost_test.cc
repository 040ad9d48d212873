#include "msdeform/energies/rigid_cell_coupling_cost.h"

#include <cmath>
#include <memory>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "tests/energies/cost_test_util.h"

namespace msdeform {
namespace {

struct Cell {
  Eigen::Quaterniond rotation;
  Eigen::Vector3d position;  // deformed centre
};

std::vector<std::vector<double>> Blocks(const Cell& a, const Cell& b) {
  auto q = [](const Eigen::Quaterniond& r) {
    return std::vector<double>(r.coeffs().data(), r.coeffs().data() + 4);
  };
  auto p = [](const Eigen::Vector3d& x) { return std::vector<double>(x.data(), x.data() + 3); };
  return {q(a.rotation), p(a.position), q(b.rotation), p(b.position)};
}

double SquaredNorm(const std::vector<double>& residuals) {
  double sum = 0.0;
  for (double r : residuals) sum += r * r;
  return sum;
}

// 1/w^3 integral over the cube of side w at `centre` of |T_a(x) - T_b(x)|^2
// by the 2-point Gauss rule per axis, exact for the quadratic integrand.
double GaussIntegral(const Cell& a, const Eigen::Vector3d& rest_a, const Cell& b,
                     const Eigen::Vector3d& rest_b, const Eigen::Vector3d& centre, double w) {
  const double g = 0.5 * w / std::sqrt(3.0);
  double sum = 0.0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d x =
        centre + g * Eigen::Vector3d(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    const Eigen::Vector3d ta = a.rotation * (x - rest_a) + a.position;
    const Eigen::Vector3d tb = b.rotation * (x - rest_b) + b.position;
    sum += (ta - tb).squaredNorm() * (w * w * w / 8.0);
  }
  return sum / (w * w * w);
}

Cell RandomCell(std::mt19937* random) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::Vector4d q(uniform(*random), uniform(*random), uniform(*random), uniform(*random));
  return {Eigen::Quaterniond(q.normalized()),
          Eigen::Vector3d(uniform(*random), uniform(*random), uniform(*random))};
}

TEST(RigidCellCouplingCostTest, ZeroWhenBothCellsMoveByOneRigidMotion) {
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(0.9, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()));
  const Eigen::Vector3d translation(0.3, -4.0, 2.5);
  const double w = 0.25;
  const Eigen::Vector3d c_i(1.0, 2.0, 3.0);
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(w, 0, 0), Eigen::Vector3d(w, -w, 0), Eigen::Vector3d(w, w, w),
        Eigen::Vector3d(0, 0, 0)}) {
    const Eigen::Vector3d c_j = c_i + offset;
    std::unique_ptr<ceres::CostFunction> cost(RigidCellCouplingCost::CreateForCubes(c_i, c_j, w));
    const Cell a{rotation, rotation * c_i + translation};
    const Cell b{rotation, rotation * c_j + translation};
    for (double r : Residuals(*cost, Blocks(a, b))) EXPECT_NEAR(r, 0.0, 1e-14);
  }
}

TEST(RigidCellCouplingCostTest, ClosedFormEqualsTheVolumeIntegral) {
  std::mt19937 random(11);
  const double w = 0.5;
  const Eigen::Vector3d c_i(0.2, -0.1, 0.7);
  for (const Eigen::Vector3d& offset :
       {Eigen::Vector3d(w, 0, 0), Eigen::Vector3d(0, -w, w), Eigen::Vector3d(-w, w, w)}) {
    const Eigen::Vector3d c_j = c_i + offset;
    std::unique_ptr<ceres::CostFunction> cost(RigidCellCouplingCost::CreateForCubes(c_i, c_j, w));
    for (int trial = 0; trial < 5; ++trial) {
      const Cell a = RandomCell(&random), b = RandomCell(&random);
      const double integral = GaussIntegral(a, c_i, b, c_j, c_i, w) +
                              GaussIntegral(a, c_i, b, c_j, c_j, w);
      EXPECT_NEAR(SquaredNorm(Residuals(*cost, Blocks(a, b))), integral, 1e-12 * (1 + integral));
    }
  }
  // Two pieces of one cell: the one cube.
  std::unique_ptr<ceres::CostFunction> cost(RigidCellCouplingCost::CreateForCubes(c_i, c_i, w));
  const Cell a = RandomCell(&random), b = RandomCell(&random);
  const double integral = GaussIntegral(a, c_i, b, c_i, c_i, w);
  EXPECT_NEAR(SquaredNorm(Residuals(*cost, Blocks(a, b))), integral, 1e-12 * (1 + integral));
}

TEST(RigidCellCouplingCostTest, HandCheckedTranslation) {
  // Same rotation, positions 0.3 apart along x: D(x) = (0.3, 0, 0) over two
  // cubes of volume w^3 each, so E = 2 * 0.09.
  const double w = 2.0;
  std::unique_ptr<ceres::CostFunction> cost(RigidCellCouplingCost::CreateForCubes(
      Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, w), w));
  const Cell a{Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.3, 0, 0)};
  const Cell b{Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, w)};
  EXPECT_NEAR(SquaredNorm(Residuals(*cost, Blocks(a, b))), 0.18, 1e-15);
}

TEST(RigidCellCouplingCostTest, JacobiansMatchNumeric) {
  std::mt19937 random(5);
  std::unique_ptr<ceres::CostFunction> neighbours(RigidCellCouplingCost::CreateForCubes(
      Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.6, 0.2, -0.2), 0.5));
  std::unique_ptr<ceres::CostFunction> one_cell(RigidCellCouplingCost::CreateForCubes(
      Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.1, 0.2, 0.3), 0.5));
  for (int trial = 0; trial < 5; ++trial) {
    ExpectJacobianMatchesNumeric(*neighbours, Blocks(RandomCell(&random), RandomCell(&random)));
    ExpectJacobianMatchesNumeric(*one_cell, Blocks(RandomCell(&random), RandomCell(&random)));
  }
}

}  // namespace
}  // namespace msdeform
