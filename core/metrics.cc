#include "msdeform/core/metrics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include <Eigen/SVD>
#include <glog/logging.h>

#include "msdeform/core/cotangent_weights.h"

namespace msdeform {

double HandleRmsError(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                      const std::vector<int>& vertices, const Eigen::Affine3d& deformed_from_rest) {
  CHECK_EQ(rest.vertices.cols(), deformed.cols());
  if (vertices.empty()) return 0.0;
  double sum = 0.0;
  for (int v : vertices) {
    sum += (deformed.col(v) - deformed_from_rest * Eigen::Vector3d(rest.vertices.col(v)))
               .squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(vertices.size()));
}

double HandleRmsError(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                      const HandleLayout& layout, const HandleTransforms& deformed_from_rest) {
  CHECK_EQ(rest.vertices.cols(), deformed.cols());
  if (layout.moveable.empty()) return 0.0;
  double sum = 0.0;
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    const int v = layout.moveable[i];
    sum += (deformed.col(v) -
            deformed_from_rest[layout.group_of(i)] * Eigen::Vector3d(rest.vertices.col(v)))
               .squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(layout.moveable.size()));
}

Displacement VertexDisplacement(const Mesh& rest, const Eigen::Matrix3Xd& deformed,
                                const std::vector<int>& vertices) {
  CHECK_EQ(rest.vertices.cols(), deformed.cols());
  Displacement result;
  if (vertices.empty()) return result;
  for (int v : vertices) {
    const double d = (deformed.col(v) - rest.vertices.col(v)).norm();
    result.mean += d;
    result.max = std::max(result.max, d);
  }
  result.mean /= static_cast<double>(vertices.size());
  return result;
}

ArapTerms ArapEnergyPerVertex(const Mesh& rest, const Eigen::Matrix3Xd& deformed) {
  CHECK_EQ(rest.vertices.cols(), deformed.cols());
  const int n = rest.num_vertices();
  // The undirected edges (a < b) in sorted order with their cotangent weights.
  const CotangentWeights cotangent = ComputeCotangentWeights(rest);
  struct Edge {
    int a, b;
    double w;
  };
  std::vector<Edge> edges;
  edges.reserve(cotangent.weight.size() / 2);
  for (int a = 0; a < n; ++a) {
    for (int s = cotangent.adjacency.offsets[a]; s < cotangent.adjacency.offsets[a + 1]; ++s) {
      const int b = cotangent.adjacency.neighbors[s];
      if (b > a) edges.push_back({a, b, cotangent.weight[s]});
    }
  }
  // Per-vertex covariance, then the best rotation, then the energy.
  std::vector<Eigen::Matrix3d> covariance(n, Eigen::Matrix3d::Zero());
  ArapTerms terms;
  terms.energy = Eigen::VectorXd::Zero(n);
  terms.normaliser = Eigen::VectorXd::Zero(n);
  for (const Edge& edge : edges) {
    const Eigen::Vector3d e0 = rest.vertices.col(edge.a) - rest.vertices.col(edge.b);
    const Eigen::Vector3d e1 = deformed.col(edge.a) - deformed.col(edge.b);
    const Eigen::Matrix3d outer = edge.w * e1 * e0.transpose();
    covariance[edge.a] += outer;
    covariance[edge.b] += outer;  // (-e1)(-e0)^T
    terms.normaliser[edge.a] += edge.w * e0.squaredNorm();
    terms.normaliser[edge.b] += edge.w * e0.squaredNorm();
  }
  std::vector<Eigen::Matrix3d> rotation(n);
  for (int i = 0; i < n; ++i) {
    // R maximising tr(R^T S) with S = sum w e1 e0^T: R = U diag(1, 1, det(U V^T)) V^T.
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance[i], Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) *= -1.0;
    rotation[i] = u * svd.matrixV().transpose();
  }
  for (const Edge& edge : edges) {
    const Eigen::Vector3d e0 = rest.vertices.col(edge.a) - rest.vertices.col(edge.b);
    const Eigen::Vector3d e1 = deformed.col(edge.a) - deformed.col(edge.b);
    terms.energy[edge.a] += edge.w * (e1 - rotation[edge.a] * e0).squaredNorm();
    terms.energy[edge.b] += edge.w * (e1 - rotation[edge.b] * e0).squaredNorm();
  }
  return terms;
}

double NormalisedArapEnergy(const ArapTerms& terms, const std::vector<int>& vertices) {
  double energy = 0.0, normaliser = 0.0;
  if (vertices.empty()) {
    energy = terms.energy.sum();
    normaliser = terms.normaliser.sum();
  } else {
    for (int v : vertices) {
      energy += terms.energy[v];
      normaliser += terms.normaliser[v];
    }
  }
  return normaliser > 0.0 ? energy / normaliser : 0.0;
}

double MeanEdgeStrain(const Mesh& rest, const Eigen::Matrix3Xd& deformed) {
  CHECK_EQ(rest.vertices.cols(), deformed.cols());
  double sum = 0.0;
  int count = 0;
  for (const auto& [a, b] : UniqueEdges(rest)) {
    const double l0 = (rest.vertices.col(a) - rest.vertices.col(b)).norm();
    if (!(l0 > 0.0)) continue;
    sum += std::abs((deformed.col(a) - deformed.col(b)).norm() / l0 - 1.0);
    ++count;
  }
  return count > 0 ? sum / count : 0.0;
}

double OrthogonalityError(const NodeTransforms& transforms, const std::vector<int>& nodes) {
  if (nodes.empty()) return 0.0;
  double sum = 0.0;
  for (int j : nodes) {
    const Eigen::Matrix3d r = transforms.rotation(j);
    sum += (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
  }
  return sum / static_cast<double>(nodes.size());
}

std::vector<int> VerticesNear(const Mesh& mesh, const std::vector<int>& sources, double radius) {
  const int n = mesh.num_vertices();
  const VertexAdjacency adjacency = ComputeVertexAdjacency(mesh);
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int s : sources) {
    distance[s] = 0.0;
    queue.push({0.0, s});
  }
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k) {
      const int u = adjacency.neighbors[k];
      const double du = d + (mesh.vertices.col(u) - mesh.vertices.col(v)).norm();
      if (du < distance[u] && du <= radius) {
        distance[u] = du;
        queue.push({du, u});
      }
    }
  }
  std::vector<char> is_source(n, 0);
  for (int s : sources) is_source[s] = 1;
  std::vector<int> near;
  for (int v = 0; v < n; ++v)
    if (!is_source[v] && distance[v] <= radius) near.push_back(v);
  return near;
}

}  // namespace msdeform
