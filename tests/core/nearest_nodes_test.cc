#include "msdeform/core/nearest_nodes.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/deformation_graph.h"
#include "msdeform/core/procedural_meshes.h"
#include "tests/core/lattice_test_util.h"

namespace msdeform {
namespace {

using Edges = std::vector<std::pair<int, int>>;

// The ring search done literally, one cell at a time: whole rings of
// L-neighbours until min_count distinct nodes, then extra_rings more rings.
std::vector<int> RingSearch(const Lattice& lattice, const std::vector<int>& node_of_cell, int cell,
                            int min_count, int extra_rings) {
  const CompressedLists& l = lattice.neighborhood();
  std::set<int> visited = {cell};
  std::set<int> nodes = {node_of_cell[cell]};
  std::vector<int> ring = {cell};
  int last_ring = static_cast<int>(nodes.size()) >= min_count ? extra_rings : -1;
  for (int r = 1; !ring.empty() && (last_ring < 0 || r <= last_ring); ++r) {
    std::vector<int> next;
    for (int c : ring) {
      for (const int* n = l.begin(c); n != l.end(c); ++n) {
        if (visited.insert(*n).second) {
          next.push_back(*n);
          nodes.insert(node_of_cell[*n]);
        }
      }
    }
    ring = std::move(next);
    if (last_ring < 0 && static_cast<int>(nodes.size()) >= min_count) last_ring = r + extra_rings;
  }
  return std::vector<int>(nodes.begin(), nodes.end());
}

void ExpectSameAsRingSearch(const Lattice& lattice, const std::vector<int>& node_of_cell,
                            int num_nodes, int min_count, int extra_rings) {
  const CompressedLists candidates =
      CandidateNodesOfCells(lattice, node_of_cell, num_nodes, min_count, extra_rings);
  ASSERT_EQ(candidates.num_rows(), lattice.num_surface_particles());
  for (int c = 0; c < lattice.num_surface_particles(); ++c) {
    const std::vector<int> expected = RingSearch(lattice, node_of_cell, c, min_count, extra_rings);
    const std::vector<int> actual(candidates.begin(c), candidates.end(c));
    ASSERT_EQ(actual, expected) << "cell " << c << " min_count " << min_count << " extra "
                                << extra_rings << " nodes " << num_nodes;
  }
}

TEST(NearestNodesTest, PropagationEqualsPerCellRingSearch) {
  const Mesh comb = MakeComb(4, 5, 1.0, 4);
  const Lattice lattice = BuildTestLattice(comb, 0.45);
  const int num_cells = lattice.num_surface_particles();
  std::vector<int> identity(num_cells);
  for (int c = 0; c < num_cells; ++c) identity[c] = c;

  // Coarse node maps as the multi-scale graphs make them.
  GraphOptions options;
  options.nodes_per_scale = 10;
  std::vector<DeformationGraph> graphs;
  std::string error;
  ASSERT_TRUE(BuildMultiScaleGraphs(comb, lattice, options, &graphs, &error)) << error;
  ASSERT_GT(graphs.size(), 4u);

  // A scattered map: nodes made of cells all over the mesh.
  std::mt19937 rng(7);
  std::vector<int> scattered(num_cells);
  for (int& node : scattered) node = static_cast<int>(rng() % 13);

  for (int extra = 0; extra <= 2; ++extra) {
    for (int min_count : {1, 3, 5, 8}) {
      ExpectSameAsRingSearch(lattice, identity, num_cells, min_count, extra);
      ExpectSameAsRingSearch(lattice, scattered, 13, min_count, extra);
      for (size_t i = 1; i < graphs.size(); i += 3) {
        ExpectSameAsRingSearch(lattice, graphs[i].node_of_dg1, graphs[i].num_nodes(), min_count,
                               extra);
      }
    }
  }
}

TEST(NearestNodesTest, WeightsFollowEq11OverTheRingCandidates) {
  const Mesh sphere = MakeSphere(1.0, 48, 24);
  const Lattice lattice = BuildTestLattice(sphere, 0.15);
  const int num_cells = lattice.num_surface_particles();
  // Nodes on the first vertex of each cell.
  Eigen::Matrix3Xd positions(3, num_cells);
  std::vector<int> node_of_cell(num_cells);
  for (int c = 0; c < num_cells; ++c) {
    positions.col(c) = sphere.vertices.col(*lattice.vertices_of_particle().begin(c));
    node_of_cell[c] = c;
  }
  NearestNodeOptions options;
  SkinningWeights weights;
  std::vector<std::pair<int, int>> edges;
  ComputeNearestNodes(sphere.vertices, lattice, positions, node_of_cell, options, &weights, &edges);
  ASSERT_EQ(weights.k(), 4);
  ASSERT_EQ(weights.num_vertices(), sphere.num_vertices());
  EXPECT_TRUE(weights.has_16bit_ids());

  std::set<std::pair<int, int>> expected_edges;
  for (int v = 0; v < sphere.num_vertices(); ++v) {
    const std::vector<int> candidates =
        RingSearch(lattice, node_of_cell, lattice.particle_of_vertex(v), 5, options.extra_rings);
    ASSERT_GE(candidates.size(), 5u);
    std::vector<std::pair<double, int>> ranked;
    for (int node : candidates) {
      ranked.emplace_back((sphere.vertices.col(v) - positions.col(node)).squaredNorm(), node);
    }
    // Ranked by distance, ties by node id (the sphere has exact ties).
    std::sort(ranked.begin(), ranked.end());
    for (auto& entry : ranked) entry.first = std::sqrt(entry.first);
    const double d_max = ranked[4].first;
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) sum += std::pow(1.0 - ranked[i].first / d_max, 2);
    // The stored weights sum to exactly 1.
    EXPECT_EQ(((weights.weight(0, v) + weights.weight(1, v)) + weights.weight(2, v)) +
                  weights.weight(3, v),
              1.0)
        << "vertex " << v;
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(weights.node(i, v), ranked[i].second) << "vertex " << v << " slot " << i;
      // Stored on the 2^-24 grid, within (k + 1) 2^-25 of Eq. 11 (nearest_nodes.h).
      const double eq11 = std::pow(1.0 - ranked[i].first / d_max, 2) / sum;
      EXPECT_NEAR(weights.weight(i, v), eq11, 5.0 * std::ldexp(1.0, -25));
      EXPECT_EQ(std::ldexp(weights.weight(i, v), 24), std::round(std::ldexp(weights.weight(i, v), 24)))
          << "on the 2^-24 grid";
      for (int j = i + 1; j < 4; ++j) {
        expected_edges.emplace(std::min(ranked[i].second, ranked[j].second),
                               std::max(ranked[i].second, ranked[j].second));
      }
    }
  }
  EXPECT_EQ(edges, Edges(expected_edges.begin(), expected_edges.end()));
}

