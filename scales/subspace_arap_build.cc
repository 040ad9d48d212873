#include "msdeform/scales/subspace_arap_build.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

#include <glog/logging.h>

namespace msdeform {

namespace {

using NodeCoefficient = SubspaceNodeCoefficient;
// A vertex's basis, at most k + 1 entries.
using SparseBasis = std::vector<NodeCoefficient>;

// Adds scale * c to the entry of `node` in `basis` (a short list).
void AddTo(SparseBasis* basis, int node, const Eigen::Vector4d& c) {
  for (NodeCoefficient& entry : *basis) {
    if (entry.node == node) {
      entry.coefficient += c;
      return;
    }
  }
  basis->push_back({node, c});
}

// A vertex's basis entries in a flat array.
struct BasisSpan {
  const NodeCoefficient* data;
  int size;
  const NodeCoefficient* begin() const { return data; }
  const NodeCoefficient* end() const { return data + size; }
};

// 4x4 blocks of Q between nodes and pseudo-nodes, row by row.
class BlockAccumulator {
 public:
  explicit BlockAccumulator(int num_nodes) : rows_(num_nodes) {}

  // Q += scale * a b^T over the nodes of a and b.
  template <typename A, typename B>
  void AddOuter(const A& a, const B& b, double scale) {
    for (const NodeCoefficient& x : a) {
      auto& row = rows_[x.node];
      const Eigen::Vector4d sx = scale * x.coefficient;
      for (const NodeCoefficient& y : b) Block(&row, y.node).noalias() += sx * y.coefficient.transpose();
    }
  }

  // The non-zero entries (of the transpose when asked), row by row.
  void AppendTriplets(bool transpose, std::vector<Eigen::Triplet<double>>* triplets) const {
    for (int a = 0; a < static_cast<int>(rows_.size()); ++a) {
      for (const auto& [b, block] : rows_[a]) {
        for (int r = 0; r < 4; ++r) {
          for (int c = 0; c < 4; ++c) {
            if (block(r, c) == 0.0) continue;
            if (transpose) {
              triplets->emplace_back(4 * b + c, 4 * a + r, block(r, c));
            } else {
              triplets->emplace_back(4 * a + r, 4 * b + c, block(r, c));
            }
          }
        }
      }
    }
  }

 private:
  using Row = std::vector<std::pair<int, Eigen::Matrix4d>>;
  static Eigen::Matrix4d& Block(Row* row, int b) {
    for (auto& entry : *row) {
      if (entry.first == b) return entry.second;
    }
    row->emplace_back(b, Eigen::Matrix4d::Zero());
    return row->back().second;
  }

