#include "msdeform/core/deformation_graph.h"

#include <algorithm>
#include <functional>
#include <queue>
#include <random>
#include <sstream>
#include <tuple>

#include <glog/logging.h>
#include <omp.h>

namespace msdeform {
namespace {

// DG1 without weights: one node per surface cell on a random vertex of it.
DeformationGraph MakeFinestGraph(const Mesh& mesh, const Lattice& lattice, uint64_t seed) {
  const int num_cells = lattice.num_surface_cells();
  const CompressedLists& cell_vertices = lattice.vertices_of_cell();
  DeformationGraph graph;
  graph.positions.resize(3, num_cells);
  graph.node_vertex.resize(num_cells);
  graph.node_of_dg1.resize(num_cells);
  graph.members.offsets.resize(num_cells + 1);
  graph.members.values.resize(num_cells);
  // rng() % n rather than std::uniform_int_distribution: the latter's output
  // differs between standard libraries, and the bias of % is below 1e-15.
  std::mt19937_64 rng(seed);
  for (int c = 0; c < num_cells; ++c) {
    const int count = cell_vertices.size(c);
    CHECK_GT(count, 0) << "surface cell " << c << " holds no vertex";
    const int vertex = cell_vertices.begin(c)[rng() % static_cast<uint64_t>(count)];
    graph.node_vertex[c] = vertex;
    graph.positions.col(c) = mesh.vertices.col(vertex);
    graph.node_of_dg1[c] = c;
    graph.members.offsets[c] = c;
    graph.members.values[c] = c;
  }
  graph.members.offsets[num_cells] = num_cells;
  return graph;
}

}  // namespace

void DeformationGraph::Disconnect() {
  std::vector<std::pair<int, int>>().swap(edges);
  neighbors = CompressedLists();
  weights = SkinningWeights();
}

void ConnectGraph(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                  DeformationGraph* graph) {
  ComputeNearestNodes(mesh.vertices, lattice, graph->positions, graph->node_of_dg1,
                      options.nearest_nodes(),
                      &graph->weights, &graph->edges);
  const int num_nodes = graph->num_nodes();
  CompressedLists& neighbors = graph->neighbors;
  neighbors.offsets.assign(num_nodes + 1, 0);
  for (const auto& [a, b] : graph->edges) {
    ++neighbors.offsets[a + 1];
    ++neighbors.offsets[b + 1];
  }
  for (int j = 0; j < num_nodes; ++j) neighbors.offsets[j + 1] += neighbors.offsets[j];
  neighbors.values.resize(neighbors.offsets[num_nodes]);
  std::vector<int> fill(neighbors.offsets.begin(), neighbors.offsets.end() - 1);
  for (const auto& [a, b] : graph->edges) {
    neighbors.values[fill[a]++] = b;
    neighbors.values[fill[b]++] = a;
  }
  for (int j = 0; j < num_nodes; ++j) {
    std::sort(neighbors.values.begin() + neighbors.offsets[j],
              neighbors.values.begin() + neighbors.offsets[j + 1]);
  }
}

namespace {

// One edge-collapse pass over the DG1 edge graph, shortest edge first, with
// lazy deletion: a queued pair is stale once either side has changed. When no
// edge joins two clusters (several components), the two clusters with the
// closest node positions are merged instead, so every node count is reached.
class EdgeCollapse {
 public:
  explicit EdgeCollapse(const DeformationGraph& dg1)
      : dg1_positions_(dg1.positions),
        dg1_vertex_(dg1.node_vertex),
        parent_(dg1.num_nodes()),
        stamp_(dg1.num_nodes(), 0),
        members_(dg1.num_nodes()),
        adjacency_(dg1.num_nodes()),
        sum_(dg1.positions),
        position_(dg1.positions),
        vertex_(dg1.node_vertex),
        num_clusters_(dg1.num_nodes()) {
    for (int j = 0; j < num_clusters_; ++j) {
      parent_[j] = j;
      members_[j] = {j};
      adjacency_[j].assign(dg1.neighbors.begin(j), dg1.neighbors.end(j));
    }
    for (const auto& [a, b] : dg1.edges) Push(a, b, &edges_);
  }

  int num_clusters() const { return num_clusters_; }

  void CollapseTo(int target) {
    CHECK_GE(target, 1);
    while (num_clusters_ > target) {
      int a, b;
      if (!out_of_edges_) {
        if (PopValid(&edges_, &a, &b)) {
          Merge(a, b);
          continue;
        }
        out_of_edges_ = true;
        for (int j = 0; j < static_cast<int>(parent_.size()); ++j) {
          if (parent_[j] == j) roots_.push_back(j);
        }
        for (size_t i = 0; i < roots_.size(); ++i) {
          for (size_t l = i + 1; l < roots_.size(); ++l) Push(roots_[i], roots_[l], &pairs_);
        }
      }
      CHECK(PopValid(&pairs_, &a, &b));
      Merge(a, b);
    }
  }

