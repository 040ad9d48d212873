#include "msdeform/core/procedural_meshes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

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

// The smallest corner angle of any face, in degrees.
double MinimumAngleDegrees(const Mesh& mesh) {
  double smallest = 180.0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = mesh.vertices.col(mesh.faces(c, f));
      const Eigen::Vector3d u = mesh.vertices.col(mesh.faces((c + 1) % 3, f)) - p;
      const Eigen::Vector3d v = mesh.vertices.col(mesh.faces((c + 2) % 3, f)) - p;
      smallest = std::min(smallest, std::atan2(u.cross(v).norm(), u.dot(v)) * 180.0 / M_PI);
    }
  }
  return smallest;
}

TEST(ProceduralMeshesTest, CylinderIsClosedOutwardAndWellShaped) {
  // 24 segments: K = round(24 / (pi sqrt 3)) = 4 cap circles, the inner ones
  // holding 18, 12 and 6 vertices, plus the centre: 37 per cap. Rings 13 make
  // the side rows 3 / 13 = 0.23 apart, sqrt(3) / 2 of the edge 2 pi / 24 = 0.26.
  const Mesh cylinder = MakeCylinder(1.0, 3.0, 24, 13);
  EXPECT_EQ(CylinderCapRings(24), 4);
  ASSERT_EQ(cylinder.num_vertices(), 24 * 14 + 2 * 37);
  // Side 2 * 24 * 13; per cap 24 + 18, 18 + 12, 12 + 6 zipped and 6 fanned.
  EXPECT_EQ(cylinder.num_faces(), 2 * 24 * 13 + 2 * (42 + 30 + 18 + 6));
  ExpectClosedAndOriented(cylinder);
  std::string error;
  EXPECT_TRUE(ValidateMesh(cylinder, &error)) << error;
  EXPECT_EQ(ConnectedComponents(cylinder).count, 1);
  // Euler characteristic 2 (a sphere): every edge is in two faces, E = 3F / 2.
  EXPECT_EQ(cylinder.num_vertices() - 3 * cylinder.num_faces() / 2 + cylinder.num_faces(), 2);
  // Outward: side normals point away from the axis, cap normals along -z / +z.
  for (int f = 0; f < cylinder.num_faces(); ++f) {
    const Eigen::Vector3d a = cylinder.vertices.col(cylinder.faces(0, f));
    const Eigen::Vector3d b = cylinder.vertices.col(cylinder.faces(1, f));
    const Eigen::Vector3d c = cylinder.vertices.col(cylinder.faces(2, f));
    const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
    const Eigen::Vector3d centre = (a + b + c) / 3.0;
    if (a.z() == b.z() && b.z() == c.z() && (a.z() == 0.0 || a.z() == 3.0)) {
      EXPECT_NEAR(normal.z(), a.z() == 0.0 ? -1.0 : 1.0, 1e-12) << "cap face " << f;
    } else {
      EXPECT_GT(normal.dot(Eigen::Vector3d(centre.x(), centre.y(), 0.0).normalized()), 0.99)
          << "side face " << f;
    }
  }
  EXPECT_NEAR(SignedVolume(cylinder), M_PI * 3.0, 0.02 * M_PI * 3.0);
  EXPECT_GT(SignedVolume(cylinder), 0.0);
  EXPECT_GT(MinimumAngleDegrees(cylinder), 40.0);
  // On z = 0 and z = height, nowhere else below or above.
  EXPECT_EQ(cylinder.vertices.row(2).minCoeff(), 0.0);
  EXPECT_EQ(cylinder.vertices.row(2).maxCoeff(), 3.0);
}

TEST(ProceduralMeshesTest, CylinderVertexCountFollowsTheFormula) {
  for (const int segments : {3, 5, 7, 13, 64}) {
    const int cap_rings = CylinderCapRings(segments);
    int cap = 1;
    for (int k = 1; k < cap_rings; ++k) {
      cap += std::max(3, static_cast<int>(std::lround(1.0 * segments * k / cap_rings)));
    }
    const Mesh cylinder = MakeCylinder(0.5, 2.0, segments, 4);
    EXPECT_EQ(cylinder.num_vertices(), segments * 5 + 2 * cap) << segments;
    ExpectClosedAndOriented(cylinder);
    EXPECT_EQ(cylinder.num_vertices() - 3 * cylinder.num_faces() / 2 + cylinder.num_faces(), 2)
        << segments;
    EXPECT_GT(SignedVolume(cylinder), 0.0) << segments;
  }
  EXPECT_EQ(CylinderCapRings(3), 1);  // the end circles fanned to the centres
  EXPECT_EQ(CylinderCapRings(64), 12);
}

