#include "msdeform/solvers/anderson_acceleration.h"

#include <cmath>
#include <utility>

#include <Eigen/Dense>
#include <glog/logging.h>

namespace msdeform {

AndersonAcceleration::AndersonAcceleration(int dimension, int window)
    : dimension_(dimension), window_(window) {
  CHECK_GE(dimension, 0);
  CHECK_GE(window, 0);
  delta_f_.resize(dimension, window);
  delta_g_.resize(dimension, window);
  gram_ = Eigen::MatrixXd::Zero(window, window);
}

void AndersonAcceleration::Compute(const Eigen::VectorXd& x, const Eigen::VectorXd& g,
                                   Eigen::VectorXd* next) {
  CHECK_EQ(x.size(), dimension_);
  CHECK_EQ(g.size(), dimension_);
  if (window_ == 0) {
    *next = g;
    return;
  }
  Eigen::VectorXd f = g - x;
  if (!has_previous_) {
    // First iterate after a start or a Reset: nothing to combine with.
    previous_f_ = std::move(f);
    previous_g_ = g;
    has_previous_ = true;
    *next = g;
    return;
  }
  // Push the newest differences into the ring buffer and update the Gram
  // matrix's row and column of that slot.
  newest_ = (newest_ + 1) % window_;
  delta_f_.col(newest_) = f - previous_f_;
  delta_g_.col(newest_) = g - previous_g_;
  if (history_ < window_) ++history_;
  for (int j = 0; j < history_; ++j) {
    const double dot = delta_f_.col(j).dot(delta_f_.col(newest_));
    gram_(j, newest_) = dot;
    gram_(newest_, j) = dot;
  }
  previous_f_ = f;
  previous_g_ = g;

  // theta = argmin |f - dF theta|: the normal equations, with the columns
  // scaled to unit length (their lengths shrink by orders of magnitude as the
  // iteration converges) and solved by a rank-revealing decomposition.
  const int m = history_;
  Eigen::VectorXd scale(m);
  for (int j = 0; j < m; ++j) {
    scale[j] = gram_(j, j) > 0.0 ? 1.0 / std::sqrt(gram_(j, j)) : 0.0;
  }
  const Eigen::MatrixXd normal =
      scale.asDiagonal() * gram_.topLeftCorner(m, m) * scale.asDiagonal();
  Eigen::VectorXd rhs(m);
  for (int j = 0; j < m; ++j) rhs[j] = scale[j] * delta_f_.col(j).dot(f);
  const Eigen::VectorXd theta =
      scale.asDiagonal() * normal.completeOrthogonalDecomposition().solve(rhs);
  *next = g;
  for (int j = 0; j < m; ++j) next->noalias() -= theta[j] * delta_g_.col(j);
}

}  // namespace msdeform
