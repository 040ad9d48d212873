#include "msdeform/core/drag_path.h"

#include <glog/logging.h>

namespace msdeform {

std::vector<Eigen::Affine3d> InterpolateDragPath(const Eigen::Affine3d& deformed_from_rest,
                                                 const Eigen::Vector3d& pivot, int frames) {
  CHECK_GE(frames, 1);
  const Eigen::Matrix3d A = deformed_from_rest.linear();
  const Eigen::Vector3d moved_pivot = deformed_from_rest * pivot;
  const bool is_rotation =
      (A.transpose() * A - Eigen::Matrix3d::Identity()).norm() < 1e-6 && A.determinant() > 0.0;
  const Eigen::Quaterniond full_rotation(is_rotation ? A : Eigen::Matrix3d::Identity());
  std::vector<Eigen::Affine3d> path;
  for (int k = 1; k <= frames; ++k) {
    const double fraction = static_cast<double>(k) / frames;
    const Eigen::Matrix3d linear =
        is_rotation
            ? Eigen::Quaterniond::Identity().slerp(fraction, full_rotation).toRotationMatrix()
            : ((1.0 - fraction) * Eigen::Matrix3d::Identity() + fraction * A).eval();
    const Eigen::Vector3d pivot_at = pivot + fraction * (moved_pivot - pivot);
    Eigen::Affine3d frame = Eigen::Affine3d::Identity();
    frame.linear() = linear;
    frame.translation() = pivot_at - linear * pivot;
    path.push_back(frame);
  }
  path.back() = deformed_from_rest;
  return path;
}

}  // namespace msdeform
