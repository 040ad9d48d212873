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

using VertexKind = SubspaceArapData::VertexKind;

// How each vertex is formed (data->kind: Skinned when a non-Fixed node
// weighs on it, an exact handle's vertices Handle or Rest), the exact
// constraints' vertex lists, and the soft constraint terms it returns:
// (vertex, pseudo-node it is pulled to).
std::vector<std::pair<int, int>> ClassifyVertices(const SubspaceArapInput& input,
                                                  const ArapOptions& options,
                                                  SubspaceArapData* data) {
  const SkinningWeights& weights = input.graph->weights;
  const std::vector<NodeClass>& node_class = *input.node_class;
  const int num_vertices = input.mesh->num_vertices();
  const int n = input.graph->num_nodes();
  const HandleLayout& handles = *input.handles;
  const int num_groups = handles.num_groups();
  const int rest_node = n + num_groups;
  if (num_groups > 1) data->vertex_handle_group.assign(num_vertices, -1);
  const bool exact = options.constraints == ArapConstraints::kExact;
  const std::vector<char>& still = *input.still_vertices;
  auto is_still = [&still](int v) { return !still.empty() && still[v]; };

  data->kind.assign(num_vertices, VertexKind::kRest);
  for (int v = 0; v < num_vertices; ++v) {
    if (is_still(v)) continue;
    for (int s = 0; s < weights.k(); ++s) {
      if (weights.weight(s, v) != 0.0 && node_class[weights.node(s, v)] != NodeClass::kFixed) {
        data->kind[v] = VertexKind::kSkinned;
        break;
      }
    }
  }
  std::vector<std::pair<int, int>> soft_terms;
  for (int i = 0; i < static_cast<int>(handles.moveable.size()); ++i) {
    const int v = handles.moveable[i];
    if (is_still(v)) continue;
    const int handle_node = n + handles.group_of(i);
    if (num_groups > 1) data->vertex_handle_group[v] = handles.group_of(i);
    if (exact) {
      data->kind[v] = VertexKind::kHandle;
      data->exact_moveable.push_back(v);
    } else {
      soft_terms.emplace_back(v, handle_node);
    }
  }
  for (int v : input.handles->fixed) {
    if (is_still(v)) continue;
    if (exact) {
      data->kind[v] = VertexKind::kRest;
      data->exact_fixed.push_back(v);
    } else if (data->kind[v] == VertexKind::kSkinned) {
      soft_terms.emplace_back(v, rest_node);
    }
  }
  return soft_terms;
}

// The variables among the slots: 4 slots of a Totally Free node, 3 of a
// Half Free one (data->variable_slot and its inverse variable_of_slot).
void NumberSlotVariables(const std::vector<NodeClass>& node_class, SubspaceArapData* data) {
  const int n = static_cast<int>(node_class.size());
  data->variable_of_slot.assign(data->num_slots(), -1);
  for (int j = 0; j < n; ++j) {
    const int count = node_class[j] == NodeClass::kTotallyFree ? 4
                      : node_class[j] == NodeClass::kHalfFree  ? 3
                                                               : 0;
    for (int m = 0; m < count; ++m) {
      data->variable_of_slot[4 * j + m] = static_cast<int>(data->variable_slot.size());
      data->variable_slot.push_back(4 * j + m);
    }
  }
}

// The active vertices, those that can move and their neighbours: a mark
// per vertex, and their list in vertex order.
void FindActiveVertices(const std::vector<VertexKind>& kind, const VertexAdjacency& adjacency,
                        std::vector<char>* active, std::vector<int>* active_vertices) {
  const int num_vertices = static_cast<int>(kind.size());
  active->assign(num_vertices, 0);
  for (int v = 0; v < num_vertices; ++v) {
    if (kind[v] == VertexKind::kRest) continue;
    (*active)[v] = 1;
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s)
      (*active)[adjacency.neighbors[s]] = 1;
  }
  for (int v = 0; v < num_vertices; ++v)
    if ((*active)[v]) active_vertices->push_back(v);
}

