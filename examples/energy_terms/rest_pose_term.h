// An example linear energy term (docs/extending.md): a rest-pose regulariser
// that pulls a node's affine map toward the identity,
//   sqrt_weight * (R_j - I)   (9 residuals, column-major),
// affine in R_j, so the Gauss-Newton backend assembles it once per layout
// (EnergyTerm::linear) and Ceres differentiates the functor.
//
// Parameter block: R_j, 9 doubles, column-major.

#ifndef MSDEFORM_EXAMPLES_ENERGY_TERMS_REST_POSE_TERM_H_
#define MSDEFORM_EXAMPLES_ENERGY_TERMS_REST_POSE_TERM_H_

#include "msdeform/energies/energy_term.h"

namespace msdeform {

struct RestPoseCost {
  explicit RestPoseCost(double sqrt_weight) : sqrt_weight(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, T* residuals) const {
    for (int i = 0; i < 9; ++i)
      residuals[i] = T(sqrt_weight) * (rotation[i] - T(i % 4 == 0 ? 1.0 : 0.0));
    return true;
  }

  const double sqrt_weight;
};

inline EnergyTerm RestPoseTerm(int j, double sqrt_weight) {
  return MakeEnergyTerm<RestPoseCost, 9, 9>("rest_pose", {TermBlock::Rotation(j)},
                                            /*linear=*/true, RestPoseCost(sqrt_weight));
}

}  // namespace msdeform

#endif  // MSDEFORM_EXAMPLES_ENERGY_TERMS_REST_POSE_TERM_H_
