#include "msdeform/energies/position_group_cost.h"

#include <algorithm>

#include <Eigen/QR>
#include <glog/logging.h>

namespace msdeform {

PositionGroupCost::PositionGroupCost(const std::vector<std::vector<SkinningTerm>>& vertex_terms,
                                     const std::vector<Eigen::Vector3d>& rest,
                                     bool follows_handle, double sqrt_weight)
    : follows_handle_(follows_handle) {
  CHECK(!vertex_terms.empty());
  CHECK_EQ(vertex_terms.size(), rest.size());
  num_nodes_ = static_cast<int>(vertex_terms[0].size());
  const int num_vertices = static_cast<int>(rest.size());
  const int node_cols = 4 * num_nodes_;
  const int width = node_cols + 7;
  const double s = sqrt_weight;
  for (const Eigen::Vector3d& p : rest) center_ += p;
  center_ /= num_vertices;

  Eigen::MatrixXd rows(num_vertices, width);  // M
  for (int l = 0; l < num_vertices; ++l) {
    CHECK_EQ(static_cast<int>(vertex_terms[l].size()), num_nodes_);
    Eigen::Vector3d blended = Eigen::Vector3d::Zero();  // sum_i w_i (g_i - c)
    for (int i = 0; i < num_nodes_; ++i) {
      const SkinningTerm& term = vertex_terms[l][i];
      rows.block<1, 3>(l, 4 * i) = s * term.weight * term.offset.transpose();
      rows(l, 4 * i + 3) = s * term.weight;
      blended += term.weight * (term.position - center_);
    }
    rows.block<1, 3>(l, node_cols) = s * (rest[l] - center_).transpose();
    rows(l, node_cols + 3) = s;
    rows.block<1, 3>(l, node_cols + 4) = s * blended.transpose();
  }
  if (num_vertices <= node_cols) {
    factor_ = rows.leftCols(node_cols);
    factor_handle_ = rows.rightCols<7>();
    constant_factor_.resize(0, 7);
  } else {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(rows);
    const int kept = std::min(num_vertices, width);
    const Eigen::MatrixXd upper =
        qr.matrixQR().topRows(kept).triangularView<Eigen::Upper>();  // U
    factor_ = upper.topLeftCorner(node_cols, node_cols);
    factor_handle_ = upper.block(0, node_cols, node_cols, 7);
    constant_factor_ = upper.bottomRightCorner(kept - node_cols, 7);
  }
  set_num_residuals(3 * static_cast<int>(factor_.rows()));
  for (int i = 0; i < num_nodes_; ++i) {
    mutable_parameter_block_sizes()->push_back(9);
    mutable_parameter_block_sizes()->push_back(3);
  }
  SetHandle(Eigen::Affine3d::Identity());
}

void PositionGroupCost::SetHandle(const Eigen::Affine3d& handle) {
  Eigen::Matrix3d linear = Eigen::Matrix3d::Identity();  // A
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();       // d = (A - I) c + u
  if (follows_handle_) {
    linear = handle.linear();
    shift = (linear - Eigen::Matrix3d::Identity()) * center_ + handle.translation();
  }
  Eigen::Matrix<double, 7, 3> z;  // column a: [-A_a; -d_a; e_a]
  z.topRows<3>() = -linear.transpose();
  z.row(3) = -shift.transpose();
  z.bottomRows<3>().setIdentity();
  offset_ = factor_handle_ * z;
  constant_cost_ = 0.5 * (constant_factor_ * z).squaredNorm();
}

bool PositionGroupCost::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const int rows = static_cast<int>(factor_.rows());
  const int node_cols = 4 * num_nodes_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> x(node_cols, 3);  // column a: x_a
  for (int i = 0; i < num_nodes_; ++i) {
    x.middleRows<3>(4 * i) = Eigen::Map<const Eigen::Matrix3d>(parameters[2 * i]).transpose();
    x.row(4 * i + 3) = Eigen::Map<const Eigen::RowVector3d>(parameters[2 * i + 1]);
  }
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3>> r(residuals, rows, 3);
  r.noalias() = factor_ * x;
  r += offset_;
  if (jacobians == nullptr) return true;
  for (int i = 0; i < num_nodes_; ++i) {
    if (double* J = jacobians[2 * i]) {
      // d r(j, a) / d R_i(a, c) = U(j, 4 i + c); R_i is column-major.
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>> jacobian(J, 3 * rows, 9);
      jacobian.setZero();
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) jacobian.block(a * rows, 3 * c + a, rows, 1) = factor_.col(4 * i + c);
    }
    if (double* J = jacobians[2 * i + 1]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> jacobian(J, 3 * rows, 3);
      jacobian.setZero();
      for (int a = 0; a < 3; ++a) jacobian.block(a * rows, a, rows, 1) = factor_.col(4 * i + 3);
    }
  }
  return true;
}

}  // namespace msdeform
