#include "msdeform/solvers/subspace_arap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include <Eigen/Eigenvalues>
#include <glog/logging.h>

namespace msdeform {

const EnumNames<RotationClusters>& RotationClustersNames() {
  static const EnumNames<RotationClusters> names = {{RotationClusters::kWeights, "weights"},
                                                    {RotationClusters::kNodes, "nodes"},
                                                    {RotationClusters::kVertices, "vertices"}};
  return names;
}

const EnumNames<ArapConstraints>& ArapConstraintsNames() {
  static const EnumNames<ArapConstraints> names = {{ArapConstraints::kExact, "exact"},
                                                   {ArapConstraints::kSoft, "soft"}};
  return names;
}

const EnumNames<ArapSolver>& ArapSolverNames() {
  static const EnumNames<ArapSolver> names = {{ArapSolver::kLocalGlobal, "local_global"},
                                              {ArapSolver::kGaussNewton, "gauss_newton"}};
  return names;
}

bool ArapOptions::Check(std::string* error) const {
  return ArapOptionTable().CheckRanges(*this, error);  // the rows' ranges (subspace_arap.h)
}

// R maximising tr(R^T S) over rotations: U diag(1, 1, det(U V^T)) V^T for
// S = U Sigma V^T. From the eigenvectors v1, v2 of S^T S with the two
// largest eigenvalues (closed form, Eigen's computeDirect): u1 = S v1 / |S v1|,
// u2 the unit part of S v2 orthogonal to u1, and R = u1 v1^T + u2 v2^T +
// (u1 x u2)(v1 x v2)^T, a rotation by construction, which picks the sign of
// the third direction as the formula above does. A rank-one S (collinear
// spokes) completes u2 and v2 with any orthonormal pair; S = 0 gives I.
Eigen::Matrix3d BestRotation(const Eigen::Matrix3d& s) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(s.transpose() * s);
  const Eigen::Vector3d v1 = eigen.eigenvectors().col(2);
  Eigen::Vector3d v2 = eigen.eigenvectors().col(1);
  v2 = (v2 - v2.dot(v1) * v1).normalized();
  Eigen::Vector3d u1 = s * v1;
  const double n1 = u1.norm();
  if (!(n1 > 0.0)) return Eigen::Matrix3d::Identity();
  u1 /= n1;
  Eigen::Vector3d u2 = s * v2;
  u2 -= u2.dot(u1) * u1;
  const double n2 = u2.norm();
  if (n2 > 1e-12 * n1) {
    u2 /= n2;
  } else {
    // Rank one: any unit vector orthogonal to u1.
    u2 = u1.unitOrthogonal();
  }
  return u1 * v1.transpose() + u2 * v2.transpose() + u1.cross(u2) * v1.cross(v2).transpose();
}

void AppendSubspaceBasis(int v, int pseudo_node, const Mesh& mesh, const DeformationGraph& graph,
                         const Eigen::Vector3d& origin,
                         std::vector<SubspaceNodeCoefficient>* out) {
  if (pseudo_node >= 0) {
    const Eigen::Vector3d x = mesh.vertices.col(v) - origin;
    out->push_back({pseudo_node, Eigen::Vector4d(x.x(), x.y(), x.z(), 1.0)});
    return;
  }
  const SkinningWeights& weights = graph.weights;
  const size_t first = out->size();
  for (int s = 0; s < weights.k(); ++s) {
    const double w = weights.weight(s, v);
    if (w == 0.0) continue;
    const int j = weights.node(s, v);
    const Eigen::Vector3d offset = mesh.vertices.col(v) - graph.positions.col(j);
    const Eigen::Vector4d c = w * Eigen::Vector4d(offset.x(), offset.y(), offset.z(), 1.0);
    auto it = std::find_if(out->begin() + first, out->end(),
                           [j](const SubspaceNodeCoefficient& e) { return e.node == j; });
    if (it != out->end()) {
      it->coefficient += c;
    } else {
      out->push_back({j, c});
    }
  }
}

void SubspaceArap::Gather(const NodeTransforms& transforms, const HandleTransforms& handles,
                          Slots* u) const {
  CHECK_EQ(transforms.num_nodes(), data_.num_nodes);
  u->resize(num_slots(), 3);
  for (int j = 0; j < data_.num_nodes; ++j) {
    const auto r = transforms.rotation(j);
    const Eigen::Vector3d t =
        transforms.translations.col(j) + (data_.graph->positions.col(j) - data_.origin);
    u->block<3, 3>(4 * j, 0) = r.transpose();  // slot 4j + m, coordinate d: R(d, m)
    u->row(4 * j + 3) = t.transpose();
  }
  for (int g = 0; g < data_.num_handle_groups; ++g) {
    const Eigen::Affine3d& handle = handles[g];
    const int h = 4 * (data_.num_nodes + g);
    u->block<3, 3>(h, 0) = handle.linear().transpose();
    // x' - o = A (x - o) + (A o + t - o).
    u->row(h + 3) =
        (handle.linear() * data_.origin + handle.translation() - data_.origin).transpose();
  }
  const int r = 4 * data_.rest_node();
  u->block<3, 3>(r, 0).setIdentity();
  u->row(r + 3).setZero();
}

