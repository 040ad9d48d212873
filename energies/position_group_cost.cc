#include "msdeform/energies/position_group_cost.h"

#include <Eigen/Eigenvalues>
#include <glog/logging.h>

namespace msdeform {

PositionGroupCost::PositionGroupCost(const std::vector<std::vector<SkinningTerm>>& vertex_terms,
                                     const std::vector<Eigen::Vector3d>& rest,
                                     bool follows_handle, double sqrt_weight)
    : follows_handle_(follows_handle) {
  CHECK(!vertex_terms.empty());
  CHECK_EQ(vertex_terms.size(), rest.size());
  num_nodes_ = static_cast<int>(vertex_terms[0].size());
  const int cols = 12 * num_nodes_;
  const double s = sqrt_weight;
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(cols, cols);
  Eigen::MatrixXd h_map = Eigen::MatrixXd::Zero(cols, 13);  // h = h_map [tau; 1]
  gram_.setZero();
  Eigen::MatrixXd jacobian(3, cols);
  Eigen::Matrix<double, 3, 13> y_map;  // y_l = y_map [tau; 1]
  for (size_t l = 0; l < vertex_terms.size(); ++l) {
    CHECK_EQ(static_cast<int>(vertex_terms[l].size()), num_nodes_);
    jacobian.setZero();
    Eigen::Vector3d blended = Eigen::Vector3d::Zero();  // sum_i w_i g_i
    for (int i = 0; i < num_nodes_; ++i) {
      const SkinningTerm& term = vertex_terms[l][i];
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) jacobian(a, 12 * i + c * 3 + a) = s * term.weight * term.offset[c];
        jacobian(a, 12 * i + 9 + a) = s * term.weight;
      }
      blended += term.weight * term.position;
    }
    y_map.setZero();
    if (follows_handle) {
      for (int a = 0; a < 3; ++a) {
        for (int c = 0; c < 3; ++c) y_map(a, c * 3 + a) = s * rest[l][c];
        y_map(a, 9 + a) = s;
      }
      y_map.col(12) = -s * blended;
    } else {
      y_map.col(12) = s * (rest[l] - blended);
    }
    gram.noalias() += jacobian.transpose() * jacobian;
    h_map.noalias() += jacobian.transpose() * y_map;
    gram_.noalias() += y_map.transpose() * y_map;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const Eigen::VectorXd& lambda = eigen.eigenvalues();  // increasing
  const double cutoff = 1e-12 * std::max(lambda[cols - 1], 0.0);
  int rank = 0;
  for (int i = 0; i < cols; ++i) rank += lambda[i] > cutoff;
  factor_.resize(rank, cols);
  target_map_.resize(rank, 13);
  for (int r = 0; r < rank; ++r) {
    const int i = cols - rank + r;
    const double root = std::sqrt(lambda[i]);
    factor_.row(r) = root * eigen.eigenvectors().col(i).transpose();
    target_map_.row(r) = eigen.eigenvectors().col(i).transpose() * h_map / root;
  }
  set_num_residuals(rank);
  for (int i = 0; i < num_nodes_; ++i) {
    mutable_parameter_block_sizes()->push_back(9);
    mutable_parameter_block_sizes()->push_back(3);
  }
  SetHandle(Eigen::Affine3d::Identity());
}

void PositionGroupCost::SetHandle(const Eigen::Affine3d& handle) {
  Eigen::Matrix<double, 13, 1> tau1;
  if (follows_handle_) {
    Eigen::Map<Eigen::Matrix3d>(tau1.data()) = handle.linear();
    tau1.segment<3>(9) = handle.translation();
  } else {
    tau1.head<12>().setZero();
  }
  tau1[12] = 1.0;
  target_ = target_map_ * tau1;
  constant_cost_ = 0.5 * (tau1.dot(gram_ * tau1) - target_.squaredNorm());
}

bool PositionGroupCost::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const int rank = static_cast<int>(factor_.rows());
  Eigen::Map<Eigen::VectorXd> r(residuals, rank);
  r = -target_;
  for (int i = 0; i < num_nodes_; ++i) {
    r.noalias() += factor_.middleCols<9>(12 * i) * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(
                                                        parameters[2 * i]);
    r.noalias() += factor_.middleCols<3>(12 * i + 9) *
                   Eigen::Map<const Eigen::Vector3d>(parameters[2 * i + 1]);
  }
  if (jacobians == nullptr) return true;
  for (int i = 0; i < num_nodes_; ++i) {
    if (double* J = jacobians[2 * i]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 9, Eigen::RowMajor>>(J, rank, 9) =
          factor_.middleCols<9>(12 * i);
    }
    if (double* J = jacobians[2 * i + 1]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(J, rank, 3) =
          factor_.middleCols<3>(12 * i + 9);
    }
  }
  return true;
}

}  // namespace msdeform
