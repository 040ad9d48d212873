// The edge collapse of the coarse deformation graphs (core/edge_collapse.h),
// on scans in many pieces: there the collapse runs out of edges and merges
// the nearest clusters.

#include "msdeform/core/edge_collapse.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/deformation_graph.h"
#include "tests/core/lattice_test_util.h"

namespace msdeform {
namespace {

// `count` separate triangles of legs 0.1, one near each point of an integer
// grid, moved from it by up to 0.35 per axis (seeded; the first by none, so
// that the lattice of width 1 has its cells centred on the grid points):
// each triangle is a mesh component in one cell.
Mesh SeparateTriangles(int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> inside(0.0, 0.35);
  const int side = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(count))));
  Mesh mesh;
  mesh.vertices.resize(3, 3 * count);
  mesh.faces.resize(3, count);
  for (int t = 0; t < count; ++t) {
    const Eigen::Vector3d corner(t % side, (t / side) % side, t / (side * side));
    Eigen::Vector3d p = corner + Eigen::Vector3d(inside(rng), inside(rng), inside(rng));
    if (t == 0) p.setZero();
    mesh.vertices.col(3 * t) = p;
    mesh.vertices.col(3 * t + 1) = p + Eigen::Vector3d(0.1, 0.0, 0.0);
    mesh.vertices.col(3 * t + 2) = p + Eigen::Vector3d(0.0, 0.1, 0.0);
    mesh.faces.col(t) << 3 * t, 3 * t + 1, 3 * t + 2;
  }
  return mesh;
}

DeformationGraph Dg1(const Mesh& mesh, const Lattice& lattice) {
  std::vector<DeformationGraph> graphs;
  std::string error;
  EXPECT_TRUE(BuildCollapsedGraphs(mesh, lattice, GraphOptions(), {}, &graphs, &error,
                                   Connect::kFinestOnly))
      << error;
  return graphs.front();
}

// Queueing every pair of clusters held D1 (D1 - 1) / 2 entries once the
// edges ran out (about 2 million here); each cluster's nearest cluster is one
// entry per cluster, plus one per merge and per changed nearest cluster.
TEST(EdgeCollapseTest, ThousandsOfPiecesQueueEntriesLinearInTheNodes) {
  for (const int count : {500, 2000}) {
    SCOPED_TRACE(std::to_string(count) + " triangles");
    const Mesh mesh = SeparateTriangles(count, 7);
    const Lattice lattice = BuildTestLattice(mesh, 1.0);
    const DeformationGraph dg1 = Dg1(mesh, lattice);
    ASSERT_EQ(dg1.num_nodes(), count);  // one node per triangle: no edge at all
    ASSERT_TRUE(dg1.edges.empty());
    EdgeCollapse collapse(dg1);
    collapse.CollapseTo(1);
    EXPECT_EQ(collapse.num_clusters(), 1);
    EXPECT_GE(collapse.peak_queued(), count);
    EXPECT_LE(collapse.peak_queued(), 4 * static_cast<int64_t>(count));
  }
}

// The graphs of 2000 pieces: every scale has its D_i nodes, whose members
// partition DG1 and hold the vertex the node sits on, and skins every vertex.
TEST(EdgeCollapseTest, ThousandsOfPiecesGiveValidGraphs) {
  const Mesh mesh = SeparateTriangles(2000, 7);
  const Lattice lattice = BuildTestLattice(mesh, 1.0);
  std::vector<DeformationGraph> graphs;
  std::string error;
  ASSERT_TRUE(BuildMultiScaleGraphs(mesh, lattice, GraphOptions(), &graphs, &error)) << error;
  ASSERT_EQ(graphs.size(), 20u);  // N = floor(2000 / P), P = 100
  for (int i = 1; i <= 20; ++i) {
    const DeformationGraph& graph = graphs[i - 1];
    ASSERT_EQ(graph.num_nodes(), NodesAtScale(2000, i));
    std::vector<int> seen(2000, 0);
    for (int j = 0; j < graph.num_nodes(); ++j) {
      bool on_member = false;
      for (const int* m = graph.members.begin(j); m != graph.members.end(j); ++m) {
        ++seen[*m];
        EXPECT_EQ(graph.node_of_dg1[*m], j);
        on_member |= graphs[0].node_vertex[*m] == graph.node_vertex[j];
      }
      EXPECT_TRUE(on_member) << "scale " << i << " node " << j;
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 2000) << "scale " << i;
    EXPECT_EQ(graph.weights.num_vertices(), mesh.num_vertices());
  }
}

// Known answer: once out of edges, each merge joins the two nodes nearest
// each other (the squared distance of the finer snapshot's positions).
TEST(EdgeCollapseTest, PiecesMergeNearestNodesFirst) {
  const Mesh mesh = SeparateTriangles(150, 11);
  const Lattice lattice = BuildTestLattice(mesh, 1.0);
  const DeformationGraph dg1 = Dg1(mesh, lattice);
  ASSERT_EQ(dg1.num_nodes(), 150);
  EdgeCollapse collapse(dg1);
  DeformationGraph finer = collapse.Snapshot();
  for (int count = 149; count >= 1; --count) {
    collapse.CollapseTo(count);
    const DeformationGraph coarser = collapse.Snapshot();
    ASSERT_EQ(coarser.num_nodes(), count);
    // The two finer nodes that fall in one coarser node.
    std::vector<int> first_of(count, -1);
    std::pair<int, int> merged(-1, -1);
    for (int j = 0; j < finer.num_nodes(); ++j) {
      const int to = coarser.node_of_dg1[*finer.members.begin(j)];
      if (first_of[to] < 0) {
        first_of[to] = j;
      } else {
        ASSERT_EQ(merged.first, -1) << "more than one merge from " << count + 1;
        merged = {first_of[to], j};
      }
    }
    ASSERT_GE(merged.first, 0);
    double nearest = std::numeric_limits<double>::infinity();
    for (int i = 0; i < finer.num_nodes(); ++i) {
      for (int j = i + 1; j < finer.num_nodes(); ++j) {
        nearest = std::min(nearest, (finer.positions.col(i) - finer.positions.col(j)).squaredNorm());
      }
    }
    EXPECT_EQ((finer.positions.col(merged.first) - finer.positions.col(merged.second)).squaredNorm(),
              nearest)
        << count + 1 << " to " << count << " nodes";
    finer = coarser;
  }
}

}  // namespace
}  // namespace msdeform
