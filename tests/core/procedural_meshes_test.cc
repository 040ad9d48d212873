#include "core/procedural_meshes.h"

#include <map>

#include <gtest/gtest.h>

namespace msdeform {
namespace {

// Every undirected edge of a closed, consistently oriented mesh is used once in
// each direction.
void ExpectClosedAndOriented(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) ++directed[{mesh.faces(c, f), mesh.faces((c + 1) % 3, f)}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << edge.first << "->" << edge.second;
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << edge.first << "-" << edge.second;
  }
}

double SignedVolume(const Mesh& mesh) {
  double volume = 0.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    volume += mesh.vertices.col(mesh.faces(0, f))
                  .dot(mesh.vertices.col(mesh.faces(1, f)).cross(mesh.vertices.col(mesh.faces(2, f))));
  }
  return volume / 6.0;
}

TEST(ProceduralMeshesTest, BarIsClosedWithItsVolume) {
  const Mesh bar = MakeBar(5, 0.5, 3);
  ExpectClosedAndOriented(bar);
  EXPECT_NEAR(SignedVolume(bar), 5 * 0.125, 1e-12);
  std::string error;
  EXPECT_TRUE(ValidateMesh(bar, &error)) << error;
}

TEST(ProceduralMeshesTest, CombIsOneClosedComponent) {
  const Mesh comb = MakeComb(4, 3);
  ExpectClosedAndOriented(comb);
  EXPECT_NEAR(SignedVolume(comb), 7 + 4 * 3, 1e-9);
  EXPECT_EQ(ConnectedComponents(comb).count, 1);
  EXPECT_FALSE(CombToothVertices(comb, 2).empty());
}

TEST(ProceduralMeshesTest, TwoBarsAreTwoComponents) {
  const Mesh bars = MakeTwoBars(4, 1);
  ExpectClosedAndOriented(bars);
  EXPECT_EQ(ConnectedComponents(bars).count, 2);
}

TEST(ProceduralMeshesTest, SphereIsClosedAndOutward) {
  const Mesh sphere = MakeSphere(2.0, 32, 16);
  ExpectClosedAndOriented(sphere);
  EXPECT_NEAR(SignedVolume(sphere), 4.0 / 3.0 * M_PI * 8.0, 0.05 * 33.5);
  EXPECT_GT(SignedVolume(sphere), 0.0);
}

TEST(ProceduralMeshesTest, OpenTubeHasTwoBoundaryLoops) {
  const Mesh tube = MakeOpenTube(1.0, 3.0, 12, 4);
  std::map<std::pair<int, int>, int> undirected;
  for (int f = 0; f < tube.num_faces(); ++f)
    for (int c = 0; c < 3; ++c) {
      int a = tube.faces(c, f), b = tube.faces((c + 1) % 3, f);
      ++undirected[{std::min(a, b), std::max(a, b)}];
    }
  int boundary = 0;
  for (const auto& [edge, count] : undirected) boundary += count == 1;
  EXPECT_EQ(boundary, 2 * 12);
}

}  // namespace
}  // namespace msdeform
