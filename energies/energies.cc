// Analytic Jacobians of the cost functions in rot_cost.h, coherence_cost.h,
// position_cost.h and gauge_cost.h. Ceres stores each Jacobian block
// row-major: entry (residual r, parameter p) of block b is
// jacobians[b][r * block_size + p].
// A rotation block is column-major, so R(a, c) is parameter c * 3 + a.

#include <algorithm>

#include <ceres/dynamic_autodiff_cost_function.h>

#include "msdeform/energies/coherence_cost.h"
#include "msdeform/energies/gauge_cost.h"
#include "msdeform/energies/position_cost.h"
#include "msdeform/energies/rot_cost.h"

namespace msdeform {

void RotResiduals(const double* R, double s, double* residuals,
                  Eigen::Matrix<double, 6, 9>* jacobian) {
  // Residual r pairs columns (kFirst[r], kSecond[r]); the last three are c.c - 1.
  static constexpr int kFirst[6] = {0, 0, 1, 0, 1, 2};
  static constexpr int kSecond[6] = {1, 2, 2, 0, 1, 2};
  for (int r = 0; r < 6; ++r) {
    const double* a = R + 3 * kFirst[r];
    const double* b = R + 3 * kSecond[r];
    residuals[r] = s * (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] - (r >= 3 ? 1.0 : 0.0));
  }
  if (jacobian == nullptr) return;
  jacobian->setZero();
  for (int r = 0; r < 6; ++r) {
    const int a = kFirst[r], b = kSecond[r];
    for (int i = 0; i < 3; ++i) {
      (*jacobian)(r, a * 3 + i) += s * R[b * 3 + i];
      (*jacobian)(r, b * 3 + i) += s * R[a * 3 + i];
    }
  }
}

bool RotCostAnalytic::Evaluate(double const* const* parameters, double* residuals,
                               double** jacobians) const {
  if (jacobians == nullptr || jacobians[0] == nullptr) {
    RotResiduals(parameters[0], sqrt_weight_, residuals, nullptr);
    return true;
  }
  Eigen::Matrix<double, 6, 9> jacobian;
  RotResiduals(parameters[0], sqrt_weight_, residuals, &jacobian);
  Eigen::Map<Eigen::Matrix<double, 6, 9, Eigen::RowMajor>> row_major(jacobians[0]);
  row_major = jacobian;
  return true;
}

bool CoherenceCostAnalytic::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  Eigen::Map<const Eigen::Matrix3d> R_j(parameters[0]);
  Eigen::Map<const Eigen::Vector3d> t_j(parameters[1]);
  Eigen::Map<const Eigen::Vector3d> t_k(parameters[2]);
  const Eigen::Vector3d edge = g_k_ - g_j_;
  Eigen::Map<Eigen::Vector3d> residual_vector(residuals);
    residual_vector = sqrt_weight_ * (R_j * edge - edge + t_j - t_k);
  if (jacobians == nullptr) return true;
  if (jacobians[0] != nullptr) {
    std::fill(jacobians[0], jacobians[0] + 27, 0.0);
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) jacobians[0][a * 9 + c * 3 + a] = sqrt_weight_ * edge[c];
  }
  for (int block = 1; block <= 2; ++block) {
    if (jacobians[block] == nullptr) continue;
    const double sign = block == 1 ? sqrt_weight_ : -sqrt_weight_;
    std::fill(jacobians[block], jacobians[block] + 9, 0.0);
    for (int a = 0; a < 3; ++a) jacobians[block][a * 3 + a] = sign;
  }
  return true;
}

Eigen::Matrix<double, 1, 9> GaugeCostAnalytic::Jacobian(const Eigen::Vector3d& axis,
                                                         double sqrt_weight) {
  // n^T omega(R) = 1/2 [n_x (R(2,1) - R(1,2)) + n_y (R(0,2) - R(2,0)) + n_z (R(1,0) - R(0,1))].
  const Eigen::Vector3d half = 0.5 * sqrt_weight * axis;
  Eigen::Matrix<double, 1, 9> row = Eigen::Matrix<double, 1, 9>::Zero();
  row[1 * 3 + 2] = half.x();   // R(2, 1)
  row[2 * 3 + 1] = -half.x();  // R(1, 2)
  row[2 * 3 + 0] = half.y();   // R(0, 2)
  row[0 * 3 + 2] = -half.y();  // R(2, 0)
  row[0 * 3 + 1] = half.z();   // R(1, 0)
  row[1 * 3 + 0] = -half.z();  // R(0, 1)
  return row;
}

bool GaugeCostAnalytic::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const Eigen::Matrix<double, 1, 9> row = Jacobian(axis_, sqrt_weight_);
  residuals[0] = row * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(parameters[0]);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 1, 9>> jacobian(jacobians[0]);
    jacobian = row;
  }
  return true;
}

namespace {
std::vector<SkinningTerm> WithoutZeroWeights(std::vector<SkinningTerm> terms) {
  terms.erase(std::remove_if(terms.begin(), terms.end(),
                             [](const SkinningTerm& term) { return term.weight == 0.0; }),
              terms.end());
  return terms;
}
}  // namespace

ceres::CostFunction* PositionCost::Create(std::vector<SkinningTerm> terms,
                                          const Eigen::Vector3d& target, double sqrt_weight,
                                          PositionCost** functor) {
  terms = WithoutZeroWeights(std::move(terms));
  const size_t num_terms = terms.size();
  auto* owned = new PositionCost(std::move(terms), target, sqrt_weight);
  if (functor != nullptr) *functor = owned;
  auto* cost = new ceres::DynamicAutoDiffCostFunction<PositionCost, 4>(owned);
  for (size_t i = 0; i < num_terms; ++i) {
    cost->AddParameterBlock(9);
    cost->AddParameterBlock(3);
  }
  cost->SetNumResiduals(3);
  return cost;
}

PositionCostAnalytic::PositionCostAnalytic(std::vector<SkinningTerm> terms,
                                           const Eigen::Vector3d& target, double sqrt_weight)
    : terms_(WithoutZeroWeights(std::move(terms))), target_(target), sqrt_weight_(sqrt_weight) {
  for (size_t i = 0; i < terms_.size(); ++i) {
    mutable_parameter_block_sizes()->push_back(9);
    mutable_parameter_block_sizes()->push_back(3);
  }
  set_num_residuals(3);
}

bool PositionCostAnalytic::Evaluate(double const* const* parameters, double* residuals,
                                    double** jacobians) const {
  Eigen::Vector3d skinned = -target_;
  for (size_t i = 0; i < terms_.size(); ++i) {
    Eigen::Map<const Eigen::Matrix3d> R(parameters[2 * i]);
    Eigen::Map<const Eigen::Vector3d> t(parameters[2 * i + 1]);
    skinned += terms_[i].weight * (R * terms_[i].offset + terms_[i].position + t);
  }
  Eigen::Map<Eigen::Vector3d> residual_vector(residuals);
    residual_vector = sqrt_weight_ * skinned;
  if (jacobians == nullptr) return true;
  for (size_t i = 0; i < terms_.size(); ++i) {
    const double scale = sqrt_weight_ * terms_[i].weight;
    if (double* J = jacobians[2 * i]) {
      std::fill(J, J + 27, 0.0);
      for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) J[a * 9 + c * 3 + a] = scale * terms_[i].offset[c];
    }
    if (double* J = jacobians[2 * i + 1]) {
      std::fill(J, J + 9, 0.0);
      for (int a = 0; a < 3; ++a) J[a * 3 + a] = scale;
    }
  }
  return true;
}

}  // namespace msdeform
