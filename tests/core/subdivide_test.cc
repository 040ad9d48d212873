#include "msdeform/core/subdivide.h"

#include <map>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"

namespace msdeform {
namespace {

// Number of faces using each directed edge (a -> b).
std::map<std::pair<int, int>, int> DirectedEdgeUse(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> use;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) ++use[{mesh.faces(c, f), mesh.faces((c + 1) % 3, f)}];
  }
  return use;
}

// Closed and consistently oriented: every edge is used once in each direction,
// that is, shared by exactly two faces.
void ExpectClosed(const Mesh& mesh) {
  const auto use = DirectedEdgeUse(mesh);
  for (const auto& [edge, count] : use) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "->" << edge.second;
    const auto twin = use.find({edge.second, edge.first});
    EXPECT_TRUE(twin != use.end()) << "edge " << edge.first << "-" << edge.second
                                   << " is on a boundary";
  }
}

TEST(SubdivideTest, OctahedronIsClosedAndOriented) {
  const Mesh octahedron = MakeOctahedron();
  ASSERT_EQ(UniqueEdges(octahedron).size(), 12u);
  ExpectClosed(octahedron);
}

TEST(SubdivideTest, OneStepAddsAVertexPerEdgeAndSplitsFacesInFour) {
  const Mesh octahedron = MakeOctahedron();
  const int num_edges = static_cast<int>(UniqueEdges(octahedron).size());
  const Mesh once = LoopSubdivide(octahedron, 1);
  EXPECT_EQ(once.num_vertices(), octahedron.num_vertices() + num_edges);
  EXPECT_EQ(once.num_faces(), 4 * octahedron.num_faces());
  EXPECT_EQ(static_cast<int>(UniqueEdges(once).size()), 2 * num_edges + 3 * octahedron.num_faces());
  ExpectClosed(once);
  std::string error;
  EXPECT_TRUE(ValidateMesh(once, &error)) << error;
}

TEST(SubdivideTest, TwoStepsCompose) {
  const Mesh twice = LoopSubdivide(MakeOctahedron(), 2);
  EXPECT_EQ(twice.num_vertices(), 18 + 48);  // 18 vertices and 48 edges after one step.
  EXPECT_EQ(twice.num_faces(), 8 * 16);
  ExpectClosed(twice);
}

TEST(SubdivideTest, InputVerticesKeepTheirIdsAtTheirLoopPositions) {
  // Valence 4: alpha = (40 - (3 + 2 cos(pi / 2))^2) / 64 = 31/64, and the four
  // neighbours of (1, 0, 0) average to the origin, so it moves to (33/64, 0, 0).
  const Mesh once = LoopSubdivide(MakeOctahedron(), 1);
  EXPECT_TRUE(once.vertices.col(0).isApprox(Eigen::Vector3d(33.0 / 64.0, 0, 0)));
  EXPECT_TRUE(once.vertices.col(5).isApprox(Eigen::Vector3d(0, 0, -33.0 / 64.0)));
  // Edge vertices: 3/8 of each end plus 1/8 of each opposite vertex; for the
  // edge (0, 2) that is (3/8, 3/8, 0). It is one of the appended vertices.
  bool found = false;
  for (int v = 6; v < once.num_vertices(); ++v) {
    found |= once.vertices.col(v).isApprox(Eigen::Vector3d(3.0 / 8.0, 3.0 / 8.0, 0));
  }
  EXPECT_TRUE(found);
}

TEST(SubdivideTest, ZeroStepsReturnsTheInput) {
  const Mesh octahedron = MakeOctahedron();
  const Mesh same = LoopSubdivide(octahedron, 0);
  EXPECT_EQ(same.vertices, octahedron.vertices);
  EXPECT_EQ(same.faces, octahedron.faces);
}

TEST(SubdivideTest, NonManifoldEdgeIsAnErrorNotACrash) {
  // Three triangles on the edge (0, 1).
  Mesh fan;
  fan.vertices.resize(3, 5);
  fan.vertices << 0, 1, 0, 0, 1,  //
      0, 0, 1, -1, 1,             //
      0, 0, 0, 0, 1;
  fan.faces.resize(3, 3);
  fan.faces << 0, 1, 0,  //
      1, 0, 1,           //
      2, 3, 4;
  Mesh out;
  std::string error;
  EXPECT_FALSE(LoopSubdivide(fan, 1, &out, &error));
  EXPECT_NE(error.find("face 2"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
