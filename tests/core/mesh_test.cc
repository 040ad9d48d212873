#include "msdeform/core/mesh.h"

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

// Two triangles sharing the edge (1, 2), plus one isolated triangle.
Mesh TwoPatches() {
  Mesh mesh;
  mesh.vertices.resize(3, 7);
  mesh.vertices << 0, 1, 0, 1, 5, 6, 5,  //
      0, 0, 1, 1, 0, 0, 1,               //
      0, 0, 0, 0, 0, 0, 0;
  mesh.faces.resize(3, 3);
  mesh.faces << 0, 1, 4,  //
      1, 3, 5,            //
      2, 2, 6;
  return mesh;
}

TEST(MeshTest, BoundingBoxDiagonalOfUnitSquareIsSqrt2) {
  Mesh mesh = TwoPatches();
  mesh.vertices.conservativeResize(3, 4);
  mesh.faces.conservativeResize(3, 2);
  EXPECT_DOUBLE_EQ(BoundingBoxDiagonal(mesh), std::sqrt(2.0));
}

TEST(MeshTest, UniqueEdgesCountsSharedEdgeOnce) {
  const auto edges = UniqueEdges(TwoPatches());
  EXPECT_EQ(edges.size(), 8u);  // 5 for the quad, 3 for the lone triangle.
  EXPECT_EQ(edges.front(), std::make_pair(0, 1));
}

// Sorted (a < b) pairs, each once, whatever the faces' orientation and
// repeats: the set of every face side, on random faces.
TEST(MeshTest, UniqueEdgesAreTheSortedSetOfFaceSides) {
  std::mt19937 rng(4);
  Mesh mesh;
  mesh.vertices = Eigen::Matrix3Xd::Zero(3, 30);
  mesh.faces.resize(3, 200);
  std::set<std::pair<int, int>> expected;
  for (int f = 0; f < 200; ++f) {
    for (int c = 0; c < 3; ++c) mesh.faces(c, f) = static_cast<int>(rng() % 30);
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.faces(c, f), b = mesh.faces((c + 1) % 3, f);
      if (a != b) expected.emplace(std::min(a, b), std::max(a, b));
    }
  }
  const std::vector<std::pair<int, int>> edges = UniqueEdges(mesh);
  const std::vector<std::pair<int, int>> sorted_set(expected.begin(), expected.end());
  EXPECT_EQ(edges, sorted_set);
}

TEST(MeshTest, AdjacencyIsSymmetricAndSorted) {
  const VertexAdjacency adjacency = ComputeVertexAdjacency(TwoPatches());
  ASSERT_EQ(adjacency.offsets.size(), 8u);
  const std::vector<int> of_one(adjacency.neighbors.begin() + adjacency.offsets[1],
                                adjacency.neighbors.begin() + adjacency.offsets[2]);
  EXPECT_EQ(of_one, (std::vector<int>{0, 2, 3}));
}

TEST(MeshTest, ConnectedComponentsSeparatesPatches) {
  const Components components = ConnectedComponents(TwoPatches());
  EXPECT_EQ(components.count, 2);
  EXPECT_EQ(components.component_of_vertex,
            (std::vector<int>{0, 0, 0, 0, 1, 1, 1}));
}

TEST(MeshTest, NormalsOfPlanarPatchPointAlongZ) {
  const Eigen::Matrix3Xd normals = VertexNormals(TwoPatches());
  for (int v = 0; v < normals.cols(); ++v) {
    EXPECT_NEAR(normals(2, v), 1.0, 1e-12) << "vertex " << v;
  }
}

TEST(MeshTest, ValidateRejectsOutOfRangeAndNonFinite) {
  std::string error;
  Mesh mesh = TwoPatches();
  EXPECT_TRUE(ValidateMesh(mesh, &error)) << error;
  mesh.faces(2, 2) = 9;
  EXPECT_FALSE(ValidateMesh(mesh, &error));
  EXPECT_NE(error.find("face 2"), std::string::npos) << error;
  mesh = TwoPatches();
  mesh.vertices(1, 3) = std::nan("");
  EXPECT_FALSE(ValidateMesh(mesh, &error));
  EXPECT_NE(error.find("vertex 3"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