void SubspaceArap::Scatter(const Slots& u, NodeTransforms* transforms) const {
  for (int slot : data_.variable_slot) {
    const int j = slot / 4, m = slot % 4;
    if (m < 3) {
      transforms->rotation(j).col(m) = u.row(slot).transpose();
    } else {
      transforms->translations.col(j) =
          u.row(slot).transpose() - (data_.graph->positions.col(j) - data_.origin);
    }
  }
}

void SubspaceArap::Variables(const Slots& u, Slots* v) const {
  v->resize(num_slot_variables(), 3);
  for (int i = 0; i < num_slot_variables(); ++i) v->row(i) = u.row(data_.variable_slot[i]);
}

void SubspaceArap::SetVariables(const Slots& v, Slots* u) const {
  for (int i = 0; i < num_slot_variables(); ++i) u->row(data_.variable_slot[i]) = v.row(i);
}

Eigen::Matrix3d SubspaceArap::Covariance(const Slots& u, int c) const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (int e = data_.k_offsets[c]; e < data_.k_offsets[c + 1]; ++e)
    s.noalias() += u.row(data_.k_slot[e]).transpose() * data_.k_vector.col(e).transpose();
  return s;
}

double SubspaceArap::FitRotations(const Slots& u, Rotations* rotations) const {
  rotations->resize(num_clusters());
  double sum = 0.0;
  for (int c = 0; c < num_clusters(); ++c) {
    const Eigen::Matrix3d s = Covariance(u, c);
    (*rotations)[c] = BestRotation(s);
    sum += (*rotations)[c].cwiseProduct(s).sum();
  }
  return sum;
}

double SubspaceArap::EnergyFromTrace(const Slots& u, double trace) const {
  const Slots qu = data_.q * u;
  return 0.5 * (u.cwiseProduct(qu).sum() - 2.0 * trace + data_.constant) /
         (data_.length_unit * data_.length_unit);
}

double SubspaceArap::Cost(const Slots& u) const {
  Rotations rotations;
  return EnergyFromTrace(u, FitRotations(u, &rotations));
}

void SubspaceArap::GlobalRhs(const Slots& u, const Rotations& rotations, Slots* rhs) const {
  *rhs = -(data_.q_vk * u);
  for (int c = 0; c < num_clusters(); ++c) {
    for (int e = data_.k_offsets[c]; e < data_.k_offsets[c + 1]; ++e) {
      const int variable = data_.variable_of_slot[data_.k_slot[e]];
      if (variable < 0) continue;
      rhs->row(variable) += (rotations[c] * data_.k_vector.col(e)).transpose();
    }
  }
}

int SubspaceArapData::PseudoNode(int vertex) const {
  switch (kind[vertex]) {
    case VertexKind::kHandle:
      return num_nodes + (vertex_handle_group.empty() ? 0 : vertex_handle_group[vertex]);
    case VertexKind::kRest:
      return rest_node();
    case VertexKind::kSkinned:
      break;
  }
  return -1;
}

std::vector<SubspaceArap::BasisEntry> SubspaceArap::Basis(int vertex) const {
  std::vector<SubspaceNodeCoefficient> entries;
  AppendSubspaceBasis(vertex, data_.PseudoNode(vertex), *data_.mesh, *data_.graph, data_.origin,
                      &entries);
  std::vector<BasisEntry> basis;
  for (const SubspaceNodeCoefficient& entry : entries) basis.push_back({4 * entry.node, entry.coefficient});
  return basis;
}

std::vector<int> SubspaceArap::ClusterVertices(int c) const {
  return std::vector<int>(data_.cluster_vertices.begin() + data_.cluster_offsets[c],
                          data_.cluster_vertices.begin() + data_.cluster_offsets[c + 1]);
}

const OptionTable<ArapOptions>& ArapOptionTable() {
  static const OptionTable<ArapOptions>& table =
      MakeOptionTable<ArapOptions>([](auto& t) { DeclareArapOptionRows(t); });
  return table;
}

}  // namespace msdeform