  std::vector<Row> rows_;
};

// The heaviest node of v (the lowest slot on a tie).
int HeaviestNode(const SkinningWeights& weights, int v) {
  int best = weights.node(0, v);
  double best_weight = weights.weight(0, v);
  for (int s = 1; s < weights.k(); ++s) {
    if (weights.weight(s, v) > best_weight) {
      best_weight = weights.weight(s, v);
      best = weights.node(s, v);
    }
  }
  return best;
}

// Cluster labels 0..C-1 over `vertices` (sorted), by k-means on the skinning
// weight vectors (FAST). The Lloyd iterations run on a sample of about
// 8 C vertices (every stride-th), with initial centres at evenly spaced
// sample vertices of the order by heaviest node; a vertex is compared only
// with the centres that share one of its nodes. A last pass assigns every
// vertex to its nearest centre.
std::vector<int> WeightClusters(const SkinningWeights& weights, int num_nodes,
                                const std::vector<int>& vertices, int num_clusters,
                                int iterations, int num_threads) {
  if (vertices.empty()) return {};
  const int num_vertices = static_cast<int>(vertices.size());
  const int count = std::min(num_clusters, num_vertices);
  const int k = weights.k();
  const int stride = std::max(1, num_vertices / (8 * count));
  std::vector<int> sample;
  for (int i = 0; i < num_vertices; i += stride) sample.push_back(vertices[i]);
  const int num_sample = static_cast<int>(sample.size());
  std::vector<int> order(sample.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<int> heaviest(sample.size());
  for (int i = 0; i < num_sample; ++i) heaviest[i] = HeaviestNode(weights, sample[i]);
  std::stable_sort(order.begin(), order.end(),
                   [&heaviest](int a, int b) { return heaviest[a] < heaviest[b]; });
  // Centres: dense over the nodes, with the clusters each node is non-zero in.
  Eigen::MatrixXd centre = Eigen::MatrixXd::Zero(num_nodes, count);
  auto add_vertex = [&](int c, int v, double scale) {
    for (int s = 0; s < k; ++s) centre(weights.node(s, v), c) += scale * weights.weight(s, v);
  };
  for (int c = 0; c < count; ++c) {
    const int i = order[static_cast<size_t>(
        (static_cast<int64_t>(2 * c + 1) * num_sample) / (2 * count))];
    add_vertex(c, sample[i], 1.0);
  }
  std::vector<std::vector<int>> clusters_of_node(num_nodes);
  Eigen::VectorXd centre_norm(count);
  // Nearest centre of each of `list` into `label` (kept where no centre shares a node).
  auto assign = [&](const std::vector<int>& list, std::vector<int>* label) {
    for (auto& nodes : clusters_of_node) nodes.clear();
    for (int c = 0; c < count; ++c) {
      centre_norm[c] = centre.col(c).squaredNorm();
      for (int j = 0; j < num_nodes; ++j)
        if (centre(j, c) != 0.0) clusters_of_node[j].push_back(c);
    }
    const int size = static_cast<int>(list.size());
    // Threads for the last pass over every vertex only: the sample passes
    // are too short to pay for waking them.
    const int threads = size > 16 * count ? std::max(1, num_threads) : 1;
#pragma omp parallel num_threads(threads)
    {
      // Per thread: the clusters already compared with the current vertex.
      std::vector<int> seen(count, -1);
#pragma omp for schedule(static)
      for (int i = 0; i < size; ++i) {
        const int v = list[i];
        double best = std::numeric_limits<double>::infinity();
        int best_cluster = -1;
        for (int s = 0; s < k; ++s) {
          if (weights.weight(s, v) == 0.0) continue;
          for (int c : clusters_of_node[weights.node(s, v)]) {
            if (seen[c] == i) continue;
            seen[c] = i;
            double dot = 0.0;
            for (int t = 0; t < k; ++t) dot += weights.weight(t, v) * centre(weights.node(t, v), c);
            const double distance = centre_norm[c] - 2.0 * dot;
            if (distance < best || (distance == best && c < best_cluster)) {
              best = distance;
              best_cluster = c;
            }
          }
        }
        if (best_cluster >= 0) (*label)[i] = best_cluster;
      }
    }
  };
  std::vector<int> sample_label(sample.size(), 0);
  for (int iteration = 0; iteration < iterations; ++iteration) {
    assign(sample, &sample_label);
    // Each centre the mean of its sample vertices (an empty one stays).
    std::vector<int> size(count, 0);
    for (int i = 0; i < num_sample; ++i) ++size[sample_label[i]];
    for (int c = 0; c < count; ++c)
      if (size[c] > 0) centre.col(c).setZero();
    for (int i = 0; i < num_sample; ++i)
      add_vertex(sample_label[i], sample[i], 1.0 / size[sample_label[i]]);
  }
  std::vector<int> label(vertices.size(), 0);
  assign(vertices, &label);
  return label;
}

}  // namespace

std::shared_ptr<const SubspaceArap> BuildSubspaceArap(const SubspaceArapInput& input,
                                                      const ArapOptions& options) {
  CHECK(input.mesh && input.cotangent && input.graph && input.node_class && input.handles &&
        input.still_vertices);
  CHECK_GT(input.length_unit, 0.0);
  const Mesh& mesh = *input.mesh;
  const DeformationGraph& graph = *input.graph;
  const SkinningWeights& weights = graph.weights;
  const std::vector<NodeClass>& node_class = *input.node_class;
  const VertexAdjacency& adjacency = input.cotangent->adjacency;
  const std::vector<double>& cot = input.cotangent->weight;
  const int num_vertices = mesh.num_vertices();
  const int n = graph.num_nodes();
  CHECK_EQ(static_cast<int>(node_class.size()), n);
  CHECK_EQ(weights.num_vertices(), num_vertices);

  SubspaceArapData data;
  data.options = options;
  data.num_nodes = n;
  data.length_unit = input.length_unit;
  data.owner = input.owner;
  data.mesh = input.mesh;
  data.cotangent = input.cotangent;
  data.graph = input.graph;
  const int handle_node = n, rest_node = n + 1;
  const bool exact = options.constraints == ArapConstraints::kExact;
  const std::vector<char>& still = *input.still_vertices;
  auto is_still = [&still](int v) { return !still.empty() && still[v]; };

  // How each vertex is formed.
  data.kind.assign(num_vertices, SubspaceArapData::VertexKind::kRest);
  for (int v = 0; v < num_vertices; ++v) {
    if (is_still(v)) continue;
    for (int s = 0; s < weights.k(); ++s) {
      if (weights.weight(s, v) != 0.0 && node_class[weights.node(s, v)] != NodeClass::kFixed) {
        data.kind[v] = SubspaceArapData::VertexKind::kSkinned;
        break;
      }
    }
  }
  // Soft constraint terms: (vertex, pseudo-node it is pulled to).
  std::vector<std::pair<int, int>> soft_terms;
  for (int v : input.handles->moveable) {
    if (is_still(v)) continue;
    if (exact) {
      data.kind[v] = SubspaceArapData::VertexKind::kHandle;
      data.exact_moveable.push_back(v);
    } else {
      soft_terms.emplace_back(v, handle_node);
    }
  }
  for (int v : input.handles->fixed) {
    if (is_still(v)) continue;
    if (exact) {
      data.kind[v] = SubspaceArapData::VertexKind::kRest;
      data.exact_fixed.push_back(v);
    } else if (data.kind[v] == SubspaceArapData::VertexKind::kSkinned) {
      soft_terms.emplace_back(v, rest_node);
    }
  }

  // Variables: 4 slots of a Totally Free node, 3 of a Half Free one.
  data.variable_of_slot.assign(data.num_slots(), -1);
  for (int j = 0; j < n; ++j) {
    const int count = node_class[j] == NodeClass::kTotallyFree ? 4
                      : node_class[j] == NodeClass::kHalfFree  ? 3
                                                               : 0;
    for (int m = 0; m < count; ++m) {
      data.variable_of_slot[4 * j + m] = static_cast<int>(data.variable_slot.size());
      data.variable_slot.push_back(4 * j + m);
    }
  }

  // Active vertices: those that can move and their neighbours.
  std::vector<char> active(num_vertices, 0);
  for (int v = 0; v < num_vertices; ++v) {
    if (data.kind[v] == SubspaceArapData::VertexKind::kRest) continue;
    active[v] = 1;
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s)
      active[adjacency.neighbors[s]] = 1;
  }
  std::vector<int> active_vertices;
  for (int v = 0; v < num_vertices; ++v)
    if (active[v]) active_vertices.push_back(v);
  data.num_active_vertices = static_cast<int>(active_vertices.size());
  // Positions relative to the active vertices' centroid: the expanded energy
  // (u^T Q u - 2 tr + C) loses about 1e-16 of |u|^2 Q, so the slots are kept
  // as small as the moving part allows, wherever the mesh sits.
  data.origin.setZero();
  for (int v : active_vertices) data.origin += mesh.vertices.col(v);
  if (!active_vertices.empty()) data.origin /= static_cast<double>(active_vertices.size());
  const Eigen::Vector3d origin = data.origin;

