#include "msdeform/core/deformation_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glog/logging.h>
#include <gtest/gtest.h>

#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "tests/core/lattice_test_util.h"

namespace msdeform {
namespace {

using Edges = std::vector<std::pair<int, int>>;

std::vector<DeformationGraph> BuildGraphs(const Mesh& mesh, const Lattice& lattice,
                                          const GraphOptions& options) {
  std::vector<DeformationGraph> graphs;
  std::string error;
  EXPECT_TRUE(BuildMultiScaleGraphs(mesh, lattice, options, &graphs, &error)) << error;
  return graphs;
}

GraphOptions SmallP() {
  GraphOptions options;
  options.nodes_per_scale = 10;
  return options;
}

// `count` separate cubes of side 0.4 on a 3-unit grid: with cells of width 1
// each cube lies in one cell, so each is a one-node component.
Mesh Cubes(int count, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
  VoxelShape voxel(1, 1, 1);
  voxel.Set(0, 0, 0);
  const Mesh cube = MakeVoxelMesh(voxel, 0.4, 1);
  Mesh mesh;
  mesh.vertices.resize(3, count * cube.num_vertices());
  mesh.faces.resize(3, count * cube.num_faces());
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector3d shift = offset + Eigen::Vector3d(3.0 * (i % 6), 3.0 * (i / 6), 0.0);
    mesh.vertices.middleCols(i * cube.num_vertices(), cube.num_vertices()) =
        cube.vertices.colwise() + shift;
    mesh.faces.middleCols(i * cube.num_faces(), cube.num_faces()) =
        cube.faces.array() + i * cube.num_vertices();
  }
  return mesh;
}

Mesh Concatenate(const Mesh& a, const Mesh& b) {
  Mesh mesh;
  mesh.vertices.resize(3, a.num_vertices() + b.num_vertices());
  mesh.vertices << a.vertices, b.vertices;
  mesh.faces.resize(3, a.num_faces() + b.num_faces());
  mesh.faces << a.faces, (b.faces.array() + a.num_vertices()).matrix();
  return mesh;
}

// Every invariant of the layout in core/deformation_graph.h, at every scale.
void ExpectValidGraphs(const Mesh& mesh, const Lattice& lattice, const GraphOptions& options,
                       const std::vector<DeformationGraph>& graphs) {
  const int d1 = lattice.num_surface_particles();
  const int num_scales = std::max(1, d1 / options.nodes_per_scale);
  ASSERT_EQ(static_cast<int>(graphs.size()), num_scales) << "D1 = " << d1;
  for (int i = 1; i <= num_scales; ++i) {
    const DeformationGraph& graph = graphs[i - 1];
    SCOPED_TRACE("scale " + std::to_string(i));
    const int num_nodes = graph.num_nodes();
    ASSERT_EQ(num_nodes, static_cast<int>(std::lround(static_cast<double>(d1) / i)));
    ASSERT_EQ(static_cast<int>(graph.node_vertex.size()), num_nodes);
    ASSERT_EQ(graph.members.num_rows(), num_nodes);
    ASSERT_EQ(static_cast<int>(graph.node_of_dg1.size()), d1);

    // Members partition DG1 and agree with node_of_dg1; nodes sit on the
    // vertex of one of their DG1 members.
    std::vector<int> seen(d1, 0);
    for (int j = 0; j < num_nodes; ++j) {
      ASSERT_GT(graph.members.size(j), 0) << "node " << j;
      ASSERT_TRUE(std::is_sorted(graph.members.begin(j), graph.members.end(j)));
      bool on_member_vertex = false;
      for (const int* m = graph.members.begin(j); m != graph.members.end(j); ++m) {
        ASSERT_GE(*m, 0);
        ASSERT_LT(*m, d1);
        ++seen[*m];
        EXPECT_EQ(graph.node_of_dg1[*m], j);
        on_member_vertex |= graphs[0].node_vertex[*m] == graph.node_vertex[j];
      }
      EXPECT_TRUE(on_member_vertex) << "node " << j;
      EXPECT_EQ(graph.positions.col(j), mesh.vertices.col(graph.node_vertex[j]));
    }
    for (int m = 0; m < d1; ++m) ASSERT_EQ(seen[m], 1) << "DG1 node " << m;

    // One collapse pass: every node of a coarser scale is a union of nodes of
    // the finer scale.
    if (i > 1) {
      const DeformationGraph& finer = graphs[i - 2];
      std::vector<int> coarse_of_fine(finer.num_nodes(), -1);
      for (int m = 0; m < d1; ++m) {
        int& coarse = coarse_of_fine[finer.node_of_dg1[m]];
        if (coarse < 0) coarse = graph.node_of_dg1[m];
        ASSERT_EQ(coarse, graph.node_of_dg1[m]) << "DG1 node " << m;
      }
    }

    // Weights: k per vertex, valid ids, non-negative, summing to exactly one.
    const SkinningWeights& w = graph.weights;
    ASSERT_EQ(w.k(), options.k);
    ASSERT_EQ(w.num_vertices(), mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      double sum = 0.0;
      for (int slot = 0; slot < w.k(); ++slot) {
        ASSERT_GE(w.node(slot, v), 0);
        ASSERT_LT(w.node(slot, v), num_nodes);
        ASSERT_GE(w.weight(slot, v), 0.0);
        sum += w.weight(slot, v);
      }
      ASSERT_EQ(sum, 1.0) << "vertex " << v;
    }

    // Edges: sorted, a < b, exactly the pairs of distinct nodes that are both
    // among some vertex's nearest nodes; neighbour lists are the same edges.
    std::set<std::pair<int, int>> expected;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      for (int a = 0; a < w.k(); ++a) {
        for (int b = 0; b < w.k(); ++b) {
          const int na = w.node(a, v), nb = w.node(b, v);
          if (na < nb) expected.emplace(na, nb);
        }
      }
    }
    ASSERT_EQ(graph.edges, Edges(expected.begin(), expected.end()));
    ASSERT_EQ(graph.neighbors.num_rows(), num_nodes);
    std::set<std::pair<int, int>> from_neighbors;
    for (int j = 0; j < num_nodes; ++j) {
      ASSERT_TRUE(std::is_sorted(graph.neighbors.begin(j), graph.neighbors.end(j)));
      for (const int* n = graph.neighbors.begin(j); n != graph.neighbors.end(j); ++n) {
        from_neighbors.emplace(std::min(j, *n), std::max(j, *n));
      }
    }
    EXPECT_EQ(from_neighbors, expected);
    EXPECT_EQ(static_cast<int>(graph.neighbors.values.size()), 2 * static_cast<int>(expected.size()));
  }
}

