// A drag from rest to a final handle transform in equal steps.
//
// The final transform x -> A x + b is read about a pivot c (the handle's rest
// centroid): x -> R (x - c) + c + d with R the rotation of A and d = A c + b - c.
// Frame k of n applies slerp(I, R, k/n) and k/n of d, so the handle's
// centroid moves on a straight line while it turns at a constant rate. When A
// is not a rotation (scale or shear), A itself is blended linearly.

#ifndef MSDEFORM_CORE_DRAG_PATH_H_
#define MSDEFORM_CORE_DRAG_PATH_H_

#include <vector>

#include <Eigen/Geometry>

namespace msdeform {

// `frames` >= 1 transforms; the last one equals `deformed_from_rest`.
std::vector<Eigen::Affine3d> InterpolateDragPath(const Eigen::Affine3d& deformed_from_rest,
                                                 const Eigen::Vector3d& pivot, int frames);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_DRAG_PATH_H_
