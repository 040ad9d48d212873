// Coherence of a directed graph edge (j, k) (paper Eq. 14-15):
//   E(j, k) = | R_j (g_k - g_j) + g_j + t_j - (g_k + t_k) |^2,
// the disagreement between where node j's transform sends node k and where
// node k's own transform puts it. Residual (3 doubles):
//   sqrt(w_coh * alpha_jk) * (R_j (g_k - g_j) + g_j + t_j - g_k - t_k).
//
// Parameter blocks: R_j (9 doubles, column-major), t_j (3), t_k (3).
// A Half Free or Fixed node's t is a constant block; a Fixed node's R too.

#ifndef MSDEFORM_ENERGIES_COHERENCE_COST_H_
#define MSDEFORM_ENERGIES_COHERENCE_COST_H_

#include <Eigen/Core>
#include <ceres/autodiff_cost_function.h>
#include <ceres/sized_cost_function.h>

namespace msdeform {

struct CoherenceCost {
  // `sqrt_weight` is sqrt(w_coh * alpha_jk).
  CoherenceCost(const Eigen::Vector3d& g_j, const Eigen::Vector3d& g_k, double sqrt_weight)
      : g_j(g_j), g_k(g_k), sqrt_weight(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation_j, const T* translation_j, const T* translation_k,
                  T* residuals) const {
    Eigen::Map<const Eigen::Matrix<T, 3, 3>> R_j(rotation_j);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_j(translation_j);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_k(translation_k);
    Eigen::Map<Eigen::Matrix<T, 3, 1>> r(residuals);
    const Eigen::Matrix<T, 3, 1> edge = (g_k - g_j).cast<T>();
    r = T(sqrt_weight) * (R_j * edge + (g_j - g_k).cast<T>() + t_j - t_k);
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& g_j, const Eigen::Vector3d& g_k,
                                     double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<CoherenceCost, 3, 9, 3, 3>(
        new CoherenceCost(g_j, g_k, sqrt_weight));
  }

  const Eigen::Vector3d g_j;
  const Eigen::Vector3d g_k;
  const double sqrt_weight;
};

// The same residual with its (constant) Jacobian written out; checked against
// CoherenceCost in tests/energies/coherence_cost_test.cc.
class CoherenceCostAnalytic : public ceres::SizedCostFunction<3, 9, 3, 3> {
 public:
  CoherenceCostAnalytic(const Eigen::Vector3d& g_j, const Eigen::Vector3d& g_k,
                        double sqrt_weight)
      : g_j_(g_j), g_k_(g_k), sqrt_weight_(sqrt_weight) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  const Eigen::Vector3d g_j_;
  const Eigen::Vector3d g_k_;
  const double sqrt_weight_;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_COHERENCE_COST_H_
