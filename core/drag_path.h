// A drag from rest to a final handle transform in equal steps: the one
// generator of drag paths, for .def transforms and scenario motions alike.
//
// A motion is read about a pivot c as x -> R S (x - c) + c + d: R a rotation
// (an angle and a unit axis), S what the linear part holds beyond it (scale or
// shear; the identity for a rigid motion) and d the pivot's displacement. The
// motion carried a fraction f of the way is
//
//   x -> R_f ((1 - f) I + f S) (x - c) + c + f d,   R_f = rotation by f * angle,
//
// so the pivot moves on a straight line while the handle turns at a constant
// rate about a fixed axis, and only S is blended linearly. The angle may
// exceed 180 degrees (a scenario's 270-degree turn is 135 degrees at mid-drag).

#ifndef MSDEFORM_CORE_DRAG_PATH_H_
#define MSDEFORM_CORE_DRAG_PATH_H_

#include <vector>

#include <Eigen/Geometry>

namespace msdeform {

struct DragMotion {
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero();                  // c, at rest.
  Eigen::AngleAxisd rotation = Eigen::AngleAxisd::Identity();       // R; unit axis.
  Eigen::Matrix3d stretch = Eigen::Matrix3d::Identity();            // S.
  Eigen::Vector3d pivot_displacement = Eigen::Vector3d::Zero();     // d.
};

// Reads x -> A x + b about `pivot`: R is the polar rotation of A (the proper
// rotation nearest to it, from its SVD; angle in [0, pi]), S = R^T A (for a
// .def printed with six digits, rounding of order 1e-6) and d = A c + b - c.
// A non-finite A gives R = I and S = A.
DragMotion DragMotionFromTransform(const Eigen::Affine3d& deformed_from_rest,
                                   const Eigen::Vector3d& pivot);

// The motion carried `fraction` of the way (0: the identity, 1: all of it).
Eigen::Affine3d DragFrame(const DragMotion& motion, double fraction);

// `frames` >= 1 transforms, frame k (1-based) = DragFrame(motion, k / frames).
std::vector<Eigen::Affine3d> InterpolateDragPath(const DragMotion& motion, int frames);

// The drag to x -> A x + b about `pivot` (the handle's rest centroid for a
// .sel/.def edit): `frames` >= 1 transforms of DragMotionFromTransform's
// motion; the last one equals `deformed_from_rest` exactly.
std::vector<Eigen::Affine3d> InterpolateDragPath(const Eigen::Affine3d& deformed_from_rest,
                                                 const Eigen::Vector3d& pivot, int frames);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_DRAG_PATH_H_
