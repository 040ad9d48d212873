#include "msdeform/scales/subspace_arap.h"

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
  if (num_clusters < 1) {
    *error = "arap.num_clusters must be >= 1";
    return false;
  }
  if (kmeans_iterations < 0) {
    *error = "arap.kmeans_iterations must be >= 0";
    return false;
  }
  if (!(soft_weight > 0.0) || !std::isfinite(soft_weight)) {
    *error = "arap.soft_weight must be a finite weight > 0";
    return false;
  }
  return true;
}

namespace {

// A vertex's basis: (node or pseudo-node, 4 coefficients), at most k + 1.
struct NodeCoefficient {
  int node;
  Eigen::Vector4d coefficient;
};
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

// Appends vertex v's basis to *out: the pseudo-node `pseudo_node` with
// coefficients [x_v - origin; 1] (the handle or the rest pose), or, for a
// skinned vertex (pseudo_node < 0), w_j [x_v - g_j; 1] per node j of non-zero
// weight, a node in two slots once.
void AppendBasis(int v, int pseudo_node, const Mesh& mesh, const DeformationGraph& graph,
                 const Eigen::Vector3d& origin, std::vector<NodeCoefficient>* out) {
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
                           [j](const NodeCoefficient& e) { return e.node == j; });
    if (it != out->end()) {
      it->coefficient += c;
    } else {
      out->push_back({j, c});
    }
  }
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

