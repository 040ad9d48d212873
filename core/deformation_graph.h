// Deformation graphs at several scales (paper §3.2; docs/method.md §3).
//
// DG1 has one node per surface cell of the lattice, on a vertex of that cell
// chosen at random (seeded): DG1 node i is surface particle i. The coarser
// graphs DG_2 .. DG_N come from DG1 by edge collapse, shortest edge first, in
// one pass down to D_N nodes with a snapshot at each D_i:
//   N = max(1, floor(D1 / P)),   D_i = round(D1 / i) = floor(D1 / i + 1/2).
// Each DG_i node knows the DG1 nodes merged into it and sits on a mesh vertex
// (the member node vertex nearest the members' centroid). Edges never join two
// mesh components, so when no edge is left before D_i is reached the two
// nodes nearest each other are merged instead, keeping every D_i exact
// (core/edge_collapse.h: O(C log C) for C clusters). Every
// scale has its own nearest nodes, skinning weights (Eq. 11) and edges
// (core/nearest_nodes.h): its connection, which costs a pass over every mesh
// vertex and can be made when the scale is first used (ConnectGraph; the
// collapse needs only DG1's). Choices and timings: docs/decisions/graphs-and-skinning.md.
//
// A node j maps a point p to R_j (p - g_j) + g_j + t_j (Eq. 8); skinning with
// these transforms is in core/skinning.h.

#ifndef MSDEFORM_CORE_DEFORMATION_GRAPH_H_
#define MSDEFORM_CORE_DEFORMATION_GRAPH_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/nearest_nodes.h"
#include "msdeform/core/timing.h"
#include "msdeform/core/option_table.h"

namespace msdeform {

struct DeformationGraph {
  Eigen::Matrix3Xd positions;         // g_j, 3 by #nodes (rest positions).
  std::vector<int> node_vertex;       // Mesh vertex each node sits on; #nodes.
  CompressedLists members;            // DG1 node ids merged into node j, sorted (DG1: {j}).
  std::vector<int> node_of_dg1;       // DG1 node -> node of this graph; #DG1 nodes.
  std::vector<std::pair<int, int>> edges;  // Undirected (a < b), sorted.
  CompressedLists neighbors;          // Per node, sorted; the same edges both ways.
  SkinningWeights weights;            // k nearest nodes of every mesh vertex.

  int num_nodes() const { return static_cast<int>(positions.cols()); }
  // Whether edges, neighbors and weights are there (ConnectGraph); the node
  // fields above always are.
  bool is_connected() const { return weights.num_vertices() > 0; }
  // Drops edges, neighbors and weights (a cache's eviction); ConnectGraph
  // makes the same ones again.
  void Disconnect();
};

// Per-node transforms (R_j, t_j) of one graph, laid out so that Ceres parameter
// blocks can point straight into the columns: R_j is 9 doubles, column-major.
struct NodeTransforms {
  Eigen::Matrix<double, 9, Eigen::Dynamic> rotations;  // Column j = R_j, column-major.
  Eigen::Matrix3Xd translations;                        // Column j = t_j.

  static NodeTransforms Identity(int num_nodes);

  int num_nodes() const { return static_cast<int>(rotations.cols()); }
  Eigen::Map<Eigen::Matrix3d> rotation(int j) {
    return Eigen::Map<Eigen::Matrix3d>(rotations.col(j).data());
  }
  Eigen::Map<const Eigen::Matrix3d> rotation(int j) const {
    return Eigen::Map<const Eigen::Matrix3d>(rotations.col(j).data());
  }
};

struct GraphOptions {
  // Nearest nodes per vertex (paper: 4); the (k+1)-th gives d_max (Eq. 11).
  int k = 4;
  // P: nodes per scale step. N = max(1, floor(D1 / P)) scales (paper: 100).
  int nodes_per_scale = 100;
  // Seed of the random vertex chosen in each surface cell for DG1 (mt19937_64).
  uint64_t seed = 1;
  // Cell rings searched for candidates beyond the first ring that reaches
  // k + 1 distinct nodes (core/nearest_nodes.h, docs/decisions/graphs-and-skinning.md).
  int extra_rings = 1;
  // OpenMP threads for building; 0 uses the OpenMP default (the Deformer
  // passes its own num_threads instead).
  int num_threads = 0;

  // The nearest-node part of these options.
  NearestNodeOptions nearest_nodes() const;
  bool Check(std::string* error) const;
};

// N = max(1, floor(num_dg1_nodes / nodes_per_scale)).
int NumScales(int num_dg1_nodes, int nodes_per_scale);
// D_i = floor(num_dg1_nodes / i + 1/2) in exact integer arithmetic (scale i >= 1).
int NodesAtScale(int num_dg1_nodes, int scale);

// Which graphs the builders below connect (nearest nodes, weights, edges).
enum class Connect {
  kAll,         // every graph
  kFinestOnly,  // DG1 only; ConnectGraph connects the others when needed
};

// Builds DG1 .. DG_N of `mesh` over `lattice` (built from this mesh). Element
// i of *graphs is DG_{i+1}. Returns false with a message when the options are
// invalid.
bool BuildMultiScaleGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                           std::vector<DeformationGraph>* graphs, std::string* error,
                           Connect connect = Connect::kAll, StageTimes* times = nullptr);

// The same for an explicit list of node counts: DG1, then one graph per entry
// of `node_counts` (non-increasing, each in [1, D1]) by the same edge-collapse
// pass. Used for the static-graph ablation (e.g. 220 nodes, docs/method.md §7).
// Element 0 of *graphs is DG1, element i + 1 has node_counts[i] nodes.
bool BuildCollapsedGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                          const std::vector<int>& node_counts,
                          std::vector<DeformationGraph>* graphs, std::string* error,
                          Connect connect = Connect::kAll, StageTimes* times = nullptr);

// Nearest nodes, skinning weights, edges and neighbour lists of a graph whose
// nodes are placed (a graph of the builders above), the same whenever it is
// called. `options` as given to the builder (k, extra rings, threads).
void ConnectGraph(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                  DeformationGraph* graph);

// GraphOptions' rows (core/option_table.h), declared in its header beside the fields: a new field
// is the field above and its row here. GraphOptionTable() (deformation_graph.cc) builds the table
// from them once; a template, so that only that file compiles the rows.
template <typename Table>
void DeclareGraphOptionRows(Table& t) {
  using G = GraphOptions;
  t.Int("k", &G::k, "Nearest nodes per vertex (paper: 4).");
  t.Int("nodes_per_scale", &G::nodes_per_scale,
        "P: nodes per scale step, of the graph stack and of Eq. 6.")
      .Range(1, kOptionIntMax, "an integer >= 1");
  t.Int("seed", &G::seed, "Seed of the random vertex chosen in each surface cell for DG1.");
  t.Int("extra_rings", &G::extra_rings,
        "Cell rings searched beyond the first that reaches k + 1 nodes.");
  t.Int("num_threads", &G::num_threads,
        "OpenMP threads for building; 0 uses the OpenMP default.")
      .Range(0, kMaxThreads, "an integer in 0..1024 (0: OpenMP default)");
}
const OptionTable<GraphOptions>& GraphOptionTable();

}  // namespace msdeform

#endif  // MSDEFORM_CORE_DEFORMATION_GRAPH_H_