// The rotation cluster label of each active vertex, as options.clusters
// asks: one per vertex, its heaviest node, or k-means on the skinning
// weights. Not yet compact.
std::vector<int> RotationClusterLabels(const ArapOptions& options, const SkinningWeights& weights,
                                       int num_nodes, const std::vector<int>& active_vertices,
                                       int num_threads) {
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
      label = WeightClusters(weights, num_nodes, active_vertices, options.num_clusters,
                             options.kmeans_iterations, num_threads);
      break;
  }
  return label;
}

// Stores the clusters: the labels made compact (numbered by their first
// vertex), data->cluster_of_vertex, and each cluster's vertices
// (cluster_vertices[cluster_offsets[c] .. cluster_offsets[c + 1])).
void StoreClusters(std::vector<int> label, const std::vector<int>& active_vertices,
                   int num_vertices, SubspaceArapData* data) {
  std::vector<int> renumber;
  std::vector<int> map(label.empty() ? 0 : *std::max_element(label.begin(), label.end()) + 1,
                       -1);
  for (int& l : label) {
    if (map[l] < 0) map[l] = static_cast<int>(renumber.size()), renumber.push_back(l);
    l = map[l];
  }
  const int num_clusters = static_cast<int>(renumber.size());
  data->cluster_of_vertex.assign(num_vertices, -1);
  for (size_t i = 0; i < active_vertices.size(); ++i)
    data->cluster_of_vertex[active_vertices[i]] = label[i];
  data->cluster_offsets.assign(num_clusters + 1, 0);
  for (int l : label) ++data->cluster_offsets[l + 1];
  std::partial_sum(data->cluster_offsets.begin(), data->cluster_offsets.end(),
                   data->cluster_offsets.begin());
  data->cluster_vertices.resize(active_vertices.size());
  std::vector<int> fill(data->cluster_offsets.begin(), data->cluster_offsets.end() - 1);
  for (size_t i = 0; i < active_vertices.size(); ++i)
    data->cluster_vertices[fill[label[i]]++] = active_vertices[i];
}

// The bases of the active vertices and their neighbours, once each, flat:
// vertex v's entries are entries[begin[v] .. begin[v + 1]).
struct FlatBases {
  std::vector<int> begin;
  std::vector<NodeCoefficient> entries;
  BasisSpan of(int v) const {
    return BasisSpan{entries.data() + begin[v], begin[v + 1] - begin[v]};
  }
};

FlatBases BasesNearActive(const SubspaceArapData& data, const std::vector<int>& active_vertices,
                          const Mesh& mesh, const DeformationGraph& graph,
                          const VertexAdjacency& adjacency, const Eigen::Vector3d& origin) {
  const int num_vertices = mesh.num_vertices();
  FlatBases bases;
  bases.begin.assign(num_vertices + 1, 0);
  std::vector<char> needed(num_vertices, 0);
  for (int v : active_vertices) {
    needed[v] = 1;
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s)
      needed[adjacency.neighbors[s]] = 1;
  }
  for (int v = 0; v < num_vertices; ++v) {
    bases.begin[v] = static_cast<int>(bases.entries.size());
    if (!needed[v]) continue;
    AppendSubspaceBasis(v, data.PseudoNode(v), mesh, graph, origin, &bases.entries);
  }
  bases.begin[num_vertices] = static_cast<int>(bases.entries.size());
  return bases;
}

// One fixed range of clusters' share of Q, K_c and C.
struct ClusterChunk {
  explicit ClusterChunk(int num_nodes) : q(num_nodes), cross(num_nodes) {}
  BlockAccumulator q, cross;  // cross: sum -b_i c_i^T; Q gets it and its transpose
  std::vector<int> k_offsets;  // per cluster, the end of its entries
  std::vector<int> k_slot;
  std::vector<Eigen::Vector3d> k_vector;
  double constant = 0.0;
};

