#include "msdeform/core/cotangent_weights.h"

#include <algorithm>
#include <utility>
#include <vector>

#include <glog/logging.h>

namespace msdeform {
namespace {

// The slot of neighbour k in v's sorted list.
int Slot(const VertexAdjacency& adjacency, int v, int k) {
  const auto begin = adjacency.neighbors.begin() + adjacency.offsets[v];
  const auto end = adjacency.neighbors.begin() + adjacency.offsets[v + 1];
  const auto it = std::lower_bound(begin, end, k);
  CHECK(it != end && *it == k) << "edge " << v << "-" << k << " is not in the adjacency";
  return static_cast<int>(it - adjacency.neighbors.begin());
}

}  // namespace

CotangentWeights ComputeCotangentWeights(const Mesh& mesh) {
  CotangentWeights result;
  result.adjacency = ComputeVertexAdjacency(mesh);
  const VertexAdjacency& adjacency = result.adjacency;
  // Per edge (at its slot in the lower vertex's list) the sum of its
  // half-cotangents. Two halves sum the same in either order; an edge of three
  // or more faces is summed again in ascending order, so that its weight does
  // not depend on the order of the faces.
  std::vector<double> sum(adjacency.neighbors.size(), 0.0);
  std::vector<int> count(adjacency.neighbors.size(), 0);
  std::vector<std::pair<int, double>> corners(3 * static_cast<size_t>(mesh.num_faces()));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int i = mesh.faces(c, f), j = mesh.faces((c + 1) % 3, f),
                k = mesh.faces((c + 2) % 3, f);
      const Eigen::Vector3d a = mesh.vertices.col(j) - mesh.vertices.col(i);
      const Eigen::Vector3d b = mesh.vertices.col(k) - mesh.vertices.col(i);
      const double cross = a.cross(b).norm();
      const double half = 0.5 * (cross > 0.0 ? a.dot(b) / cross : 0.0);
      const int slot = Slot(adjacency, std::min(j, k), std::max(j, k));
      sum[slot] += half;
      ++count[slot];
      corners[3 * static_cast<size_t>(f) + c] = {slot, half};
    }
  }
  if (std::any_of(count.begin(), count.end(), [](int n) { return n > 2; })) {
    std::sort(corners.begin(), corners.end());
    for (size_t s = 0; s < corners.size();) {
      size_t e = s;
      double w = 0.0;
      while (e < corners.size() && corners[e].first == corners[s].first) w += corners[e++].second;
      if (count[corners[s].first] > 2) sum[corners[s].first] = w;
      s = e;
    }
  }
  result.weight.assign(adjacency.neighbors.size(), 0.0);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s) {
      const int k = adjacency.neighbors[s];
      if (k < v) continue;
      const double w = std::max(sum[s], 0.0);
      result.weight[s] = w;
      result.weight[Slot(adjacency, k, v)] = w;
    }
  }
  return result;
}

}  // namespace msdeform
