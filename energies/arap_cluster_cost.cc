#include "msdeform/energies/arap_cluster_cost.h"

#include <cmath>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <glog/logging.h>

namespace msdeform {

ArapClusterCost::ArapClusterCost(Eigen::MatrixXd factor, std::vector<Column> columns,
                                 const std::vector<int>& block_sizes)
    : factor_(std::move(factor)), columns_(std::move(columns)) {
  CHECK_EQ(factor_.cols(), static_cast<int>(columns_.size()));
  for (const Column& column : columns_) {
    CHECK_LT(column.block, static_cast<int>(block_sizes.size()));
    if (column.block >= 0) CHECK_LE(column.offset + 3, block_sizes[column.block]);
  }
  set_num_residuals(3 * static_cast<int>(factor_.rows()));
  *mutable_parameter_block_sizes() = block_sizes;
}

bool ArapClusterCost::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  const int rank = static_cast<int>(factor_.rows());
  const int n = static_cast<int>(columns_.size());
  Eigen::Matrix<double, Eigen::Dynamic, 3> z(n, 3);
  for (int a = 0; a < n; ++a) {
    const Column& column = columns_[a];
    for (int d = 0; d < 3; ++d) {
      z(a, d) = column.constant[d] +
                (column.block >= 0 ? parameters[column.block][column.offset + d] : 0.0);
    }
  }
  // residuals[d rank + i] = (A z_d)_i
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3>> r(residuals, rank, 3);
  r.noalias() = factor_ * z;
  if (jacobians == nullptr) return true;
  const std::vector<int>& sizes = parameter_block_sizes();
  for (size_t b = 0; b < sizes.size(); ++b) {
    if (jacobians[b] != nullptr) std::fill(jacobians[b], jacobians[b] + 3 * rank * sizes[b], 0.0);
  }
  for (int a = 0; a < n; ++a) {
    const Column& column = columns_[a];
    if (column.block < 0 || jacobians[column.block] == nullptr) continue;
    double* jacobian = jacobians[column.block];
    const int size = sizes[column.block];
    for (int d = 0; d < 3; ++d) {
      for (int i = 0; i < rank; ++i)
        jacobian[(d * rank + i) * size + column.offset + d] += factor_(i, a);
    }
  }
  return true;
}

namespace {

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d hat;
  hat << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return hat;
}

}  // namespace

bool RotationMatrixManifold::Plus(const double* x, const double* delta,
                                  double* x_plus_delta) const {
  const Eigen::Map<const Eigen::Matrix3d> r(x);
  const Eigen::Map<const Eigen::Vector3d> w(delta);
  const double angle = w.norm();
  const Eigen::Matrix3d step = angle > 0.0
                                   ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                   : Eigen::Matrix3d::Identity();
  Eigen::Map<Eigen::Matrix3d> result(x_plus_delta);
  result = r * step;
  return true;
}

bool RotationMatrixManifold::PlusJacobian(const double* x, double* jacobian) const {
  // Column k: R [e_k]x, entry (d, m) at row 3 m + d; 9 by 3, row-major.
  const Eigen::Map<const Eigen::Matrix3d> r(x);
  Eigen::Map<Eigen::Matrix<double, 9, 3, Eigen::RowMajor>> j(jacobian);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Matrix3d column = r * Hat(Eigen::Vector3d::Unit(k));
    j.col(k) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(column.data());
  }
  return true;
}

bool RotationMatrixManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  const Eigen::Map<const Eigen::Matrix3d> ry(y), rx(x);
  const Eigen::AngleAxisd difference(Eigen::Matrix3d(rx.transpose() * ry));
  Eigen::Map<Eigen::Vector3d> result(y_minus_x);
  result = difference.angle() * difference.axis();
  return true;
}

bool RotationMatrixManifold::MinusJacobian(const double* x, double* jacobian) const {
  // The columns of PlusJacobian are orthogonal with squared norm 2.
  Eigen::Matrix<double, 9, 3, Eigen::RowMajor> plus;
  PlusJacobian(x, plus.data());
  Eigen::Map<Eigen::Matrix<double, 3, 9, Eigen::RowMajor>> result(jacobian);
  result = 0.5 * plus.transpose();
  return true;
}

Eigen::MatrixXd PsdFactor(const Eigen::MatrixXd& g, double relative_floor) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(g);
  const Eigen::VectorXd& values = eigen.eigenvalues();  // ascending
  const double largest = values.size() ? values.maxCoeff() : 0.0;
  std::vector<int> kept;
  for (int i = 0; i < values.size(); ++i)
    if (values[i] > relative_floor * largest && values[i] > 0.0) kept.push_back(i);
  Eigen::MatrixXd factor(kept.size(), g.cols());
  for (size_t r = 0; r < kept.size(); ++r)
    factor.row(r) = std::sqrt(values[kept[r]]) * eigen.eigenvectors().col(kept[r]).transpose();
  return factor;
}

}  // namespace msdeform
