// One rotation cluster of the subspace ARAP energy (solvers/subspace_arap.h,
// docs/method.md §9) as a Ceres residual block of fixed size, independent of
// the cluster's vertex count. Over the slots the cluster reaches and its
// rotation, with z_d = [u_d (the slots' values in coordinate d); R_c(d, :)^T],
// the cluster's spokes sum to
//   sum_s w_s |(x'_i - x'_k) - R_c e_s|^2 = sum_d z_d^T G_c z_d,
//   G_c = [[Q_c, -K_c^T], [-K_c, Cov_c]]  (PSD, fixed per layout),
// so with G_c = A^T A (A: rank by #columns, from G_c's eigenvectors) the
// residuals are r = (A z_0, A z_1, A z_2), 3 rank of them, and 1/2 |r|^2 is
// the cluster's energy (A carries 1/unit). The same block with no rotation
// columns holds the soft constraint terms.
//
// Parameter blocks: each column a of A reads coordinate d of one block as
//   z_d(a) = block[offset + d] + constant[d]
// (block -1: the constant alone): R_j (9 doubles, column-major) gives
// R_j(d, m) at offset 3 m; t_j (3) gives t'_j = t_j + g_j at offset 0 with
// constant g_j (or g_j less an origin); a constant 12-double block of the
// handle's four slots gives slot m at 3 m; the cluster's rotation R_c (9,
// column-major, on RotationMatrixManifold) gives R_c(d, a) at 3 a. Analytic
// Jacobian.

#ifndef MSDEFORM_ENERGIES_ARAP_CLUSTER_COST_H_
#define MSDEFORM_ENERGIES_ARAP_CLUSTER_COST_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>
#include <ceres/manifold.h>

namespace msdeform {

class ArapClusterCost : public ceres::CostFunction {
 public:
  struct Column {
    int block = -1;  // index into the parameter blocks, or -1
    int offset = 0;  // coordinate d at block[offset + d]
    Eigen::Vector3d constant = Eigen::Vector3d::Zero();
  };
  // `factor`: rank by columns.size(); `block_sizes`: of the parameter
  // blocks the columns name.
  ArapClusterCost(Eigen::MatrixXd factor, std::vector<Column> columns,
                  const std::vector<int>& block_sizes);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const Eigen::MatrixXd factor_;
  const std::vector<Column> columns_;
};

// A 3x3 rotation stored as 9 doubles (column-major), updated on its tangent
// space: Plus(R, w) = R exp([w]x).
class RotationMatrixManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 9; }
  int TangentSize() const override { return 3; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

// The factor A (rank by n, rank <= n) with A^T A = G for a symmetric PSD G:
// its eigenvalues above relative_floor times the largest, scaled rows of
// eigenvectors; the rest dropped.
Eigen::MatrixXd PsdFactor(const Eigen::MatrixXd& g, double relative_floor = 1e-13);

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_ARAP_CLUSTER_COST_H_