  // Rotation clusters over the active vertices.
  std::vector<int> label(active_vertices.size());
  switch (options.clusters) {
    case RotationClusters::kVertices:
      std::iota(label.begin(), label.end(), 0);
      break;
    case RotationClusters::kNodes:
      for (size_t i = 0; i < active_vertices.size(); ++i)
        label[i] = HeaviestNode(weights, active_vertices[i]);
      break;
    case RotationClusters::kWeights:
      label = WeightClusters(weights, n, active_vertices, options.num_clusters,
                             options.kmeans_iterations, input.num_threads);
      break;
  }
  // Compact labels, numbered by their first vertex.
  {
    std::vector<int> renumber;
    std::vector<int> map(label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1,
                         -1);
    for (int& l : label) {
      if (map[l] < 0) map[l] = static_cast<int>(renumber.size()), renumber.push_back(l);
      l = map[l];
    }
    const int num_clusters = static_cast<int>(renumber.size());
    data.cluster_of_vertex.assign(num_vertices, -1);
    for (size_t i = 0; i < active_vertices.size(); ++i)
      data.cluster_of_vertex[active_vertices[i]] = label[i];
    data.cluster_offsets.assign(num_clusters + 1, 0);
    for (int l : label) ++data.cluster_offsets[l + 1];
    std::partial_sum(data.cluster_offsets.begin(), data.cluster_offsets.end(),
                     data.cluster_offsets.begin());
    data.cluster_vertices.resize(active_vertices.size());
    std::vector<int> fill(data.cluster_offsets.begin(), data.cluster_offsets.end() - 1);
    for (size_t i = 0; i < active_vertices.size(); ++i)
      data.cluster_vertices[fill[label[i]]++] = active_vertices[i];
  }