  // The current clusters as a graph without weights or edges; nodes numbered
  // by their smallest DG1 member.
  DeformationGraph Snapshot() {
    const int num_dg1 = static_cast<int>(parent_.size());
    DeformationGraph graph;
    graph.node_of_dg1.resize(num_dg1);
    std::vector<int> label(num_dg1, -1), root_of_label;
    root_of_label.reserve(num_clusters_);
    for (int i = 0; i < num_dg1; ++i) {
      const int root = Find(i);
      if (label[root] < 0) {
        label[root] = static_cast<int>(root_of_label.size());
        root_of_label.push_back(root);
      }
      graph.node_of_dg1[i] = label[root];
    }
    const int num_nodes = static_cast<int>(root_of_label.size());
    graph.positions.resize(3, num_nodes);
    graph.node_vertex.resize(num_nodes);
    graph.members.offsets.assign(num_nodes + 1, 0);
    for (int j = 0; j < num_nodes; ++j) {
      const int root = root_of_label[j];
      graph.positions.col(j) = position_.col(root);
      graph.node_vertex[j] = vertex_[root];
      graph.members.offsets[j + 1] =
          graph.members.offsets[j] + static_cast<int>(members_[root].size());
    }
    graph.members.values.resize(num_dg1);
    std::vector<int> fill(graph.members.offsets.begin(), graph.members.offsets.end() - 1);
    for (int i = 0; i < num_dg1; ++i) graph.members.values[fill[graph.node_of_dg1[i]]++] = i;
    return graph;
  }

 private:
  struct Entry {
    double squared_length;
    int a, b;  // a < b
    int stamp_a, stamp_b;
    bool operator>(const Entry& other) const {
      return std::tie(squared_length, a, b) > std::tie(other.squared_length, other.a, other.b);
    }
  };
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>>;

  int Find(int j) {
    while (parent_[j] != j) {
      parent_[j] = parent_[parent_[j]];
      j = parent_[j];
    }
    return j;
  }

  void Push(int a, int b, Queue* queue) {
    if (a > b) std::swap(a, b);
    queue->push({(position_.col(a) - position_.col(b)).squaredNorm(), a, b, stamp_[a], stamp_[b]});
  }

  bool PopValid(Queue* queue, int* a, int* b) {
    while (!queue->empty()) {
      const Entry entry = queue->top();
      queue->pop();
      if (parent_[entry.a] == entry.a && parent_[entry.b] == entry.b &&
          stamp_[entry.a] == entry.stamp_a && stamp_[entry.b] == entry.stamp_b) {
        *a = entry.a;
        *b = entry.b;
        return true;
      }
    }
    return false;
  }

  void Merge(int a, int b) {
    const int keep = members_[a].size() >= members_[b].size() ? a : b;
    const int gone = keep == a ? b : a;
    parent_[gone] = keep;
    ++stamp_[keep];
    ++stamp_[gone];
    --num_clusters_;
    members_[keep].insert(members_[keep].end(), members_[gone].begin(), members_[gone].end());
    std::vector<int>().swap(members_[gone]);
    sum_.col(keep) += sum_.col(gone);

    // Placed on the member node vertex nearest the members' centroid.
    const Eigen::Vector3d centroid = sum_.col(keep) / static_cast<double>(members_[keep].size());
    int best = -1;
    double best_distance = 0.0;
    for (const int member : members_[keep]) {
      const double distance = (dg1_positions_.col(member) - centroid).squaredNorm();
      if (best < 0 || distance < best_distance || (distance == best_distance && member < best)) {
        best = member;
        best_distance = distance;
      }
    }
    position_.col(keep) = dg1_positions_.col(best);
    vertex_[keep] = dg1_vertex_[best];

    std::vector<int> adjacency;
    adjacency.reserve(adjacency_[keep].size() + adjacency_[gone].size());
    for (const int side : {keep, gone}) {
      for (const int x : adjacency_[side]) {
        const int root = Find(x);
        if (root != keep) adjacency.push_back(root);
      }
      std::vector<int>().swap(adjacency_[side]);
    }
    std::sort(adjacency.begin(), adjacency.end());
    adjacency.erase(std::unique(adjacency.begin(), adjacency.end()), adjacency.end());
    adjacency_[keep] = std::move(adjacency);

    if (!out_of_edges_) {
      for (const int x : adjacency_[keep]) Push(keep, x, &edges_);
    } else {
      CHECK(adjacency_[keep].empty());
      roots_.erase(std::find(roots_.begin(), roots_.end(), gone));
      for (const int x : roots_) {
        if (x != keep) Push(keep, x, &pairs_);
      }
    }
  }