std::shared_ptr<const SubspaceArap> SubspaceArap::Build(const SubspaceArapInput& input,
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

  std::shared_ptr<SubspaceArap> arap(new SubspaceArap());
  arap->options_ = options;
  arap->num_nodes_ = n;
  arap->length_unit_ = input.length_unit;
  arap->owner_ = input.owner;
  arap->mesh_ = input.mesh;
  arap->cotangent_ = input.cotangent;
  arap->graph_ = input.graph;
  const int handle_node = n, rest_node = n + 1;
  const bool exact = options.constraints == ArapConstraints::kExact;
  const std::vector<char>& still = *input.still_vertices;
  auto is_still = [&still](int v) { return !still.empty() && still[v]; };

  // How each vertex is formed.
  arap->kind_.assign(num_vertices, VertexKind::kRest);
  for (int v = 0; v < num_vertices; ++v) {
    if (is_still(v)) continue;
    for (int s = 0; s < weights.k(); ++s) {
      if (weights.weight(s, v) != 0.0 && node_class[weights.node(s, v)] != NodeClass::kFixed) {
        arap->kind_[v] = VertexKind::kSkinned;
        break;
      }
    }
  }
  // Soft constraint terms: (vertex, pseudo-node it is pulled to).
  std::vector<std::pair<int, int>> soft_terms;
  for (int v : input.handles->moveable) {
    if (is_still(v)) continue;
    if (exact) {
      arap->kind_[v] = VertexKind::kHandle;
      arap->exact_moveable_.push_back(v);
    } else {
      soft_terms.emplace_back(v, handle_node);
    }
  }
  for (int v : input.handles->fixed) {
    if (is_still(v)) continue;
    if (exact) {
      arap->kind_[v] = VertexKind::kRest;
      arap->exact_fixed_.push_back(v);
    } else if (arap->kind_[v] == VertexKind::kSkinned) {
      soft_terms.emplace_back(v, rest_node);
    }
  }

  // Variables: 4 slots of a Totally Free node, 3 of a Half Free one.
  arap->variable_of_slot_.assign(arap->num_slots(), -1);
  for (int j = 0; j < n; ++j) {
    const int count = node_class[j] == NodeClass::kTotallyFree ? 4
                      : node_class[j] == NodeClass::kHalfFree  ? 3
                                                               : 0;
    for (int m = 0; m < count; ++m) {
      arap->variable_of_slot_[4 * j + m] = static_cast<int>(arap->variable_slot_.size());
      arap->variable_slot_.push_back(4 * j + m);
    }
  }

  // Active vertices: those that can move and their neighbours.
  std::vector<char> active(num_vertices, 0);
  for (int v = 0; v < num_vertices; ++v) {
    if (arap->kind_[v] == VertexKind::kRest) continue;
    active[v] = 1;
    for (int s = adjacency.offsets[v]; s < adjacency.offsets[v + 1]; ++s)
      active[adjacency.neighbors[s]] = 1;
  }
  std::vector<int> active_vertices;
  for (int v = 0; v < num_vertices; ++v)
    if (active[v]) active_vertices.push_back(v);
  arap->num_active_vertices_ = static_cast<int>(active_vertices.size());
  // Positions relative to the active vertices' centroid: the expanded energy
  // (u^T Q u - 2 tr + C) loses about 1e-16 of |u|^2 Q, so the slots are kept
  // as small as the moving part allows, wherever the mesh sits.
  arap->origin_.setZero();
  for (int v : active_vertices) arap->origin_ += mesh.vertices.col(v);
  if (!active_vertices.empty()) arap->origin_ /= static_cast<double>(active_vertices.size());
  const Eigen::Vector3d origin = arap->origin_;

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
    arap->cluster_of_vertex_.assign(num_vertices, -1);
    for (size_t i = 0; i < active_vertices.size(); ++i)
      arap->cluster_of_vertex_[active_vertices[i]] = label[i];
    arap->cluster_offsets_.assign(num_clusters + 1, 0);
    for (int l : label) ++arap->cluster_offsets_[l + 1];
    std::partial_sum(arap->cluster_offsets_.begin(), arap->cluster_offsets_.end(),
                     arap->cluster_offsets_.begin());
    arap->cluster_vertices_.resize(active_vertices.size());
    std::vector<int> fill(arap->cluster_offsets_.begin(), arap->cluster_offsets_.end() - 1);
    for (size_t i = 0; i < active_vertices.size(); ++i)
      arap->cluster_vertices_[fill[label[i]]++] = active_vertices[i];
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
    AppendBasis(v, arap->PseudoNode(v), mesh, graph, origin, &basis_entries);
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
  arap->covariance_.assign(arap->num_clusters(), Eigen::Matrix3d::Zero());
  constexpr int kChunks = 16;
  const int num_clusters = arap->num_clusters();
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
      for (int p = arap->cluster_offsets_[c]; p < arap->cluster_offsets_[c + 1]; ++p) {
        const int i = arap->cluster_vertices_[p];
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
          arap->covariance_[c] += w * e * e.transpose();  // c is this chunk's alone
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
  arap->k_offsets_.assign(1, 0);
  std::vector<Eigen::Vector3d> k_vectors;
  for (const Chunk& chunk : chunks) {
    const int base = static_cast<int>(arap->k_slot_.size());
    for (int end : chunk.k_offsets) arap->k_offsets_.push_back(base + end);
    arap->k_slot_.insert(arap->k_slot_.end(), chunk.k_slot.begin(), chunk.k_slot.end());
    k_vectors.insert(k_vectors.end(), chunk.k_vector.begin(), chunk.k_vector.end());
    arap->constant_ += chunk.constant;
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
  arap->k_vector_.resize(3, static_cast<int>(k_vectors.size()));
  for (size_t e = 0; e < k_vectors.size(); ++e) arap->k_vector_.col(e) = k_vectors[e];

  {
    std::vector<Eigen::Triplet<double>> triplets;
    for (const Chunk& chunk : chunks) {
      chunk.q.AppendTriplets(/*transpose=*/false, &triplets);
      chunk.cross.AppendTriplets(/*transpose=*/false, &triplets);
      chunk.cross.AppendTriplets(/*transpose=*/true, &triplets);
    }
    q.AppendTriplets(/*transpose=*/false, &triplets);
    arap->q_.resize(arap->num_slots(), arap->num_slots());
    arap->q_.setFromTriplets(triplets.begin(), triplets.end());
  }
  // Q_vv and Q_vk (rows: variables; columns: known slots).
  std::vector<Eigen::Triplet<double>> vv, vk;
  for (int col = 0; col < arap->q_.outerSize(); ++col) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(arap->q_, col); it; ++it) {
      const int row_variable = arap->variable_of_slot_[it.row()];
      if (row_variable < 0) continue;
      const int col_variable = arap->variable_of_slot_[col];
      if (col_variable >= 0) {
        vv.emplace_back(row_variable, col_variable, it.value());
      } else {
        vk.emplace_back(row_variable, col, it.value());
      }
    }
  }
  const int nv = arap->num_slot_variables();
  arap->q_vv_.resize(nv, nv);
  arap->q_vv_.setFromTriplets(vv.begin(), vv.end());
  arap->q_vk_.resize(nv, arap->num_slots());
  arap->q_vk_.setFromTriplets(vk.begin(), vk.end());
  return arap;
}