// Q = sum over spokes (i, k) of active i of w (b_i - b_k)(b_i - b_k)^T
//   = sum_i [(W_i + omega_i) b_i b_i^T - b_i c_i^T - c_i b_i^T]
//     + sum over inactive k of omega_k b_k b_k^T,
// W_i = sum_k w_ik, c_i = sum_k w_ik b_k, omega_k = sum over active
// neighbours i of w_ik. This is the active vertices' part (all but the last
// sum) with K_c, C and each cluster's covariance (into data->covariance),
// in kChunks fixed ranges of clusters (run in parallel; merged in
// order by the caller, so the sums do not depend on the thread count).
std::vector<ClusterChunk> AccumulateClusterChunks(const Mesh& mesh,
                                                  const VertexAdjacency& adjacency,
                                                  const std::vector<double>& cot,
                                                  const FlatBases& bases,
                                                  const std::vector<double>& omega, int num_threads,
                                                  SubspaceArapData* data) {
  const int n = data->num_nodes;
  data->covariance.assign(data->num_clusters(), Eigen::Matrix3d::Zero());
  constexpr int kChunks = 16;
  const int num_clusters = data->num_clusters();
  const int num_pseudo = n + data->num_handle_groups + 1;
  std::vector<ClusterChunk> chunks(kChunks, ClusterChunk(num_pseudo));
#pragma omp parallel for schedule(dynamic) num_threads(std::max(1, num_threads))
  for (int chunk_index = 0; chunk_index < kChunks; ++chunk_index) {
    ClusterChunk& chunk = chunks[chunk_index];
    std::vector<int> local_of_node(num_pseudo, -1);
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
      for (int p = data->cluster_offsets[c]; p < data->cluster_offsets[c + 1]; ++p) {
        const int i = data->cluster_vertices[p];
        const BasisSpan bi = bases.of(i);
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
          data->covariance[c] += w * e * e.transpose();  // c is this chunk's alone
          for (const NodeCoefficient& entry : bases.of(k)) {
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
  return chunks;
}

// The chunks' K_c (data->k_offsets, k_slot, k_vector) and C, in chunk order.
void MergeKAndConstant(const std::vector<ClusterChunk>& chunks, SubspaceArapData* data) {
  data->k_offsets.assign(1, 0);
  std::vector<Eigen::Vector3d> k_vectors;
  for (const ClusterChunk& chunk : chunks) {
    const int base = static_cast<int>(data->k_slot.size());
    for (int end : chunk.k_offsets) data->k_offsets.push_back(base + end);
    data->k_slot.insert(data->k_slot.end(), chunk.k_slot.begin(), chunk.k_slot.end());
    k_vectors.insert(k_vectors.end(), chunk.k_vector.begin(), chunk.k_vector.end());
    data->constant += chunk.constant;
  }
  data->k_vector.resize(3, static_cast<int>(k_vectors.size()));
  for (size_t e = 0; e < k_vectors.size(); ++e) data->k_vector.col(e) = k_vectors[e];
}

// Q's other terms: the inactive neighbours' share (omega_k b_k b_k^T) and
// the soft constraints (soft_weight d d^T, d = b_v - [x_v; 1] at the target
// pseudo-node).
BlockAccumulator InactiveAndSoftTerms(const Mesh& mesh, const FlatBases& bases,
                                      const std::vector<double>& omega,
                                      const std::vector<char>& active,
                                      const std::vector<std::pair<int, int>>& soft_terms,
                                      const Eigen::Vector3d& origin, const ArapOptions& options,
                                      int num_pseudo_nodes) {
  const int num_vertices = mesh.num_vertices();
  BlockAccumulator q(num_pseudo_nodes);
  for (int v = 0; v < num_vertices; ++v) {
    if (omega[v] == 0.0 || active[v]) continue;
    q.AddOuter(bases.of(v), bases.of(v), omega[v]);
  }
  for (const auto& [v, target] : soft_terms) {
    SparseBasis d(bases.of(v).begin(), bases.of(v).end());
    const Eigen::Vector3d x = mesh.vertices.col(v) - origin;
    AddTo(&d, target, -Eigen::Vector4d(x.x(), x.y(), x.z(), 1.0));
    q.AddOuter(d, d, options.soft_weight);
  }
  return q;
}

// data->q from the chunks' blocks (in chunk order) and the other terms'.
void AssembleQ(const std::vector<ClusterChunk>& chunks, const BlockAccumulator& q,
               SubspaceArapData* data) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (const ClusterChunk& chunk : chunks) {
    chunk.q.AppendTriplets(/*transpose=*/false, &triplets);
    chunk.cross.AppendTriplets(/*transpose=*/false, &triplets);
    chunk.cross.AppendTriplets(/*transpose=*/true, &triplets);
  }
  q.AppendTriplets(/*transpose=*/false, &triplets);
  data->q.resize(data->num_slots(), data->num_slots());
  data->q.setFromTriplets(triplets.begin(), triplets.end());
}

// Q_vv and Q_vk (rows: variables; columns: known slots) out of data->q.
void SplitQByVariables(SubspaceArapData* data) {
  std::vector<Eigen::Triplet<double>> vv, vk;
  for (int col = 0; col < data->q.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(data->q, col); it; ++it) {
      const int row_variable = data->variable_of_slot[it.row()];
      if (row_variable < 0) continue;
      const int col_variable = data->variable_of_slot[col];
      if (col_variable >= 0) {
        vv.emplace_back(row_variable, col_variable, it.value());
      } else {
        vk.emplace_back(row_variable, col, it.value());
      }
    }
  }
  const int nv = data->num_slot_variables();
  data->q_vv.resize(nv, nv);
  data->q_vv.setFromTriplets(vv.begin(), vv.end());
  data->q_vk.resize(nv, data->num_slots());
  data->q_vk.setFromTriplets(vk.begin(), vk.end());
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
  data.num_handle_groups = input.handles->num_groups();
  data.length_unit = input.length_unit;
  data.owner = input.owner;
  data.mesh = input.mesh;
  data.cotangent = input.cotangent;
  data.graph = input.graph;

  const std::vector<std::pair<int, int>> soft_terms = ClassifyVertices(input, options, &data);
  NumberSlotVariables(node_class, &data);
  std::vector<char> active;
  std::vector<int> active_vertices;
  FindActiveVertices(data.kind, adjacency, &active, &active_vertices);
  data.num_active_vertices = static_cast<int>(active_vertices.size());
  // Positions relative to the active vertices' centroid: the expanded energy
  // (u^T Q u - 2 tr + C) loses about 1e-16 of |u|^2 Q, so the slots are kept
  // as small as the moving part allows, wherever the mesh sits.
  data.origin.setZero();
  for (int v : active_vertices) data.origin += mesh.vertices.col(v);
  if (!active_vertices.empty()) data.origin /= static_cast<double>(active_vertices.size());
  const Eigen::Vector3d origin = data.origin;

  StoreClusters(RotationClusterLabels(options, weights, n, active_vertices, input.num_threads),
                active_vertices, num_vertices, &data);
  const FlatBases bases = BasesNearActive(data, active_vertices, mesh, graph, adjacency, origin);

  // omega_k: the cotangent weights of k's spokes from active vertices.
  std::vector<double> omega(num_vertices, 0.0);
  for (int i : active_vertices) {
    for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s)
      omega[adjacency.neighbors[s]] += cot[s];
  }
  const std::vector<ClusterChunk> chunks =
      AccumulateClusterChunks(mesh, adjacency, cot, bases, omega, input.num_threads, &data);
  MergeKAndConstant(chunks, &data);
  AssembleQ(chunks,
            InactiveAndSoftTerms(mesh, bases, omega, active, soft_terms, origin, options,
                                 n + data.num_handle_groups + 1),
            &data);
  SplitQByVariables(&data);
  return std::make_shared<const SubspaceArap>(std::move(data));
}

}  // namespace msdeform