// 8K vertices: several of the parallel loop's 1,024-vertex chunks for each
// of 2 and 3 threads. DG1-like (a node per cell) and coarse (a node per 7
// cells, as a selected scale) node sets.
TEST(NearestNodesTest, ResultDoesNotDependOnThreadCount) {
  const Mesh sphere = MakeSphere(1.0, 128, 64);
  ASSERT_GT(sphere.num_vertices(), 6 * 1024);
  const Lattice lattice = BuildTestLattice(sphere, 0.1);
  const int num_cells = lattice.num_surface_particles();
  for (const int cells_per_node : {1, 7}) {
    const int num_nodes = (num_cells + cells_per_node - 1) / cells_per_node;
    Eigen::Matrix3Xd positions(3, num_nodes);
    std::vector<int> node_of_cell(num_cells);
    for (int c = 0; c < num_cells; ++c) {
      node_of_cell[c] = c / cells_per_node;
      positions.col(node_of_cell[c]) = lattice.rest_positions().col(c);
    }
    SkinningWeights one;
    Edges edges_one;
    NearestNodeOptions options;
    options.num_threads = 1;
    ComputeNearestNodes(sphere.vertices, lattice, positions, node_of_cell, options, &one,
                        &edges_one);
    ASSERT_FALSE(edges_one.empty());
    for (const int threads : {2, 3}) {
      SkinningWeights many;
      Edges edges_many;
      options.num_threads = threads;
      ComputeNearestNodes(sphere.vertices, lattice, positions, node_of_cell, options, &many,
                          &edges_many);
      // Bit for bit: operator== compares the float weights and the ids exactly.
      EXPECT_TRUE(one == many) << threads << " threads, " << cells_per_node << " cells per node";
      EXPECT_EQ(edges_one, edges_many) << threads << " threads";
    }
  }
}

