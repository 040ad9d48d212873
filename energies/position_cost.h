// Position constraint of one handle vertex (paper Eq. 16):
//   residual = sqrt(w_con) * ( sum_j w_j [R_j (v - g_j) + g_j + t_j] - q ),
// the skinned position of rest vertex v (Eq. 9, over its nearest nodes j with
// normalised weights w_j) minus its target q. 3 residuals.
//
// Parameter blocks, two per node in the order of `nodes`: R_j (9 doubles,
// column-major), t_j (3). Nodes must be distinct (Ceres forbids a block twice
// in one residual); weight-0 slots are dropped by Create().

#ifndef MSDEFORM_ENERGIES_POSITION_COST_H_
#define MSDEFORM_ENERGIES_POSITION_COST_H_

#include <vector>

#include <Eigen/Core>
#include <ceres/cost_function.h>

namespace msdeform {

// One node's share of a skinned vertex: weight w_j and the vertex relative to
// the node, v - g_j, plus g_j itself.
struct SkinningTerm {
  double weight;
  Eigen::Vector3d offset;    // v - g_j
  Eigen::Vector3d position;  // g_j
};

struct PositionCost {
  PositionCost(std::vector<SkinningTerm> terms, const Eigen::Vector3d& target,
               double sqrt_weight)
      : terms(std::move(terms)), target(target), sqrt_weight(sqrt_weight) {}

  // For ceres::DynamicAutoDiffCostFunction: parameters[2 i] = R_i,
  // parameters[2 i + 1] = t_i.
  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    Eigen::Matrix<T, 3, 1> skinned = -target.cast<T>();
    for (size_t i = 0; i < terms.size(); ++i) {
      Eigen::Map<const Eigen::Matrix<T, 3, 3>> R(parameters[2 * i]);
      Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(parameters[2 * i + 1]);
      skinned += T(terms[i].weight) *
                 (R * terms[i].offset.cast<T>() + terms[i].position.cast<T>() + t);
    }
    Eigen::Map<Eigen::Matrix<T, 3, 1>> residual_vector(residuals);
    residual_vector = T(sqrt_weight) * skinned;
    return true;
  }

  // The autodiff reference; one (R, t) block pair per term. With functor !=
  // nullptr, *functor is the functor the cost function owns (to move its
  // target each frame).
  static ceres::CostFunction* Create(std::vector<SkinningTerm> terms,
                                     const Eigen::Vector3d& target, double sqrt_weight,
                                     PositionCost** functor = nullptr);

  const std::vector<SkinningTerm> terms;
  Eigen::Vector3d target;  // q; not const, so that a drag frame can move it
  const double sqrt_weight;
};

// The same residual with its Jacobian written out (it is linear in R and t);
// checked against PositionCost in tests/energies/position_cost_test.cc.
class PositionCostAnalytic : public ceres::CostFunction {
 public:
  PositionCostAnalytic(std::vector<SkinningTerm> terms, const Eigen::Vector3d& target,
                       double sqrt_weight);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // Moves the target (a drag frame) without rebuilding the problem.
  void set_target(const Eigen::Vector3d& target) { target_ = target; }

 private:
  const std::vector<SkinningTerm> terms_;
  Eigen::Vector3d target_;
  const double sqrt_weight_;
};

}  // namespace msdeform

#endif  // MSDEFORM_ENERGIES_POSITION_COST_H_
