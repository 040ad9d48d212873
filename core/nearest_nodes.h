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
// whatever the node size (see docs/decisions.md).

#ifndef MSDEFORM_CORE_NEAREST_NODES_H_
#define MSDEFORM_CORE_NEAREST_NODES_H_

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/lattice.h"

namespace msdeform {

// The k nearest nodes of every vertex and their weights. Column v belongs to
// vertex v; rows are ordered nearest first. A vertex with fewer than k
// candidates (a tiny mesh component) fills the unused rows with its nearest
// node and weight 0.
struct SkinningWeights {
  int k = 4;
  Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic> nodes;  // k by #V node ids.
  Eigen::MatrixXd weights;  // k by #V, >= 0, each column sums to 1.

  int num_vertices() const { return static_cast<int>(nodes.cols()); }
};

struct NearestNodeOptions {
  // Nearest nodes per vertex (paper: 4); the (k+1)-th gives d_max.
  int k = 4;
  // Rings searched beyond the first ring that reaches k + 1 distinct nodes.
  // 1 ranks a node just beyond that ring by its true distance (decisions.md).
  int extra_rings = 1;
  // OpenMP threads for the per-vertex work; 0 uses the OpenMP default.
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