TEST(NearestNodesTest, VertexWithFewerThanKPlusOneCandidatesGetsValidWeights) {
  // A single triangle whose vertices lie in three cells: 3 candidate nodes < k + 1.
  Mesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0.0, 2.0, 0.0,  //
      0.0, 0.0, 2.0,                   //
      0.0, 0.0, 0.0;
  triangle.faces.resize(3, 1);
  triangle.faces << 0, 1, 2;
  const Lattice lattice = BuildTestLattice(triangle, 1.0);
  ASSERT_EQ(lattice.num_surface_particles(), 3);
  // Node c sits on the vertex of cell c; node 0 is moved off its vertex.
  Eigen::Matrix3Xd positions(3, 3);
  std::vector<int> node_of_cell = {0, 1, 2};
  for (int c = 0; c < 3; ++c) {
    positions.col(c) = triangle.vertices.col(*lattice.vertices_of_particle().begin(c));
  }
  positions.col(0) = triangle.vertices.col(*lattice.vertices_of_particle().begin(0)) +
                     Eigen::Vector3d(0.1, 0.1, 0.0);
  SkinningWeights weights;
  std::vector<std::pair<int, int>> edges;
  ComputeNearestNodes(triangle.vertices, lattice, positions, node_of_cell, NearestNodeOptions(),
                      &weights, &edges);
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(weights.weight(0, v) + weights.weight(1, v) + weights.weight(2, v), 1.0);
    EXPECT_EQ(weights.weight(3, v), 0.0) << "unused slot";
    EXPECT_EQ(weights.node(3, v), weights.node(0, v)) << "unused slot holds the nearest node";
    // All three candidates carry weight (d_max = twice the farthest distance).
    EXPECT_GT(weights.weight(2, v), 0.0);
    EXPECT_GT(weights.weight(0, v), weights.weight(2, v));
  }
  EXPECT_EQ(edges, (Edges{{0, 1}, {0, 2}, {1, 2}}));
}

TEST(NearestNodesTest, SingleNodeComponentFallsBackToWeightOne) {
  // A small triangle inside one cell: one candidate at distance 0 for its node vertex.
  Mesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0.0, 0.1, 0.0,  //
      0.0, 0.0, 0.1,                   //
      0.0, 0.0, 0.0;
  triangle.faces.resize(3, 1);
  triangle.faces << 0, 1, 2;
  const Lattice lattice = BuildTestLattice(triangle, 1.0);
  ASSERT_EQ(lattice.num_surface_particles(), 1);
  Eigen::Matrix3Xd positions = triangle.vertices.col(0);
  SkinningWeights weights;
  std::vector<std::pair<int, int>> edges;
  ComputeNearestNodes(triangle.vertices, lattice, positions, {0}, NearestNodeOptions(), &weights,
                      &edges);
  for (int v = 0; v < 3; ++v) {
    EXPECT_EQ(weights.weight(0, v), 1.0) << v;
    for (int slot = 0; slot < 4; ++slot) {
      EXPECT_EQ(weights.node(slot, v), 0) << v;
      if (slot > 0) {
        EXPECT_EQ(weights.weight(slot, v), 0.0) << v;
      }
    }
  }
  EXPECT_TRUE(edges.empty());
}

