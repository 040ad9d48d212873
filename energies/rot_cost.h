// Rot (paper Eq. 12-13): how far a node's 3x3 matrix R_j is from a rotation.
//
// With c1, c2, c3 the columns of R_j, the six residuals are
//   sqrt(w_rot) * [c1.c2, c1.c3, c2.c3, c1.c1 - 1, c2.c2 - 1, c3.c3 - 1],
// so that E_rot sums their squares over the Totally Free and Half Free nodes.
//
// Parameter block: R, 9 doubles, column-major (Eigen's default), so columns
// are R[0..2], R[3..5], R[6..8].

#ifndef MSDEFORM_ENERGIES_ROT_COST_H_
#define MSDEFORM_ENERGIES_ROT_COST_H_

#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>
#include <Eigen/Core>

namespace msdeform {

struct RotCost {
  explicit RotCost(double sqrt_weight) : sqrt_weight(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, T* residuals) const {
    const T* c1 = rotation;
    const T* c2 = rotation + 3;
    const T* c3 = rotation + 6;
    auto dot = [](const T* a, const T* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    residuals[0] = sqrt_weight * dot(c1, c2);
    residuals[1] = sqrt_weight * dot(c1, c3);
    residuals[2] = sqrt_weight * dot(c2, c3);
    residuals[3] = sqrt_weight * (dot(c1, c1) - 1.0);
    residuals[4] = sqrt_weight * (dot(c2, c2) - 1.0);
    residuals[5] = sqrt_weight * (dot(c3, c3) - 1.0);
    return true;
  }

  // The autodiff reference.
  static ceres::CostFunction* Create(double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<RotCost, 6, 9>(new RotCost(sqrt_weight));
  }

  const double sqrt_weight;
};

// The six residuals of RotCost at R (9 doubles, column-major) scaled by s,
// with jacobian != nullptr also their 6x9 Jacobian (column c * 3 + a is
// R(a, c)). The one analytic evaluation: RotCostAnalytic, the Gauss-Newton
// backend's per-node 9x9 blocks and EvaluateEnergy's reference all call it.
void RotResiduals(const double* R, double s, double* residuals,
                  Eigen::Matrix<double, 6, 9>* jacobian);

// The same residuals with a hand-written Jacobian (checked against RotCost
// in tests/energies/rot_cost_test.cc); what the deformer uses.
class RotCostAnalytic : public ceres::SizedCostFunction<6, 9> {
 public:
  explicit RotCostAnalytic(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const double sqrt_weight_;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_ROT_COST_H_