TEST(DeformationGraphTest, ScaleCountsAndNodeCounts) {
  EXPECT_EQ(NumScales(0, 100), 1);
  EXPECT_EQ(NumScales(99, 100), 1);
  EXPECT_EQ(NumScales(200, 100), 2);
  EXPECT_EQ(NumScales(4321, 100), 43);
  EXPECT_EQ(NodesAtScale(5, 2), 3);  // 2.5 rounds up.
  EXPECT_EQ(NodesAtScale(7, 3), 2);  // 2.33
  EXPECT_EQ(NodesAtScale(8, 3), 3);  // 2.67
  EXPECT_EQ(NodesAtScale(4321, 43), 100);  // 100.49
  for (int d1 = 0; d1 < 500; ++d1) {
    for (int i = 1; i < 60; ++i) {
      ASSERT_EQ(NodesAtScale(d1, i), static_cast<int>(std::floor(d1 / static_cast<double>(i) + 0.5)))
          << d1 << " / " << i;
    }
  }
}

TEST(DeformationGraphTest, Dg1HasOneNodePerSurfaceCellOnASeededRandomVertex) {
  const Mesh sphere = MakeSphere(1.0, 64, 32);
  const Lattice lattice = BuildTestLattice(sphere, 0.1);
  GraphOptions options;
  options.nodes_per_scale = 1000000;  // DG1 only.
  const std::vector<DeformationGraph> graphs = BuildGraphs(sphere, lattice, options);
  ASSERT_EQ(graphs.size(), 1u);
  const DeformationGraph& dg1 = graphs[0];
  ASSERT_EQ(dg1.num_nodes(), lattice.num_surface_particles());
  int not_first_vertex = 0;
  for (int j = 0; j < dg1.num_nodes(); ++j) {
    EXPECT_EQ(lattice.particle_of_vertex(dg1.node_vertex[j]), j) << "node " << j;
    EXPECT_EQ(dg1.node_of_dg1[j], j);
    ASSERT_EQ(dg1.members.size(j), 1);
    EXPECT_EQ(*dg1.members.begin(j), j);
    not_first_vertex += dg1.node_vertex[j] != *lattice.vertices_of_particle().begin(j);
  }
  EXPECT_GT(not_first_vertex, 0) << "the vertex should be random, not the first of the cell";

  // Same seed, same graph; another seed, other vertices.
  EXPECT_EQ(BuildGraphs(sphere, lattice, options)[0].node_vertex, dg1.node_vertex);
  options.seed += 1;
  EXPECT_NE(BuildGraphs(sphere, lattice, options)[0].node_vertex, dg1.node_vertex);
}