TEST(SkinningWeightsTest, StoresWeightsOnTheGridSummingToExactlyOne) {
  SkinningWeights weights(4, 3, 10);
  ASSERT_TRUE(weights.has_16bit_ids());
  const int nodes[3][4] = {{7, 2, 9, 0}, {3, 3, 3, 3}, {1, 4, 5, 6}};
  // Thirds do not round to the grid; 1/2, 1/4 and 1/8 do; the last sums to
  // 1 - 2^-60 in doubles, as a normalised sum can.
  const double third = 1.0 / 3.0;
  const double values[3][4] = {{third, third, third, 0.0},
                               {1.0, 0.0, 0.0, 0.0},
                               {0.5, 0.25, 0.125, 0.125 - std::ldexp(1.0, -60)}};
  for (int v = 0; v < 3; ++v) weights.SetVertex(v, nodes[v], values[v]);
  const double grid = std::ldexp(1.0, -24);
  // 1/3 rounds to 5592405 grid steps (2^24 / 3 = 5592405.33); the remainder
  // of the sum, one step, goes to the first of the largest.
  EXPECT_EQ(weights.weight(0, 0), 5592406 * grid);
  EXPECT_EQ(weights.weight(1, 0), 5592405 * grid);
  EXPECT_EQ(weights.weight(2, 0), 5592405 * grid);
  EXPECT_EQ(weights.weight(3, 0), 0.0);
  EXPECT_EQ(weights.weight(0, 1), 1.0);
  for (int slot = 1; slot < 4; ++slot) EXPECT_EQ(weights.weight(slot, 1), 0.0);
  EXPECT_EQ(weights.weight(0, 2), 0.5);
  EXPECT_EQ(weights.weight(1, 2), 0.25);
  EXPECT_EQ(weights.weight(2, 2), 0.125);
  EXPECT_EQ(weights.weight(3, 2), 0.125);
  for (int v = 0; v < 3; ++v) {
    double sum = 0.0;
    for (int slot = 0; slot < 4; ++slot) {
      EXPECT_EQ(weights.node(slot, v), nodes[v][slot]);
      sum += weights.weight(slot, v);
    }
    EXPECT_EQ(sum, 1.0) << "vertex " << v;
  }
}

TEST(SkinningWeightsTest, LargeGraphsGet32BitIds) {
  SkinningWeights small(2, 1, kMaxNodesFor16BitIds);
  SkinningWeights large(2, 1, kMaxNodesFor16BitIds + 1);
  EXPECT_TRUE(small.has_16bit_ids());
  EXPECT_NE(small.ids16(), nullptr);
  EXPECT_EQ(small.ids32(), nullptr);
  EXPECT_FALSE(large.has_16bit_ids());
  EXPECT_EQ(large.ids16(), nullptr);
  EXPECT_NE(large.ids32(), nullptr);
  const int small_nodes[2] = {kMaxNodesFor16BitIds - 1, 0};
  const int large_nodes[2] = {kMaxNodesFor16BitIds, 70000};
  const double values[2] = {0.75, 0.25};
  small.SetVertex(0, small_nodes, values);
  large.SetVertex(0, large_nodes, values);
  EXPECT_EQ(small.node(0, 0), kMaxNodesFor16BitIds - 1);
  EXPECT_EQ(large.node(0, 0), kMaxNodesFor16BitIds);
  EXPECT_EQ(large.node(1, 0), 70000);
}

TEST(NearestNodesTest, OptionsCheck) {
  NearestNodeOptions options;
  std::string error;
  EXPECT_TRUE(options.Check(&error));
  options.k = SkinningWeights::kMaxK;
  EXPECT_TRUE(options.Check(&error));
  for (int k : {0, SkinningWeights::kMaxK + 1}) {
    options.k = k;
    EXPECT_FALSE(options.Check(&error));
    EXPECT_EQ(error, "k (nearest nodes per vertex) must be in [1, 64], got " + std::to_string(k));
  }
  options = NearestNodeOptions();
  options.extra_rings = -1;
  EXPECT_FALSE(options.Check(&error));
  options = NearestNodeOptions();
  options.num_threads = kMaxThreads;
  EXPECT_TRUE(options.Check(&error));
  // 100000 threads crashed inside libgomp.
  for (int threads : {-1, kMaxThreads + 1, 100000}) {
    options.num_threads = threads;
    EXPECT_FALSE(options.Check(&error));
    EXPECT_EQ(error, "num_threads must be in 0..1024 (0: OpenMP default), got " +
                         std::to_string(threads));
  }
}

}  // namespace
}  // namespace msdeform