void SubspaceArap::Gather(const NodeTransforms& transforms, const Eigen::Affine3d& handle,
                          Slots* u) const {
  CHECK_EQ(transforms.num_nodes(), num_nodes_);
  u->resize(num_slots(), 3);
  for (int j = 0; j < num_nodes_; ++j) {
    const auto r = transforms.rotation(j);
    const Eigen::Vector3d t =
        transforms.translations.col(j) + (graph_->positions.col(j) - origin_);
    u->block<3, 3>(4 * j, 0) = r.transpose();  // slot 4j + m, coordinate d: R(d, m)
    u->row(4 * j + 3) = t.transpose();
  }
  const int h = 4 * num_nodes_;
  u->block<3, 3>(h, 0) = handle.linear().transpose();
  // x' - o = A (x - o) + (A o + t - o).
  u->row(h + 3) = (handle.linear() * origin_ + handle.translation() - origin_).transpose();
  u->block<3, 3>(h + 4, 0).setIdentity();
  u->row(h + 7).setZero();
}

void SubspaceArap::Scatter(const Slots& u, NodeTransforms* transforms) const {
  for (int slot : variable_slot_) {
    const int j = slot / 4, m = slot % 4;
    if (m < 3) {
      transforms->rotation(j).col(m) = u.row(slot).transpose();
    } else {
      transforms->translations.col(j) =
          u.row(slot).transpose() - (graph_->positions.col(j) - origin_);
    }
  }
}

void SubspaceArap::Variables(const Slots& u, Slots* v) const {
  v->resize(num_slot_variables(), 3);
  for (int i = 0; i < num_slot_variables(); ++i) v->row(i) = u.row(variable_slot_[i]);
}

void SubspaceArap::SetVariables(const Slots& v, Slots* u) const {
  for (int i = 0; i < num_slot_variables(); ++i) u->row(variable_slot_[i]) = v.row(i);
}

Eigen::Matrix3d SubspaceArap::Covariance(const Slots& u, int c) const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (int e = k_offsets_[c]; e < k_offsets_[c + 1]; ++e)
    s.noalias() += u.row(k_slot_[e]).transpose() * k_vector_.col(e).transpose();
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
  const Slots qu = q_ * u;
  return 0.5 * (u.cwiseProduct(qu).sum() - 2.0 * trace + constant_) /
         (length_unit_ * length_unit_);
}

double SubspaceArap::Cost(const Slots& u) const {
  Rotations rotations;
  return EnergyFromTrace(u, FitRotations(u, &rotations));
}

void SubspaceArap::GlobalRhs(const Slots& u, const Rotations& rotations, Slots* rhs) const {
  *rhs = -(q_vk_ * u);
  for (int c = 0; c < num_clusters(); ++c) {
    for (int e = k_offsets_[c]; e < k_offsets_[c + 1]; ++e) {
      const int variable = variable_of_slot_[k_slot_[e]];
      if (variable < 0) continue;
      rhs->row(variable) += (rotations[c] * k_vector_.col(e)).transpose();
    }
  }
}

int SubspaceArap::PseudoNode(int vertex) const {
  switch (kind_[vertex]) {
    case VertexKind::kHandle:
      return num_nodes_;
    case VertexKind::kRest:
      return num_nodes_ + 1;
    case VertexKind::kSkinned:
      break;
  }
  return -1;
}

std::vector<SubspaceArap::BasisEntry> SubspaceArap::Basis(int vertex) const {
  std::vector<NodeCoefficient> entries;
  AppendBasis(vertex, PseudoNode(vertex), *mesh_, *graph_, origin_, &entries);
  std::vector<BasisEntry> basis;
  for (const NodeCoefficient& entry : entries) basis.push_back({4 * entry.node, entry.coefficient});
  return basis;
}

std::vector<int> SubspaceArap::ClusterVertices(int c) const {
  return std::vector<int>(cluster_vertices_.begin() + cluster_offsets_[c],
                          cluster_vertices_.begin() + cluster_offsets_[c + 1]);
}

}  // namespace msdeform