TEST(DeformationGraphTest, ProceduralMeshesGiveExactNodeCountsAndValidGraphs) {
  struct Case {
    std::string name;
    Mesh mesh;
    double cell_width;
  };
  const std::vector<Case> cases = {
      {"sphere", MakeSphere(1.0, 48, 24), 0.15},
      {"bar", MakeBar(10, 1.0, 4), 0.3},
      {"comb", MakeComb(4, 5, 1.0, 4), 0.45},
      {"two bars", MakeTwoBars(8, 2, 1.0, 4), 0.4},
      {"tube", MakeOpenTube(1.0, 3.0, 48, 24), 0.2},
      {"cubes and a sphere", Concatenate(Cubes(30), [] {
         Mesh s = MakeSphere(2.0, 32, 16);
         s.vertices.colwise() += Eigen::Vector3d(7.0, 20.0, 0.0);
         return s;
       }()), 1.0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Lattice lattice = BuildTestLattice(c.mesh, c.cell_width);
    const GraphOptions options = SmallP();
    const std::vector<DeformationGraph> graphs = BuildGraphs(c.mesh, lattice, options);
    EXPECT_GE(graphs.size(), 4u) << "the case should have several scales";
    ExpectValidGraphs(c.mesh, lattice, options, graphs);
  }
}

// ConnectGraph of DG1 and of a coarse scale on 8K vertices (several chunks of
// the nearest-node loop per thread): the same weights, edges and neighbour
// lists bit for bit on 1, 2 and 3 threads, and the neighbour lists are the
// edges both ways, sorted.
TEST(DeformationGraphTest, ConnectGraphDoesNotDependOnThreadCount) {
  const Mesh sphere = MakeSphere(1.0, 128, 64);
  ASSERT_GT(sphere.num_vertices(), 6 * 1024);
  const Lattice lattice = BuildTestLattice(sphere, 0.1);
  GraphOptions options;
  const int num_dg1 = lattice.num_surface_particles();
  std::vector<DeformationGraph> graphs;
  std::string error;
  ASSERT_TRUE(BuildCollapsedGraphs(sphere, lattice, options, {num_dg1 / 8}, &graphs, &error,
                                   Connect::kFinestOnly))
      << error;
  for (DeformationGraph& graph : graphs) {
    std::vector<DeformationGraph> connected;
    for (const int threads : {1, 2, 3}) {
      options.num_threads = threads;
      graph.Disconnect();
      ConnectGraph(sphere, lattice, options, &graph);
      connected.push_back(graph);
    }
    const DeformationGraph& one = connected[0];
    std::vector<std::vector<int>> expected(one.num_nodes());
    for (const auto& [a, b] : one.edges) {
      expected[a].push_back(b);
      expected[b].push_back(a);
    }
    for (int j = 0; j < one.num_nodes(); ++j) {
      std::sort(expected[j].begin(), expected[j].end());
      EXPECT_EQ(std::vector<int>(one.neighbors.begin(j), one.neighbors.end(j)), expected[j]);
    }
    for (int i = 1; i < 3; ++i) {
      SCOPED_TRACE(std::to_string(i + 1) + " threads, " + std::to_string(graph.num_nodes()) +
                   " nodes");
      EXPECT_TRUE(connected[i].weights == one.weights);
      EXPECT_EQ(connected[i].edges, one.edges);
      EXPECT_EQ(connected[i].neighbors.offsets, one.neighbors.offsets);
      EXPECT_EQ(connected[i].neighbors.values, one.neighbors.values);
    }
  }
}

TEST(DeformationGraphTest, ComponentsAreMergedOnlyWhenEdgesRunOut) {
  // 30 one-node cubes and a sphere: coarse scales have fewer nodes than there
  // are components, so components must be merged to reach D_i exactly, but
  // never while the sphere still has an edge to collapse.
  Mesh sphere = MakeSphere(2.0, 32, 16);
  sphere.vertices.colwise() += Eigen::Vector3d(7.0, 20.0, 0.0);
  const Mesh mesh = Concatenate(Cubes(30), sphere);
  const Lattice lattice = BuildTestLattice(mesh, 1.0);
  const std::vector<DeformationGraph> graphs = BuildGraphs(mesh, lattice, SmallP());
  const Components components = ConnectedComponents(mesh);
  ASSERT_EQ(components.count, 31);
  ASSERT_LT(graphs.back().num_nodes(), components.count);
  int scales_without_mixing = 0;
  for (const DeformationGraph& graph : graphs) {
    // Number of nodes holding more than one component.
    int mixed = 0;
    for (int j = 0; j < graph.num_nodes(); ++j) {
      std::set<int> held;
      for (const int* m = graph.members.begin(j); m != graph.members.end(j); ++m) {
        held.insert(components.component_of_vertex[graphs[0].node_vertex[*m]]);
      }
      mixed += held.size() > 1;
    }
    if (graph.num_nodes() >= components.count) {
      EXPECT_EQ(mixed, 0) << graph.num_nodes() << " nodes";
      ++scales_without_mixing;
    } else {
      EXPECT_GT(mixed, 0) << graph.num_nodes() << " nodes";
    }
  }
  EXPECT_GE(scales_without_mixing, 2);
  EXPECT_LT(scales_without_mixing, static_cast<int>(graphs.size()));
  // Each cube is a one-node component in DG1: its vertices follow that node alone.
  for (int v = 0; v < 30 * 8; ++v) {
    EXPECT_EQ(graphs[0].weights.node(0, v), lattice.particle_of_vertex(v));
    EXPECT_EQ(graphs[0].weights.weight(0, v), 1.0);
  }
}

TEST(DeformationGraphTest, FirstCollapseMergesTheShortestDg1Edge) {
  const Mesh sphere = MakeSphere(1.0, 48, 24);
  const Lattice lattice = BuildTestLattice(sphere, 0.15);
  std::vector<DeformationGraph> graphs;
  std::string error;
  const int d1 = lattice.num_surface_particles();
  ASSERT_TRUE(BuildCollapsedGraphs(sphere, lattice, GraphOptions(), {d1 - 1}, &graphs, &error))
      << error;
  ASSERT_EQ(graphs.size(), 2u);
  const DeformationGraph& dg1 = graphs[0];
  std::pair<int, int> shortest;
  double shortest_length = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : dg1.edges) {
    const double length = (dg1.positions.col(a) - dg1.positions.col(b)).squaredNorm();
    if (length < shortest_length) {
      shortest_length = length;
      shortest = {a, b};
    }
  }
  const DeformationGraph& merged = graphs[1];
  ASSERT_EQ(merged.num_nodes(), d1 - 1);
  const int node = merged.node_of_dg1[shortest.first];
  EXPECT_EQ(merged.node_of_dg1[shortest.second], node);
  EXPECT_EQ(merged.members.size(node), 2);
  // The merged node sits on one of the two vertices, the nearer to their midpoint.
  const Eigen::Vector3d centroid =
      0.5 * (dg1.positions.col(shortest.first) + dg1.positions.col(shortest.second));
  const int expected_vertex = (dg1.positions.col(shortest.first) - centroid).squaredNorm() <=
                                      (dg1.positions.col(shortest.second) - centroid).squaredNorm()
                                  ? dg1.node_vertex[shortest.first]
                                  : dg1.node_vertex[shortest.second];
  EXPECT_EQ(merged.node_vertex[node], expected_vertex);
}

