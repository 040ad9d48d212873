#include "msdeform/solvers/deformation_energy.h"

#include <Eigen/Eigenvalues>

#include "msdeform/energies/coherence_cost.h"
#include "msdeform/energies/gauge_cost.h"
#include "msdeform/energies/rot_cost.h"

namespace msdeform {

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
                      const HandleTransforms& handles) {
  double sum = 0.0;
  for (int j : energy.rot_nodes) {
    double r[6];
    RotResiduals(transforms.rotations.col(j).data(), energy.sqrt_rot, r, nullptr);
    for (double value : r) sum += value * value;
  }
  const Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  for (const DeformationEnergy::Coherence& term : energy.coherence) {
    // g_j = 0, g_k = edge: the functor only uses their difference.
    Eigen::Vector3d r;
    CoherenceCost(origin, term.edge, term.sqrt_weight)(
        transforms.rotations.col(term.j).data(), transforms.translations.col(term.j).data(),
        transforms.translations.col(term.k).data(), r.data());
    sum += r.squaredNorm();
  }
  std::vector<const double*> parameters;
  for (const DeformationEnergy::Position& term : energy.positions) {
    parameters.clear();
    for (int j : term.nodes) {
      parameters.push_back(transforms.rotations.col(j).data());
      parameters.push_back(transforms.translations.col(j).data());
    }
    const Eigen::Vector3d target =
        term.follows_handle() ? Eigen::Vector3d(handles[term.handle_group] * term.rest) : term.rest;
    Eigen::Vector3d r;
    PositionCost(term.terms, target, term.sqrt_weight)(parameters.data(), r.data());
    sum += r.squaredNorm();
  }
  for (const DeformationEnergy::Gauge& term : energy.gauge) {
    const double r = GaugeCostAnalytic::Jacobian(term.axis, term.sqrt_weight)
                         .dot(transforms.rotations.col(term.node));
    sum += r * r;
  }
  double extra = 0.0;
  for (const EnergyTerm& term : energy.terms) extra += EnergyTermCost(term, transforms);
  for (const std::shared_ptr<const TermFamily>& family : energy.families) {
    extra += family->Cost(transforms, handles);
  }
  return 0.5 * sum + extra;
}

}  // namespace msdeform
