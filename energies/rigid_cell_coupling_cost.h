// The volumetric coupling of two neighbouring rigid cells (Botsch, Pauly,
// Wicke, Gross 2007, "Adaptive space deformations based on rigid cells",
// the coupling energy of their §4): how far the two cells' rigid motions
// disagree over the volume of the two cells,
//   E_ij = 1/w^3 * integral over C_i u C_j of |T_i(x) - T_j(x)|^2 dx,
// with w the cell width (the 1/w^3 makes E_ij a length squared and changes no
// minimiser). Cell k moves by T_k(x) = R_k (x - c_k) + p_k: its rotation R_k
// and the deformed position p_k of its rest centre c_k.
//
// Closed form. D(x) = T_i(x) - T_j(x) = A x + b is affine, with
// A = R_i - R_j. Let V be the volume of the region C_i u C_j, m its centroid
// and M = integral (x - m)(x - m)^T dx its second central moment. Writing
// x = m + y, the cross term integrates to zero (integral y dx = 0), so
//   integral |D(x)|^2 dx = V |D(m)|^2 + tr(A M A^T) = V |D(m)|^2 + |A L|_F^2
// for any L with L L^T = M. For two cubes of side w with centres c_i != c_j
// (face, edge or corner neighbours; they do not overlap), m = (c_i + c_j) / 2,
// V = 2 w^3, and each cube adds its own moment w^5/12 I plus w^3 (c_k - m)
// (c_k - m)^T with c_k - m = +-d/2, d = c_i - c_j:
//   M = w^5/6 I + w^3/2 d d^T.
// Two pieces of one split surface cell (core/lattice.h) share the cube:
// V = w^3, m = c, M = w^5/12 I. RigidCellCouplingCost::Create takes
// V / w^3, m and M / w^3, so any union of boxes fits.
//
// Residuals (12): [sqrt(V / w^3) D(m) (3); vec(R_i L - R_j L) (9)], with
// L the Cholesky factor of M / w^3; their squared norm is E_ij. Zero exactly
// when T_i = T_j (a rigid motion of both cells), for any rigid motion.
//
// Parameter blocks: q_i, q_j (4 doubles each, Eigen's quaternion order
// x, y, z, w, on ceres::EigenQuaternionManifold) and p_i, p_j (3 doubles),
// in the order q_i, p_i, q_j, p_j.

#ifndef MSDEFORM_ENERGIES_RIGID_CELL_COUPLING_COST_H_
#define MSDEFORM_ENERGIES_RIGID_CELL_COUPLING_COST_H_

#include <cmath>

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace msdeform {

struct RigidCellCouplingCost {
  // rest_i, rest_j: the cells' rest centres; centroid, scaled_volume and
  // scaled_moment: m, V / w^3 and M / w^3 of the region C_i u C_j.
  RigidCellCouplingCost(const Eigen::Vector3d& rest_i, const Eigen::Vector3d& rest_j,
                        const Eigen::Vector3d& centroid, double scaled_volume,
                        const Eigen::Matrix3d& scaled_moment)
      : centroid_from_i(centroid - rest_i),
        centroid_from_j(centroid - rest_j),
        sqrt_volume(std::sqrt(scaled_volume)),
        moment_factor(scaled_moment.llt().matrixL()) {}

  template <typename T>
  bool operator()(const T* q_i, const T* p_i, const T* q_j, const T* p_j, T* residuals) const {
    // Eigen's quaternion order (x, y, z, w) to ceres' (w, x, y, z).
    const T quaternion_i[4] = {q_i[3], q_i[0], q_i[1], q_i[2]};
    const T quaternion_j[4] = {q_j[3], q_j[0], q_j[1], q_j[2]};
    // D(m) = R_i (m - c_i) + p_i - R_j (m - c_j) - p_j.
    const T from_i[3] = {T(centroid_from_i[0]), T(centroid_from_i[1]), T(centroid_from_i[2])};
    const T from_j[3] = {T(centroid_from_j[0]), T(centroid_from_j[1]), T(centroid_from_j[2])};
    T rotated_i[3], rotated_j[3];
    ceres::UnitQuaternionRotatePoint(quaternion_i, from_i, rotated_i);
    ceres::UnitQuaternionRotatePoint(quaternion_j, from_j, rotated_j);
    for (int a = 0; a < 3; ++a) {
      residuals[a] = sqrt_volume * (rotated_i[a] + p_i[a] - rotated_j[a] - p_j[a]);
    }
    // (R_i - R_j) L, column by column: R_i l_c - R_j l_c.
    for (int c = 0; c < 3; ++c) {
      const T column[3] = {T(moment_factor(0, c)), T(moment_factor(1, c)),
                           T(moment_factor(2, c))};
      ceres::UnitQuaternionRotatePoint(quaternion_i, column, rotated_i);
      ceres::UnitQuaternionRotatePoint(quaternion_j, column, rotated_j);
      for (int a = 0; a < 3; ++a) residuals[3 + 3 * c + a] = rotated_i[a] - rotated_j[a];
    }
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& rest_i, const Eigen::Vector3d& rest_j,
                                     const Eigen::Vector3d& centroid, double scaled_volume,
                                     const Eigen::Matrix3d& scaled_moment) {
    return new ceres::AutoDiffCostFunction<RigidCellCouplingCost, 12, 4, 3, 4, 3>(
        new RigidCellCouplingCost(rest_i, rest_j, centroid, scaled_volume, scaled_moment));
  }

  // Two cubes of side w with centres rest_i and rest_j: the moments above
  // (one cube when the centres coincide, two split pieces of a cell).
  static ceres::CostFunction* CreateForCubes(const Eigen::Vector3d& rest_i,
                                             const Eigen::Vector3d& rest_j, double cell_width) {
    const Eigen::Vector3d d = rest_i - rest_j;
    const double w2 = cell_width * cell_width;
    if (d.squaredNorm() == 0.0) {
      return Create(rest_i, rest_j, rest_i, 1.0, w2 / 12.0 * Eigen::Matrix3d::Identity());
    }
    return Create(rest_i, rest_j, 0.5 * (rest_i + rest_j), 2.0,
                  w2 / 6.0 * Eigen::Matrix3d::Identity() + 0.5 * d * d.transpose());
  }

  const Eigen::Vector3d centroid_from_i;  // m - c_i
  const Eigen::Vector3d centroid_from_j;  // m - c_j
  const double sqrt_volume;               // sqrt(V / w^3)
  const Eigen::Matrix3d moment_factor;    // L, L L^T = M / w^3
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_RIGID_CELL_COUPLING_COST_H_