TEST(DeformationGraphTest, CombToothNeverTakesANodeOfAnotherTooth) {
  // Teeth 1 wide with 1-wide gaps. Cells of 0.75 to 0.95 keep the teeth in
  // separate but touching cells, and make the nodes sparse enough that a
  // global Euclidean search would pick nodes of the neighbouring tooth.
  // Vertices within one voxel of the spine are left out: through the spine,
  // the next tooth's base is geodesically close to them.
  const int num_teeth = 3;
  const Mesh comb = MakeComb(num_teeth, 6, 1.0, 5);
  std::vector<int> tooth_of_vertex(comb.num_vertices(), -1);
  for (int t = 0; t < num_teeth; ++t) {
    for (int v : CombToothVertices(comb, t)) tooth_of_vertex[v] = t;
  }
  for (const double cell_width : {0.75, 0.85, 0.95}) {
    for (const uint64_t seed : {1, 2, 3}) {
      SCOPED_TRACE("cell width " + std::to_string(cell_width) + ", seed " + std::to_string(seed));
      const Lattice lattice = BuildTestLattice(comb, cell_width);
      GraphOptions options;
      options.nodes_per_scale = 1000000;
      options.seed = seed;
      const DeformationGraph dg1 = BuildGraphs(comb, lattice, options)[0];
      auto tooth_of_node = [&](int node) { return tooth_of_vertex[dg1.node_vertex[node]]; };
      int checked = 0;
      int euclidean_crossings = 0;
      for (int t = 0; t < num_teeth; ++t) {
        for (int v : CombToothVertices(comb, t)) {
          if (comb.vertices(1, v) <= 2.0) continue;
          for (int i = 0; i < dg1.weights.k(); ++i) {
            const int owner = tooth_of_node(dg1.weights.node(i, v));
            EXPECT_TRUE(owner == t || owner == -1)
                << "vertex " << v << " of tooth " << t << " takes node "
                << dg1.weights.node(i, v) << " of tooth " << owner;
            ++checked;
          }
          // A global Euclidean 4-NN, for contrast.
          std::vector<std::pair<double, int>> all;
          for (int j = 0; j < dg1.num_nodes(); ++j) {
            all.emplace_back((comb.vertices.col(v) - dg1.positions.col(j)).squaredNorm(), j);
          }
          std::partial_sort(all.begin(), all.begin() + 4, all.end());
          for (int i = 0; i < 4; ++i) {
            const int owner = tooth_of_node(all[i].second);
            euclidean_crossings += owner != t && owner != -1;
          }
        }
      }
      EXPECT_GT(checked, 1000);
      EXPECT_GT(euclidean_crossings, 0) << "the geometry should tempt a Euclidean search";
    }
  }
}

