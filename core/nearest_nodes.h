// Nearest deformation-graph nodes of each mesh vertex, their skinning weights
// (paper §5.1, Eq. 11) and the graph edges they imply (docs/method.md §3).
//
// Candidates come through the surface-cell neighbourhood only, never from a
// global Euclidean search: starting from the vertex's cell, whole rings of
// L-neighbours are added (ring r = cells r L-hops away) until the cells seen
// map to at least k + 1 distinct nodes, then `extra_rings` more rings. The
// candidates are ranked by Euclidean distance; the k nearest get
//   w_j = (1 - |v - g_j| / d_max)^2,  d_max = distance of the (k+1)-th,
// normalised to sum 1. Two nodes are joined by an edge when both are among the
// k nearest nodes of some vertex (Sumner et al. 2007).
//
// The candidate set depends only on the cell, so it is found once per cell, by
// a layered multi-source propagation over the L graph that is exactly the
// per-cell ring search above but costs O(#cells x candidates x |L|) per scale,
// whatever the node size (see docs/decisions/graphs-and-skinning.md).

#ifndef MSDEFORM_CORE_NEAREST_NODES_H_
#define MSDEFORM_CORE_NEAREST_NODES_H_

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/lattice.h"
#include "msdeform/core/uninitialized_vector.h"

namespace msdeform {

struct NearestNodeOptions;

// The k nearest nodes of every vertex and their weights, stored compactly:
// skinning reads them for every moving vertex in every frame, so their bytes
// are a large part of its memory traffic (docs/decisions/millions-of-vertices.md, "Compact
// skinning data").
//
// - Node ids are 16-bit when the graph has at most 65,536 nodes (every graph
//   the default lattice makes) and 32-bit otherwise.
// - Weights are floats on the grid of multiples of 2^-24, rounded from the
//   double weights of Eq. 11 and then corrected on the nearest node so that
//   the k of a vertex sum to exactly 1 (an exact sum keeps a rigid motion of
//   every node exact under skinning). Each differs from the double weight by
//   at most (k + 1) 2^-25; a weight of 0 or 1 stays exactly 0 or 1.
//
// Slot s of vertex v is its s-th nearest node. A vertex with fewer than k
// candidates (a tiny mesh component) fills the unused slots with its nearest
// node and weight 0.
class SkinningWeights {
 public:
  SkinningWeights() = default;
  // The largest k.
  static constexpr int kMaxK = 64;

  // k slots for each of num_vertices vertices, over a graph of num_nodes
  // nodes (which picks the id width); every slot starts as node 0, weight 0.
  SkinningWeights(int k, int num_vertices, int num_nodes);

  int k() const { return k_; }
  int num_vertices() const { return num_vertices_; }
  // Whether node ids are stored in 16 bits (the graph has <= 65,536 nodes).
  bool has_16bit_ids() const { return has_16bit_ids_; }

  int node(int slot, int v) const {
    const size_t i = static_cast<size_t>(k_) * v + slot;
    return has_16bit_ids_ ? ids16_[i] : ids32_[i];
  }
  double weight(int slot, int v) const { return weights_[static_cast<size_t>(k_) * v + slot]; }

  // Sets the k slots of vertex v: nodes[s] and the double weights[s] (>= 0,
  // summing to 1 up to rounding), stored as described above. Calls for
  // different vertices may run in parallel.
  void SetVertex(int v, const int* nodes, const double* weights);

  // The stored arrays, k entries per vertex, vertex after vertex: the ids in
  // the width has_16bit_ids() says (the other pointer is nullptr) and the
  // weights.
  const uint16_t* ids16() const { return ids16_.empty() ? nullptr : ids16_.data(); }
  const int32_t* ids32() const { return ids32_.empty() ? nullptr : ids32_.data(); }
  const float* weights() const { return weights_.data(); }

  bool operator==(const SkinningWeights& other) const {
    return k_ == other.k_ && num_vertices_ == other.num_vertices_ &&
           has_16bit_ids_ == other.has_16bit_ids_ && ids16_ == other.ids16_ &&
           ids32_ == other.ids32_ && weights_ == other.weights_;
  }

 private:
  // Resized without a zero pass: ComputeNearestNodes sets every slot in its
  // parallel loop, so the pages are first touched there, by the threads that
  // fill them.
  template <typename T>
  using Storage = UninitializedVector<T>;

  struct Unset {};
  // k slots per vertex as above, left unset: the caller sets every vertex.
  SkinningWeights(int k, int num_vertices, int num_nodes, Unset);
  friend void ComputeNearestNodes(const Eigen::Matrix3Xd& vertices, const Lattice& lattice,
                                  const Eigen::Matrix3Xd& node_positions,
                                  const std::vector<int>& node_of_cell,
                                  const NearestNodeOptions& options, SkinningWeights* weights,
                                  std::vector<std::pair<int, int>>* edges);

  int k_ = 0;
  int num_vertices_ = 0;
  bool has_16bit_ids_ = true;
  Storage<uint16_t> ids16_;  // k by #V, when the graph has <= 65,536 nodes;
  Storage<int32_t> ids32_;   // otherwise these.
  Storage<float> weights_;   // k by #V.
};

// The most threads any option accepts (msdeform --threads has the same range).
// An OpenMP team of 100000 threads crashed inside libgomp; no machine this
// runs on has anywhere near 1024 cores.
constexpr int kMaxThreads = 1024;

// The largest graph whose node ids SkinningWeights stores in 16 bits.
constexpr int kMaxNodesFor16BitIds = 65536;

struct NearestNodeOptions {
  // Nearest nodes per vertex (paper: 4); the (k+1)-th gives d_max.
  int k = 4;
  // Rings searched beyond the first ring that reaches k + 1 distinct nodes.
  // 1 ranks a node just beyond that ring by its true distance
  // (docs/decisions/graphs-and-skinning.md).
  int extra_rings = 1;
  // OpenMP threads for the per-vertex work, 0..kMaxThreads; 0 uses the OpenMP
  // default.
  int num_threads = 0;

  bool Check(std::string* error) const;
};

// Candidate nodes of every surface cell, as described above: row c lists, in
// increasing node id, the nodes node_of_cell[c'] of the cells c' within the
// ring radius of cell c. `node_of_cell` has one entry per surface cell with
// values in [0, num_nodes). A cell whose L-connected part maps to fewer than
// min_count nodes gets all of them.
CompressedLists CandidateNodesOfCells(const Lattice& lattice, const std::vector<int>& node_of_cell,
                                      int num_nodes, int min_count, int extra_rings);

// Weights (Eq. 11) and edges for the nodes at `node_positions` (3 by #nodes),
// where surface cell c belongs to node node_of_cell[c]. `vertices` are the rest
// positions the lattice was built from (3 by #V). Edges are undirected (a < b)
// and sorted.
void ComputeNearestNodes(const Eigen::Matrix3Xd& vertices, const Lattice& lattice,
                         const Eigen::Matrix3Xd& node_positions,
                         const std::vector<int>& node_of_cell, const NearestNodeOptions& options,
                         SkinningWeights* weights, std::vector<std::pair<int, int>>* edges);

}  // namespace msdeform

#endif  // MSDEFORM_CORE_NEAREST_NODES_H_
