// Gauge fixing of a node's rotation about an axis n that Eq. 17 leaves free
// (docs/decisions/gauge-freedom.md): a node whose Rot, Coherence-as-source
// and Position terms only see R_j through vectors parallel to n costs the same
// under R_j -> Q_{R_j n}(theta) R_j (a spin about the deformed n), so one
// linear residual picks the representative:
//   sqrt_weight * n^T omega(R),  omega(R) = 1/2 (R32 - R23, R13 - R31, R21 - R12),
// omega the axial vector of R's skew part (w for R = I + [w]x, sin(theta) u
// for a rotation by theta about unit u). It is zero at R = I and for every
// rotation about an axis perpendicular to n, and sqrt_weight * sin(theta) for
// a rotation by theta about n. One residual.
//
// Parameter block: R (9 doubles, column-major), so R(a, c) is R[c * 3 + a].

#ifndef MSDEFORM_ENERGIES_GAUGE_COST_H_
#define MSDEFORM_ENERGIES_GAUGE_COST_H_

#include <Eigen/Core>
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

namespace msdeform {

struct GaugeCost {
  // `axis` is the unit vector n; `sqrt_weight` the residual scale.
  GaugeCost(const Eigen::Vector3d& axis, double sqrt_weight)
      : axis(axis), sqrt_weight(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, T* residuals) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 3>> R(rotation);
    const Eigen::Matrix<T, 3, 1> omega(T(0.5) * (R(2, 1) - R(1, 2)), T(0.5) * (R(0, 2) - R(2, 0)),
                                       T(0.5) * (R(1, 0) - R(0, 1)));
    residuals[0] = T(sqrt_weight) * axis.cast<T>().dot(omega);
    return true;
  }

  // The autodiff reference.
  static ceres::CostFunction* Create(const Eigen::Vector3d& axis, double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<GaugeCost, 1, 9>(new GaugeCost(axis, sqrt_weight));
  }

  const Eigen::Vector3d axis;
  const double sqrt_weight;
};

// The same residual with its (constant) Jacobian written out; checked against
// GaugeCost in tests/energies/gauge_cost_test.cc. What the deformer uses.
class GaugeCostAnalytic : public ceres::SizedCostFunction<1, 9> {
 public:
  GaugeCostAnalytic(const Eigen::Vector3d& axis, double sqrt_weight)
      : axis_(axis), sqrt_weight_(sqrt_weight) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The row J (1 x 9, column-major R) with residual = J R: the gauge term of
  // `axis` scaled by `sqrt_weight`. Shared with the Gauss-Newton backend.
  static Eigen::Matrix<double, 1, 9> Jacobian(const Eigen::Vector3d& axis, double sqrt_weight);

 private:
  const Eigen::Vector3d axis_;
  const double sqrt_weight_;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_GAUGE_COST_H_
