#include "msdeform/core/drag_path.h"

#include <Eigen/SVD>
#include <glog/logging.h>

namespace msdeform {

DragMotion DragMotionFromTransform(const Eigen::Affine3d& deformed_from_rest,
                                   const Eigen::Vector3d& pivot) {
  const Eigen::Matrix3d A = deformed_from_rest.linear();
  DragMotion motion;
  motion.pivot = pivot;
  motion.pivot_displacement = deformed_from_rest * pivot - pivot;
  if (!A.allFinite()) {
    motion.stretch = A;
    return motion;
  }
  // A = U Sigma V^T; the nearest proper rotation is U diag(1, 1, det(U V^T)) V^T.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d& V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0.0) U.col(2) = -U.col(2);
  const Eigen::Matrix3d R = U * V.transpose();
  motion.rotation = Eigen::AngleAxisd(R);
  motion.stretch = R.transpose() * A;
  return motion;
}

Eigen::Affine3d DragFrame(const DragMotion& motion, double fraction) {
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(fraction * motion.rotation.angle(), motion.rotation.axis())
          .toRotationMatrix();
  // I + f (S - I) rather than (1 - f) I + f S: exactly I for a rigid motion.
  const Eigen::Matrix3d blended_stretch =
      Eigen::Matrix3d::Identity() + fraction * (motion.stretch - Eigen::Matrix3d::Identity());
  Eigen::Affine3d frame = Eigen::Affine3d::Identity();
  frame.linear() = turn * blended_stretch;
  frame.translation() =
      (motion.pivot + fraction * motion.pivot_displacement) - frame.linear() * motion.pivot;
  return frame;
}

std::vector<Eigen::Affine3d> InterpolateDragPath(const DragMotion& motion, int frames) {
  CHECK_GE(frames, 1);
  std::vector<Eigen::Affine3d> path;
  path.reserve(frames);
  for (int k = 1; k <= frames; ++k) {
    path.push_back(DragFrame(motion, static_cast<double>(k) / frames));
  }
  return path;
}

std::vector<Eigen::Affine3d> InterpolateDragPath(const Eigen::Affine3d& deformed_from_rest,
                                                 const Eigen::Vector3d& pivot, int frames) {
  std::vector<Eigen::Affine3d> path =
      InterpolateDragPath(DragMotionFromTransform(deformed_from_rest, pivot), frames);
  path.back() = deformed_from_rest;
  return path;
}

}  // namespace msdeform
