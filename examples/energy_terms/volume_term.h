// An example energy term (docs/extending.md, "Adding an energy term"): volume
// preservation of each node's affine map, a nonlinear residual per node,
//   sqrt_weight * (det R_j - 1),
// zero for every rotation (and every volume-preserving shear), so it leaves
// a rigid edit's minimum where it was and pulls a stretched node back toward
// unit volume. The whole term is this file: the functor (what both backends
// differentiate), an optional hand-written Jacobian, and the loop that adds
// it to a DeformationEnergy. Neither solver knows it.
//
// Parameter block: R_j, 9 doubles, column-major (columns R[0..2], R[3..5], R[6..8]).

#ifndef MSDEFORM_EXAMPLES_ENERGY_TERMS_VOLUME_TERM_H_
#define MSDEFORM_EXAMPLES_ENERGY_TERMS_VOLUME_TERM_H_

#include <Eigen/Core>
#include <ceres/sized_cost_function.h>

#include "msdeform/energies/energy_term.h"
#include "msdeform/solvers/deformation_energy.h"

namespace msdeform {

struct VolumeCost {
  explicit VolumeCost(double sqrt_weight) : sqrt_weight(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, T* residual) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 3>> R(rotation);
    const T det = R.col(0).dot(R.col(1).cross(R.col(2)));
    residual[0] = T(sqrt_weight) * (det - T(1.0));
    return true;
  }

  const double sqrt_weight;
};

// The same residual with its Jacobian: d det / d c0 = c1 x c2, and cyclically.
class VolumeCostAnalytic : public ceres::SizedCostFunction<1, 9> {
 public:
  explicit VolumeCostAnalytic(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<const Eigen::Matrix3d> R(parameters[0]);
    const Eigen::Vector3d d0 = R.col(1).cross(R.col(2));
    residuals[0] = sqrt_weight_ * (R.col(0).dot(d0) - 1.0);
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, 3, 3>> J(jacobians[0]);  // entry c * 3 + a
      J.col(0) = sqrt_weight_ * d0;
      J.col(1) = sqrt_weight_ * R.col(2).cross(R.col(0));
      J.col(2) = sqrt_weight_ * R.col(0).cross(R.col(1));
    }
    return true;
  }

 private:
  const double sqrt_weight_;
};

// The volume term of node j.
inline EnergyTerm VolumeTerm(int j, double sqrt_weight) {
  EnergyTerm term = MakeEnergyTerm<VolumeCost, 1, 9>("volume", {TermBlock::Rotation(j)},
                                                     /*linear=*/false, VolumeCost(sqrt_weight));
  term.new_analytic = [sqrt_weight] { return new VolumeCostAnalytic(sqrt_weight); };
  return term;
}

// One volume term per node whose R varies (Totally Free and Half Free).
inline void AddVolumeTerms(double sqrt_weight, DeformationEnergy* energy) {
  for (int j = 0; j < static_cast<int>(energy->node_class.size()); ++j) {
    if (energy->node_class[j] != NodeClass::kFixed) energy->terms.push_back(VolumeTerm(j, sqrt_weight));
  }
}

}  // namespace msdeform

#endif  // MSDEFORM_EXAMPLES_ENERGY_TERMS_VOLUME_TERM_H_