  const Eigen::Matrix3Xd dg1_positions_;
  const std::vector<int> dg1_vertex_;
  std::vector<int> parent_;  // Union-find over DG1 ids; a cluster is named by its root.
  std::vector<int> stamp_;   // Bumped whenever a cluster changes.
  std::vector<std::vector<int>> members_;
  std::vector<std::vector<int>> adjacency_;  // May hold stale (merged) ids.
  Eigen::Matrix3Xd sum_;       // Sum of member DG1 positions, per root.
  Eigen::Matrix3Xd position_;  // Node position, per root.
  std::vector<int> vertex_;    // Node vertex, per root.
  int num_clusters_;
  Queue edges_;
  bool out_of_edges_ = false;
  std::vector<int> roots_;  // Current clusters, once out of edges.
  Queue pairs_;             // All cluster pairs, once out of edges.
};

}  // namespace

NearestNodeOptions GraphOptions::nearest_nodes() const {
  NearestNodeOptions nearest;
  nearest.k = k;
  nearest.extra_rings = extra_rings;
  nearest.num_threads = num_threads;
  return nearest;
}

bool GraphOptions::Check(std::string* error) const {
  if (nodes_per_scale < 1) {
    *error = "nodes_per_scale (P) must be >= 1, got " + std::to_string(nodes_per_scale);
    return false;
  }
  return nearest_nodes().Check(error);
}

NodeTransforms NodeTransforms::Identity(int num_nodes) {
  CHECK_GE(num_nodes, 0);
  NodeTransforms transforms;
  transforms.rotations.resize(9, num_nodes);
  for (int j = 0; j < num_nodes; ++j) {
    transforms.rotations.col(j) << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  }
  transforms.translations.setZero(3, num_nodes);
  return transforms;
}

int NumScales(int num_dg1_nodes, int nodes_per_scale) {
  CHECK_GE(num_dg1_nodes, 0);
  CHECK_GE(nodes_per_scale, 1);
  return std::max(1, num_dg1_nodes / nodes_per_scale);
}

int NodesAtScale(int num_dg1_nodes, int scale) {
  CHECK_GE(num_dg1_nodes, 0);
  CHECK_GE(scale, 1);
  return static_cast<int>((2 * static_cast<int64_t>(num_dg1_nodes) + scale) /
                          (2 * static_cast<int64_t>(scale)));
}

bool BuildMultiScaleGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                           std::vector<DeformationGraph>* graphs, std::string* error,
                           Connect connect) {
  if (!options.Check(error)) return false;
  const int num_dg1 = lattice.num_surface_cells();
  const int num_scales = NumScales(num_dg1, options.nodes_per_scale);
  std::vector<int> node_counts;
  for (int i = 2; i <= num_scales; ++i) node_counts.push_back(NodesAtScale(num_dg1, i));
  return BuildCollapsedGraphs(mesh, lattice, options, node_counts, graphs, error, connect);
}

bool BuildCollapsedGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                          const std::vector<int>& node_counts,
                          std::vector<DeformationGraph>* graphs, std::string* error,
                          Connect connect) {
  CHECK(graphs != nullptr);
  if (!options.Check(error)) return false;
  CHECK_EQ(static_cast<int>(lattice.cell_of_vertex().size()), mesh.num_vertices())
      << "the lattice was built from another mesh";
  const int num_dg1 = lattice.num_surface_cells();
  for (size_t i = 0; i < node_counts.size(); ++i) {
    const int previous = i == 0 ? num_dg1 : node_counts[i - 1];
    if (node_counts[i] < 1 || node_counts[i] > previous) {
      std::ostringstream message;
      message << "node count " << i << " is " << node_counts[i]
              << "; node counts must be non-increasing and in [1, D1 = " << num_dg1 << "]";
      *error = message.str();
      return false;
    }
  }

  graphs->clear();
  graphs->reserve(node_counts.size() + 1);
  graphs->push_back(MakeFinestGraph(mesh, lattice, options.seed));
  ConnectGraph(mesh, lattice, options, &graphs->front());
  EdgeCollapse collapse(graphs->front());
  for (const int count : node_counts) {
    collapse.CollapseTo(count);
    graphs->push_back(collapse.Snapshot());
  }
  if (connect == Connect::kFinestOnly) return true;
  // The coarse scales are independent: with enough of them, one thread per
  // scale also shares out the serial parts (candidate search, edge lists).
  const int num_coarse = static_cast<int>(graphs->size()) - 1;
  const int num_threads = options.num_threads > 0 ? options.num_threads : omp_get_max_threads();
  if (num_threads > 1 && num_coarse >= 2 * num_threads) {
    GraphOptions one_thread = options;
    one_thread.num_threads = 1;
#pragma omp parallel for num_threads(num_threads) schedule(dynamic, 1)
    for (int i = 1; i <= num_coarse; ++i) ConnectGraph(mesh, lattice, one_thread, &(*graphs)[i]);
  } else {
    for (int i = 1; i <= num_coarse; ++i) ConnectGraph(mesh, lattice, options, &(*graphs)[i]);
  }
  return true;
}

}  // namespace msdeform