  // The bases of the active vertices and their neighbours, once each, flat:
  // vertex v's entries are basis_entries[basis_begin[v] .. basis_begin[v + 1]).
  std::vector<int> basis_begin(num_vertices + 1, 0);
  std::vector<char> needed(num_vertices, 0);
  for (int v : active_vertices) {
    needed[v] = 1;
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s)
      needed[adjacency.neighbors[s]] = 1;
  }
  std::vector<NodeCoefficient> basis_entries;
  for (int v = 0; v < num_vertices; ++v) {
    basis_begin[v] = static_cast<int>(basis_entries.size());
    if (!needed[v]) continue;
    AppendSubspaceBasis(v, data.PseudoNode(v), mesh, graph, origin, &basis_entries);
  }
  basis_begin[num_vertices] = static_cast<int>(basis_entries.size());
  auto basis = [&](int v) {
    return BasisSpan{basis_entries.data() + basis_begin[v], basis_begin[v + 1] - basis_begin[v]};
  };

  // Q = sum over spokes (i, k) of active i of w (b_i - b_k)(b_i - b_k)^T
  //   = sum_i [(W_i + omega_i) b_i b_i^T - b_i c_i^T - c_i b_i^T]
  //     + sum over inactive k of omega_k b_k b_k^T,
  // W_i = sum_k w_ik, c_i = sum_k w_ik b_k, omega_k = sum over active
  // neighbours i of w_ik. K_c and C by cluster, in kChunks fixed ranges of
  // clusters (run in parallel; merged in order, so the sums do not depend on
  // the thread count).
  std::vector<double> omega(num_vertices, 0.0);
  for (int i : active_vertices) {
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s)
      omega[adjacency.neighbors[s]] += cot[s];
  }
  struct Chunk {
    explicit Chunk(int num_nodes) : q(num_nodes), cross(num_nodes) {}
    BlockAccumulator q, cross;  // cross: sum -b_i c_i^T; Q gets it and its transpose
    std::vector<int> k_offsets;  // per cluster, the end of its entries
    std::vector<int> k_slot;
    std::vector<Eigen::Vector3d> k_vector;
    double constant = 0.0;
  };
  data.covariance.assign(data.num_clusters(), Eigen::Matrix3d::Zero());
  constexpr int kChunks = 16;
  const int num_clusters = data.num_clusters();
  std::vector<Chunk> chunks(kChunks, Chunk(n + 2));
