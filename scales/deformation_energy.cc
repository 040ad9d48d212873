#include "msdeform/scales/deformation_energy.h"

#include <Eigen/Eigenvalues>

#include "msdeform/energies/gauge_cost.h"

namespace msdeform {

void RotResiduals(const double* R, double s, double* residuals,
                  Eigen::Matrix<double, 6, 9>* jacobian) {
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

int DeformationEnergy::num_variables() const {
  int variables = 0;
  for (NodeClass c : node_class)
    variables += c == NodeClass::kTotallyFree ? 12 : c == NodeClass::kHalfFree ? 9 : 0;
  return variables;
}

std::vector<DeformationEnergy::Gauge> GaugeTerms(const DeformationEnergy& energy) {
  std::vector<DeformationEnergy::Gauge> gauge;
  if (!(energy.sqrt_rot > 0.0)) return gauge;
  const int num_nodes = static_cast<int>(energy.node_class.size());
  std::vector<Eigen::Matrix3d> scatter(num_nodes, Eigen::Matrix3d::Zero());
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    const Eigen::Vector3d u = term.sqrt_weight * term.edge;
    scatter[term.j] += u * u.transpose();
  }
  for (const DeformationEnergy::Position& term : energy.positions) {
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const Eigen::Vector3d u = term.sqrt_weight * term.terms[i].weight * term.terms[i].offset;
      scatter[term.nodes[i]] += u * u.transpose();
    }
  }
  for (int j : energy.rot_nodes) {
    if (energy.node_class[j] == NodeClass::kFixed) continue;
    const Eigen::Matrix3d& S = scatter[j];
    if (S.trace() == 0.0) {
      for (int axis = 0; axis < 3; ++axis)
        gauge.push_back({j, Eigen::Vector3d::Unit(axis), energy.sqrt_rot});
      continue;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(S);
    const Eigen::Vector3d lambda = eigen.eigenvalues();  // ascending
    if (lambda[1] <= 1e-12 * lambda[2])
      gauge.push_back({j, eigen.eigenvectors().col(2).normalized(), energy.sqrt_rot});
  }
  return gauge;
}

double EvaluateEnergy(const DeformationEnergy& energy, const NodeTransforms& transforms,
                      const Eigen::Affine3d& handle) {
  double sum = 0.0;
  for (int j : energy.rot_nodes) {
    double r[6];
    RotResiduals(transforms.rotations.col(j).data(), energy.sqrt_rot, r, nullptr);
    for (double value : r) sum += value * value;
  }
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    const Eigen::Vector3d r =
        term.sqrt_weight * (transforms.rotation(term.j) * term.edge - term.edge +
                            transforms.translations.col(term.j) -
                            transforms.translations.col(term.k));
    sum += r.squaredNorm();
  }
  for (const DeformationEnergy::Position& term : energy.positions) {
    Eigen::Vector3d skinned = term.follows_handle ? Eigen::Vector3d(-(handle * term.rest))
                                                  : Eigen::Vector3d(-term.rest);
    for (size_t i = 0; i < term.nodes.size(); ++i) {
      const int j = term.nodes[i];
      skinned += term.terms[i].weight * (transforms.rotation(j) * term.terms[i].offset +
                                         term.terms[i].position + transforms.translations.col(j));
    }
    sum += (term.sqrt_weight * skinned).squaredNorm();
  }
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    const double r = GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight)
                         .dot(transforms.rotations.col(term.node));
    sum += r * r;
  }
  return 0.5 * sum;
}

}  // namespace msdeform