TEST(DeformationGraphTest, InvalidOptionsAreReported) {
  const Mesh bar = MakeBar(4);
  const Lattice lattice = BuildTestLattice(bar, 0.5);
  std::vector<DeformationGraph> graphs;
  std::string error;
  GraphOptions options;
  options.k = 0;
  EXPECT_FALSE(BuildMultiScaleGraphs(bar, lattice, options, &graphs, &error));
  EXPECT_NE(error.find("k "), std::string::npos) << error;
  options = GraphOptions();
  options.nodes_per_scale = 0;
  EXPECT_FALSE(BuildMultiScaleGraphs(bar, lattice, options, &graphs, &error));
  EXPECT_NE(error.find("nodes_per_scale"), std::string::npos) << error;
  options = GraphOptions();
  const int d1 = lattice.num_surface_particles();
  EXPECT_FALSE(BuildCollapsedGraphs(bar, lattice, options, {d1 / 2, d1 / 2 + 1}, &graphs, &error));
  EXPECT_NE(error.find("non-increasing"), std::string::npos) << error;
  EXPECT_FALSE(BuildCollapsedGraphs(bar, lattice, options, {0}, &graphs, &error));
  EXPECT_FALSE(BuildCollapsedGraphs(bar, lattice, options, {d1 + 1}, &graphs, &error));
}

TEST(DeformationGraphTest, RealMeshesHaveValidWeightsAtEveryScale) {
  const std::vector<std::string> names = {"armadillo", "camel", "elephant", "dino",   "man",
                                          "hand",      "cactus", "plane",   "bunny00"};
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const std::string path = std::string(MSDEFORM_DATA_DIR) + "/meshes/" + name + ".off";
    Mesh mesh;
    std::string error;
    ASSERT_TRUE(ReadMesh(path, &mesh, &error))
        << error << " (run data/fetch_meshes.sh to fetch the real meshes)";
    Lattice lattice;
    ASSERT_TRUE(Lattice::Build(mesh, LatticeOptions(), &lattice, &error)) << error;
    const GraphOptions options;
    const std::vector<DeformationGraph> graphs = BuildGraphs(mesh, lattice, options);
    LOG(INFO) << name << ": " << mesh.num_vertices() << " vertices, D1 = "
              << lattice.num_surface_particles() << ", N = " << graphs.size();
    ExpectValidGraphs(mesh, lattice, options, graphs);
  }
}

}  // namespace
}  // namespace msdeform