#pragma omp parallel for schedule(dynamic) num_threads(std::max(1, input.num_threads))
  for (int chunk_index = 0; chunk_index < kChunks; ++chunk_index) {
    Chunk& chunk = chunks[chunk_index];
    std::vector<int> local_of_node(n + 2, -1);
    std::vector<int> local_nodes;
    std::vector<Eigen::Matrix<double, 3, 4>> local_k;
    SparseBasis ci;
    auto local_index = [&](int node) {
      int& local = local_of_node[node];
      if (local < 0) {
        local = static_cast<int>(local_nodes.size());
        local_nodes.push_back(node);
        local_k.push_back(Eigen::Matrix<double, 3, 4>::Zero());
      }
      return local;
    };
    const int first = static_cast<int>(static_cast<int64_t>(num_clusters) * chunk_index / kChunks);
    const int last =
        static_cast<int>(static_cast<int64_t>(num_clusters) * (chunk_index + 1) / kChunks);
    for (int c = first; c < last; ++c) {
      for (int p = data.cluster_offsets[c]; p < data.cluster_offsets[c + 1]; ++p) {
        const int i = data.cluster_vertices[p];
        const BasisSpan bi = basis(i);
        ci.clear();
        double wi = 0.0;
        Eigen::Vector3d we = Eigen::Vector3d::Zero();
        for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
          const int k = adjacency.neighbors[s];
          const double w = cot[s];
          if (w == 0.0) continue;
          const Eigen::Vector3d e = mesh.vertices.col(i) - mesh.vertices.col(k);
          wi += w;
          we += w * e;
          chunk.constant += w * e.squaredNorm();
          data.covariance[c] += w * e * e.transpose();  // c is this chunk's alone
          for (const NodeCoefficient& entry : basis(k)) {
            AddTo(&ci, entry.node, w * entry.coefficient);
            local_k[local_index(entry.node)] -= w * e * entry.coefficient.transpose();  // -w e b_k^T
          }
        }
        for (const NodeCoefficient& entry : bi)
          local_k[local_index(entry.node)] += we * entry.coefficient.transpose();
        chunk.q.AddOuter(bi, bi, wi + omega[i]);
        chunk.cross.AddOuter(bi, BasisSpan{ci.data(), static_cast<int>(ci.size())}, -1.0);
      }
      for (size_t l = 0; l < local_nodes.size(); ++l) {
        for (int m = 0; m < 4; ++m) {
          chunk.k_slot.push_back(4 * local_nodes[l] + m);
          chunk.k_vector.push_back(local_k[l].col(m));
        }
        local_of_node[local_nodes[l]] = -1;
      }
      local_nodes.clear();
      local_k.clear();
      chunk.k_offsets.push_back(static_cast<int>(chunk.k_slot.size()));
    }
  }
  data.k_offsets.assign(1, 0);
  std::vector<Eigen::Vector3d> k_vectors;
  for (const Chunk& chunk : chunks) {
    const int base = static_cast<int>(data.k_slot.size());
    for (int end : chunk.k_offsets) data.k_offsets.push_back(base + end);
    data.k_slot.insert(data.k_slot.end(), chunk.k_slot.begin(), chunk.k_slot.end());
    k_vectors.insert(k_vectors.end(), chunk.k_vector.begin(), chunk.k_vector.end());
    data.constant += chunk.constant;
  }
  // The inactive neighbours' share, and the soft constraints.
  BlockAccumulator q(n + 2);
  for (int v = 0; v < num_vertices; ++v) {
    if (omega[v] == 0.0 || active[v]) continue;
    q.AddOuter(basis(v), basis(v), omega[v]);
  }
  for (const auto& [v, target] : soft_terms) {
    SparseBasis d(basis(v).begin(), basis(v).end());
    const Eigen::Vector3d x = mesh.vertices.col(v) - origin;
    AddTo(&d, target, -Eigen::Vector4d(x.x(), x.y(), x.z(), 1.0));
    q.AddOuter(d, d, options.soft_weight);
  }
  data.k_vector.resize(3, static_cast<int>(k_vectors.size()));
  for (size_t e = 0; e < k_vectors.size(); ++e) data.k_vector.col(e) = k_vectors[e];

  {
    std::vector<Eigen::Triplet<double>> triplets;
    for (const Chunk& chunk : chunks) {
      chunk.q.AppendTriplets(/*transpose=*/false, &triplets);
      chunk.cross.AppendTriplets(/*transpose=*/false, &triplets);
      chunk.cross.AppendTriplets(/*transpose=*/true, &triplets);
    }
    q.AppendTriplets(/*transpose=*/false, &triplets);
    data.q.resize(data.num_slots(), data.num_slots());
    data.q.setFromTriplets(triplets.begin(), triplets.end());
  }
  // Q_vv and Q_vk (rows: variables; columns: known slots).
  std::vector<Eigen::Triplet<double>> vv, vk;
  for (int col = 0; col < data.q.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(data.q, col); it; ++it) {
      const int row_variable = data.variable_of_slot[it.row()];
      if (row_variable < 0) continue;
      const int col_variable = data.variable_of_slot[col];
      if (col_variable >= 0) {
        vv.emplace_back(row_variable, col_variable, it.value());
      } else {
        vk.emplace_back(row_variable, col, it.value());
      }
    }
  }
  const int nv = data.num_slot_variables();
  data.q_vv.resize(nv, nv);
  data.q_vv.setFromTriplets(vv.begin(), vv.end());
  data.q_vk.resize(nv, data.num_slots());
  data.q_vk.setFromTriplets(vk.begin(), vk.end());
  return std::make_shared<const SubspaceArap>(std::move(data));
}


}  // namespace msdeform