// Every vertex's faces form one fan: the edges opposite the vertex, followed
// head to tail, make a single cycle through all of them.
void ExpectVertexManifold(const Mesh& mesh) {
  std::vector<std::map<int, int>> link(mesh.num_vertices());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      link[mesh.faces(c, f)][mesh.faces((c + 1) % 3, f)] = mesh.faces((c + 2) % 3, f);
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    ASSERT_FALSE(link[v].empty()) << "isolated vertex " << v;
    size_t steps = 0;
    int at = link[v].begin()->first;
    do {
      auto next = link[v].find(at);
      ASSERT_NE(next, link[v].end()) << "open fan at vertex " << v;
      at = next->second;
      ++steps;
    } while (at != link[v].begin()->first && steps <= link[v].size());
    EXPECT_EQ(steps, link[v].size()) << "vertex " << v << " has more than one fan";
  }
}

TEST(ProceduralMeshesTest, ForkIsOneClosedManifoldWithProngsGapApart) {
  // 0.1 of a default lattice cell: the diagonal is sqrt(278) voxels, 48 cells.
  const double voxel = 0.5, gap = 0.1 * std::sqrt(278.0) / 48.0;
  const Mesh fork = MakeFork(gap, voxel, 4);
  std::string error;
  ASSERT_TRUE(ValidateMesh(fork, &error)) << error;
  ExpectClosedAndOriented(fork);
  ExpectVertexManifold(fork);
  EXPECT_EQ(ConnectedComponents(fork).count, 1);
  // A sphere's Euler characteristic: the squeeze keeps the comb's topology.
  EXPECT_EQ(fork.num_vertices() - 3 * fork.num_faces() / 2 + fork.num_faces(), 2);
  // Base (4 + gap) x 3 x 2 voxels, prongs 2 x 12 x 2 each (a shear keeps volume).
  EXPECT_NEAR(SignedVolume(fork), (6.0 * (4.0 + gap) + 96.0) * std::pow(voxel, 3), 1e-9);
  const Eigen::AlignedBox3d box = BoundingBox(fork);
  EXPECT_NEAR((box.max() - box.min() - Eigen::Vector3d(7.0, 15.0, 2.0) * voxel).norm(), 0.0, 1e-12);
  EXPECT_NEAR(BoundingBoxDiagonal(fork) / 48.0 * 0.1, gap * voxel, 1e-12);

  // Above the base every face lies on one side of the slab 2 < x < 2 + gap
  // (voxels), so the prongs' surfaces are at least gap apart; facing
  // vertices along the touching stretch are exactly gap apart.
  const double wall = 2.0 * voxel, far_wall = (2.0 + gap) * voxel;
  for (int f = 0; f < fork.num_faces(); ++f) {
    int above = 0, left = 0, right = 0;
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector3d p = fork.vertices.col(fork.faces(c, f));
      above += p.y() > kForkBaseHeight * voxel + 1e-12;
      left += p.x() <= wall + 1e-12;
      right += p.x() >= far_wall - 1e-12;
    }
    if (above > 0) {
      EXPECT_TRUE(left == 3 || right == 3) << "face " << f << " spans the gap";
    }
  }
  const std::vector<int> prong0 = ForkProngVertices(fork, 0, voxel);
  const std::vector<int> prong1 = ForkProngVertices(fork, 1, voxel);
  const std::vector<int> base = ForkBaseVertices(fork, voxel);
  EXPECT_EQ(prong0.size() + prong1.size() + base.size(), static_cast<size_t>(fork.num_vertices()));
  double closest = std::numeric_limits<double>::infinity();
  int pairs_at_gap = 0;
  for (int a : prong0) {
    for (int b : prong1) {
      const double distance = (fork.vertices.col(a) - fork.vertices.col(b)).norm();
      closest = std::min(closest, distance);
      pairs_at_gap += distance < gap * voxel * (1.0 + 1e-9);
    }
  }
  EXPECT_NEAR(closest, gap * voxel, 1e-12);
  // Facing wall vertices (4 per voxel along y and z) over the 3-voxel
  // stretch above the base, y = 3.25 .. 6: 12 heights x 9 depths.
  EXPECT_EQ(pairs_at_gap, 12 * 9);
  // The tips are kForkTipGap apart.
  const std::vector<int> tip0 = ForkTipVertices(fork, 0, voxel);
  const std::vector<int> tip1 = ForkTipVertices(fork, 1, voxel);
  ASSERT_FALSE(tip0.empty());
  ASSERT_FALSE(tip1.empty());
  double tip_gap = std::numeric_limits<double>::infinity();
  for (int a : tip0) {
    for (int b : tip1) {
      tip_gap = std::min(tip_gap, (fork.vertices.col(a) - fork.vertices.col(b)).norm());
    }
  }
  // Closest at the tip voxel's bottom, y = 14, 8 of the 9 voxels up the spread.
  EXPECT_NEAR(tip_gap, (gap + (kForkTipGap - gap) * 8.0 / 9.0) * voxel, 1e-12);
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
