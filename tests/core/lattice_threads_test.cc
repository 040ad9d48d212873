// The mesh passes (core/mesh.h) and the lattice give the same bits on 1, 2
// and 3 threads. The test mesh is big enough that every pass takes its
// parallel path (16K items and more) and that the ordered scatters of
// core/mesh.cc run more than one block (2 MB of entries: 21,845 faces for the
// normals, 87,381 for the edges), its vertex and face ids are shuffled as in a
// mesh made by subdivision, and it has several components, isolated vertices,
// split cells (a fork whose prongs share cells) and interior cells.

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/lattice.h"
#include "msdeform/core/mesh.h"
#include "msdeform/core/procedural_meshes.h"

namespace msdeform {
namespace {

constexpr int kIsolatedVertices = 5;

// A fork (cells of width 1 hold both prongs), a solid cube beside it, and
// isolated vertices; vertices and faces in a random order.
Mesh ShuffledTestMesh() {
  const Mesh fork = MakeFork(0.1, 1.0, 12);
  VoxelShape cube_shape(9, 9, 9);
  cube_shape.Fill(Eigen::Vector3i::Zero(), Eigen::Vector3i::Constant(9));
  Mesh cube = MakeVoxelMesh(cube_shape, 1.0, 8);
  cube.vertices.colwise() += Eigen::Vector3d(10.0, 0.0, 0.0);
  const int num_vertices = fork.num_vertices() + cube.num_vertices() + kIsolatedVertices;
  Mesh joined;
  joined.vertices.resize(3, num_vertices);
  joined.vertices << fork.vertices, cube.vertices,
      Eigen::Matrix3Xd::Constant(3, kIsolatedVertices, -2.0);
  joined.faces.resize(3, fork.num_faces() + cube.num_faces());
  joined.faces << fork.faces, (cube.faces.array() + fork.num_vertices()).matrix();
  for (int i = 0; i < kIsolatedVertices; ++i) joined.vertices(0, num_vertices - 1 - i) += i;

  std::mt19937 rng(30);
  std::vector<int> new_id(num_vertices);
  std::iota(new_id.begin(), new_id.end(), 0);
  std::shuffle(new_id.begin(), new_id.end(), rng);
  std::vector<int> face_order(joined.num_faces());
  std::iota(face_order.begin(), face_order.end(), 0);
  std::shuffle(face_order.begin(), face_order.end(), rng);
  Mesh mesh;
  mesh.vertices.resize(3, num_vertices);
  for (int v = 0; v < num_vertices; ++v) mesh.vertices.col(new_id[v]) = joined.vertices.col(v);
  mesh.faces.resize(3, joined.num_faces());
  for (int f = 0; f < joined.num_faces(); ++f) {
    for (int k = 0; k < 3; ++k) mesh.faces(k, f) = new_id[joined.faces(k, face_order[f])];
  }
  return mesh;
}

const Mesh& TestMesh() {
  static const Mesh mesh = ShuffledTestMesh();
  return mesh;
}

// Bitwise equality of two matrices of doubles (EXPECT_EQ on doubles would
// let -0.0 equal 0.0).
bool SameBits(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) {
  return a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

void ExpectSameLists(const CompressedLists& a, const CompressedLists& b, const char* what) {
  EXPECT_EQ(a.offsets, b.offsets) << what;
  EXPECT_EQ(a.values, b.values) << what;
}

TEST(LatticeThreadsTest, TestMeshTakesEveryParallelPath) {
  const Mesh& mesh = TestMesh();
  EXPECT_GE(mesh.num_vertices(), 50000);
  EXPECT_GT(mesh.num_faces(), 87381);  // two blocks of the edges' ordered scatter
  std::string error;
  EXPECT_TRUE(ValidateMesh(mesh, &error)) << error;
}

TEST(LatticeThreadsTest, MeshPassesAreTheSameOnAnyThreadCount) {
  const Mesh& mesh = TestMesh();
  const Eigen::AlignedBox3d box = BoundingBox(mesh, 1);
  const auto edges = UniqueEdges(mesh, 1);
  const VertexAdjacency adjacency = ComputeVertexAdjacency(mesh, 1);
  const Components components = ConnectedComponents(mesh, 1);
  const Eigen::Matrix3Xd normals = VertexNormals(mesh, 1);
  // Known answers on one thread: fork, cube and each isolated vertex; ids in
  // the order of each component's smallest vertex; each edge twice in the
  // adjacency.
  EXPECT_EQ(components.count, 2 + kIsolatedVertices);
  int next_new = 0;
  for (int id : components.component_of_vertex) {
    ASSERT_LE(id, next_new);
    if (id == next_new) ++next_new;
  }
  EXPECT_EQ(adjacency.neighbors.size(), 2 * edges.size());
  for (int threads : {2, 3}) {
    SCOPED_TRACE(threads);
    const Eigen::AlignedBox3d other_box = BoundingBox(mesh, threads);
    EXPECT_TRUE(other_box.min() == box.min() && other_box.max() == box.max());
    EXPECT_EQ(UniqueEdges(mesh, threads), edges);
    const VertexAdjacency other_adjacency = ComputeVertexAdjacency(mesh, threads);
    EXPECT_EQ(other_adjacency.offsets, adjacency.offsets);
    EXPECT_EQ(other_adjacency.neighbors, adjacency.neighbors);
    const Components other_components = ConnectedComponents(mesh, threads);
    EXPECT_EQ(other_components.count, components.count);
    EXPECT_EQ(other_components.component_of_vertex, components.component_of_vertex);
    EXPECT_TRUE(SameBits(VertexNormals(mesh, threads), normals));
  }
}

Lattice BuildLattice(const Mesh& mesh, bool split_cells, int threads) {
  LatticeOptions options;
  options.cell_width = 1.0;
  options.split_cells = split_cells;
  options.num_threads = threads;
  Lattice lattice;
  std::string error;
  EXPECT_TRUE(Lattice::Build(mesh, options, &lattice, &error)) << error;
  return lattice;
}

void ExpectSameLattice(const Lattice& a, const Lattice& b) {
  EXPECT_EQ(a.num_surface_particles(), b.num_surface_particles());
  EXPECT_EQ(a.num_split_cells(), b.num_split_cells());
  ASSERT_EQ(a.num_particles(), b.num_particles());
  for (int p = 0; p < a.num_particles(); ++p) {
    ASSERT_EQ(a.cell_coords(p), b.cell_coords(p)) << "particle " << p;
  }
  EXPECT_TRUE(SameBits(a.rest_positions(), b.rest_positions()));
  EXPECT_EQ(a.particle_of_vertex(), b.particle_of_vertex());
  ExpectSameLists(a.vertices_of_particle(), b.vertices_of_particle(), "vertices_of_particle");
  ExpectSameLists(a.neighborhood(), b.neighborhood(), "neighborhood");
  ExpectSameLists(a.particle_adjacency(), b.particle_adjacency(), "particle_adjacency");
}

TEST(LatticeThreadsTest, LatticeIsTheSameOnAnyThreadCount) {
  const Mesh& mesh = TestMesh();
  for (bool split_cells : {true, false}) {
    SCOPED_TRACE(split_cells);
    const Lattice one = BuildLattice(mesh, split_cells, 1);
    // The paths the threads share out: split cells (the grown search) and
    // enough interior particles for the parallel adjacency.
    if (split_cells) {
      EXPECT_GT(one.num_split_cells(), 0);
    }
    EXPECT_GE(one.num_interior_particles(), 256);
    for (int threads : {2, 3}) {
      SCOPED_TRACE(threads);
      ExpectSameLattice(BuildLattice(mesh, split_cells, threads), one);
    }
  }
}

TEST(LatticeThreadsTest, OptionsRefuseAThreadCountOutOfRange) {
  LatticeOptions options;
  std::string error;
  options.num_threads = 0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "num_threads must be in 1..1024");
  options.num_threads = 1025;
  EXPECT_FALSE(options.Check(&error));
  options.num_threads = 1024;
  EXPECT_TRUE(options.Check(&error));
}

}  // namespace
}  // namespace msdeform
