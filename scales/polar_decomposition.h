// The rotational part of a 3x3 matrix, for shape matching (docs/method.md §2).
//
// Both functions return the rotation R in SO(3) that maximises tr(R^T A):
// the rotation of the polar decomposition A = R S when det A > 0, and the
// closest proper rotation, U diag(1, 1, -1) V^T, when det A < 0 (never a
// reflection).

#ifndef MSDEFORM_SCALES_POLAR_DECOMPOSITION_H_
#define MSDEFORM_SCALES_POLAR_DECOMPOSITION_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace msdeform {

// Müller, Bender, Chentanez, Macklin 2016, "A robust method to extract the
// rotational part of deformations": rotates the estimate by
//   omega = sum_k r_k x a_k / |sum_k r_k . a_k|
// (r_k, a_k the columns of R and A; the update is R <- cay(omega) R, the
// Cayley map in place of the paper's exponential: no sin/cos, same fixed
// point) until |omega| < `tolerance` radians or `max_iterations` updates
// were made. *rotation holds the warm start on entry
// (a unit quaternion; use the previous step's result) and the estimate on
// exit. Returns the number of updates made. With a good warm start one or two
// updates suffice; the convergence is linear (see the test for rates).
int ExtractRotation(const Eigen::Matrix3d& matrix, int max_iterations,
                    double tolerance, Eigen::Quaterniond* rotation);

// The same rotation through Eigen's JacobiSVD: U diag(1, 1, det(U V^T)) V^T.
// Slow; the reference for tests.
Eigen::Matrix3d RotationBySvd(const Eigen::Matrix3d& matrix);

}  // namespace msdeform

#endif  // MSDEFORM_SCALES_POLAR_DECOMPOSITION_H_
