#include "msdeform/scales/polar_decomposition.h"

#include <cmath>
#include <limits>

#include <Eigen/SVD>
#include <glog/logging.h>

namespace msdeform {

int ExtractRotation(const Eigen::Matrix3d& matrix, int max_iterations,
                    double tolerance, Eigen::Quaterniond* rotation) {
  CHECK(rotation != nullptr);
  // Relative guard against a zero denominator; the paper's absolute 1e-9
  // would depend on the units of `matrix`.
  const double guard = 1e-9 * matrix.cwiseAbs().maxCoeff() +
                       std::numeric_limits<double>::min();
  Eigen::Quaterniond& q = *rotation;
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    const Eigen::Matrix3d r = q.toRotationMatrix();
    const Eigen::Vector3d torque = r.col(0).cross(matrix.col(0)) +
                                   r.col(1).cross(matrix.col(1)) +
                                   r.col(2).cross(matrix.col(2));
    const double alignment = r.col(0).dot(matrix.col(0)) + r.col(1).dot(matrix.col(1)) +
                             r.col(2).dot(matrix.col(2));
    const Eigen::Vector3d omega = torque / (std::abs(alignment) + guard);
    const double angle = omega.norm();
    if (!(angle >= tolerance)) break;  // Also stops on NaN.
    // q <- cay(omega) q: the Cayley map, the unit quaternion (1, omega / 2)
    // normalised, turns by 2 atan(|omega| / 2) about omega, which agrees with
    // exp(omega) to O(|omega|^3), needs no sin/cos and never turns by more
    // than pi. The fixed point (omega = 0) is the same.
    const Eigen::Quaterniond delta(1.0, 0.5 * omega.x(), 0.5 * omega.y(), 0.5 * omega.z());
    q = delta * q;
    q.normalize();
  }
  return iteration;
}

Eigen::Matrix3d RotationBySvd(const Eigen::Matrix3d& matrix) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(matrix, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  const Eigen::Matrix3d& v = svd.matrixV();
  if ((u * v.transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * v.transpose();
}

}  // namespace msdeform
