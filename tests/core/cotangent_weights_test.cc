// Cotangent weights (core/cotangent_weights.h): values worked out by hand on
// small meshes, the symmetry w_ik = w_ki, the clamp at 0 of an edge whose
// opposite angles are obtuse, and the same numbers, bit for bit, as the
// formula experiments/metrics.cc had before the weights moved to core.

#include "msdeform/core/cotangent_weights.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"

namespace msdeform {
namespace {

Mesh MakeMesh(const std::vector<Eigen::Vector3d>& vertices,
              const std::vector<Eigen::Vector3i>& faces) {
  Mesh mesh;
  mesh.vertices.resize(3, static_cast<int>(vertices.size()));
  for (size_t v = 0; v < vertices.size(); ++v) mesh.vertices.col(v) = vertices[v];
  mesh.faces.resize(3, static_cast<int>(faces.size()));
  for (size_t f = 0; f < faces.size(); ++f) mesh.faces.col(f) = faces[f];
  return mesh;
}

// The weight of edge (i, k) as seen from i; fails the test when (i, k) is
// not an edge.
double Weight(const CotangentWeights& weights, int i, int k) {
  const VertexAdjacency& adjacency = weights.adjacency;
  for (int s = adjacency.offsets[i]; s < adjacency.offsets[i + 1]; ++s) {
    if (adjacency.neighbors[s] == k) return weights.weight[s];
  }
  ADD_FAILURE() << "no edge " << i << "-" << k;
  return -1.0;
}

int NumEdges(const CotangentWeights& weights) {
  return static_cast<int>(weights.adjacency.neighbors.size()) / 2;
}

// The right isosceles triangle (0,0), (1,0), (0,1): the right angle at vertex
// 0 faces edge 1-2 (cot 90 = 0), the 45 degree angles face the legs
// (cot 45 / 2 = 1/2 each, one face per edge).
TEST(CotangentWeightsTest, RightIsoscelesTriangle) {
  const Mesh mesh = MakeMesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  const CotangentWeights weights = ComputeCotangentWeights(mesh);
  ASSERT_EQ(NumEdges(weights), 3);
  EXPECT_NEAR(Weight(weights, 1, 2), 0.0, 1e-16);
  EXPECT_NEAR(Weight(weights, 0, 1), 0.5, 1e-15);
  EXPECT_NEAR(Weight(weights, 0, 2), 0.5, 1e-15);
}

// A regular tetrahedron: every edge has two faces with 60 degree opposite
// angles, w = (cot 60 + cot 60) / 2 = 1 / sqrt(3), whatever the edge length.
TEST(CotangentWeightsTest, RegularTetrahedron) {
  const double scale = 2.5;
  const Mesh mesh =
      MakeMesh({scale * Eigen::Vector3d(1, 1, 1), scale * Eigen::Vector3d(1, -1, -1),
                scale * Eigen::Vector3d(-1, 1, -1), scale * Eigen::Vector3d(-1, -1, 1)},
               {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
  const CotangentWeights weights = ComputeCotangentWeights(mesh);
  ASSERT_EQ(NumEdges(weights), 6);
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 4; ++k) {
      if (i == k) continue;
      EXPECT_NEAR(Weight(weights, i, k), 1.0 / std::sqrt(3.0), 1e-15) << i << "-" << k;
    }
  }
}

// A flat a x b rectangle split along its diagonal 0-2: the diagonal faces two
// right angles (w = 0); side 0-1 (length a) faces an angle of tangent a / b in
// face (0, 1, 2) only, so w = b / (2a); side 1-2 (length b) faces an angle of
// tangent b / a, w = a / (2b). The other two sides likewise.
TEST(CotangentWeightsTest, FlatRectangleSplitInTwo) {
  for (const auto& [a, b] : {std::pair<double, double>{1.0, 1.0}, {2.0, 1.0}}) {
    const Mesh mesh =
        MakeMesh({{0, 0, 0}, {a, 0, 0}, {a, b, 0}, {0, b, 0}}, {{0, 1, 2}, {0, 2, 3}});
    const CotangentWeights weights = ComputeCotangentWeights(mesh);
    ASSERT_EQ(NumEdges(weights), 5);
    EXPECT_NEAR(Weight(weights, 0, 2), 0.0, 1e-15);
    EXPECT_NEAR(Weight(weights, 0, 1), b / (2 * a), 1e-15);
    EXPECT_NEAR(Weight(weights, 2, 3), b / (2 * a), 1e-15);
    EXPECT_NEAR(Weight(weights, 1, 2), a / (2 * b), 1e-15);
    EXPECT_NEAR(Weight(weights, 0, 3), a / (2 * b), 1e-15);
  }
}

// Edge 0-1 from (-1, 0) to (1, 0) with apexes (0, 0.2) (cot = -2.4, obtuse)
// and (0, -h): the weight is the clamped sum of the two halves, not a sum of
// clamped halves. h = 4: cot = 15/8, (-2.4 + 1.875) / 2 < 0, so 0; h = 10:
// cot = 99/20, (-2.4 + 4.95) / 2 = 1.275.
TEST(CotangentWeightsTest, ObtuseOppositeAnglesClampAtZero) {
  for (const auto& [h, expected] : {std::pair<double, double>{4.0, 0.0}, {10.0, 1.275}}) {
    const Mesh mesh =
        MakeMesh({{-1, 0, 0}, {1, 0, 0}, {0, 0.2, 0}, {0, -h, 0}}, {{0, 1, 2}, {1, 0, 3}});
    const CotangentWeights weights = ComputeCotangentWeights(mesh);
    EXPECT_NEAR(Weight(weights, 0, 1), expected, 1e-14) << "h = " << h;
    EXPECT_NEAR(Weight(weights, 1, 0), expected, 1e-14) << "h = " << h;
  }
  // One obtuse triangle alone: its long edge's weight cot / 2 < 0 clamps.
  const Mesh single = MakeMesh({{-1, 0, 0}, {1, 0, 0}, {0, 0.2, 0}}, {{0, 1, 2}});
  EXPECT_EQ(Weight(ComputeCotangentWeights(single), 0, 1), 0.0);
}

// A zero-area face adds nothing (its corners have no cotangent).
TEST(CotangentWeightsTest, DegenerateFaceAddsZero) {
  const Mesh mesh = MakeMesh({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}});
  const CotangentWeights weights = ComputeCotangentWeights(mesh);
  for (double w : weights.weight) EXPECT_EQ(w, 0.0);
}

// The formula of experiments/metrics.cc before the weights moved to core:
// every face corner's half-cotangent on the opposite edge, the list sorted
// by (edge, value) and summed in that order, clamped at 0.
std::map<std::pair<int, int>, double> PreviousMetricsWeights(const Mesh& rest) {
  std::vector<std::pair<std::pair<int, int>, double>> corner_weights;
  for (int f = 0; f < rest.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int i = rest.faces(c, f), j = rest.faces((c + 1) % 3, f),
                k = rest.faces((c + 2) % 3, f);
      const Eigen::Vector3d a = rest.vertices.col(j) - rest.vertices.col(i);
      const Eigen::Vector3d b = rest.vertices.col(k) - rest.vertices.col(i);
      const double cross = a.cross(b).norm();
      const double cot = cross > 0.0 ? a.dot(b) / cross : 0.0;
      corner_weights.push_back({{std::min(j, k), std::max(j, k)}, 0.5 * cot});
    }
  }
  std::sort(corner_weights.begin(), corner_weights.end());
  std::map<std::pair<int, int>, double> edges;
  for (size_t s = 0; s < corner_weights.size();) {
    size_t e = s;
    double w = 0.0;
    while (e < corner_weights.size() && corner_weights[e].first == corner_weights[s].first) {
      w += corner_weights[e].second;
      ++e;
    }
    edges[corner_weights[s].first] = std::max(w, 0.0);
    s = e;
  }
  return edges;
}

// A fan of three faces on edge 0-1 (non-manifold), whose halves the core
// code sums in a different order from the two-face case.
Mesh ThreeFacesOnOneEdge() {
  return MakeMesh({{0, 0, 0}, {1, 0, 0}, {0.3, 1, 0}, {0.6, -0.7, 0.2}, {0.4, 0.1, 1.3}},
                  {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
}

// Fans of four faces on edge 0-1 with random apexes: where the sum of an
// edge's four halves in face order differs in its last bits from their sum
// in ascending order, the weight is the latter, as the metrics' formula had
// it, whatever the order of the faces.
TEST(CotangentWeightsTest, ManyFacesOnAnEdgeSumInAscendingOrder) {
  std::mt19937 rng(1993);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int order_sensitive = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Eigen::Vector3d> vertices = {{0, 0, 0}, {1, 0, 0}};
    std::vector<Eigen::Vector3i> faces;
    for (int f = 0; f < 4; ++f) {
      vertices.emplace_back(uniform(rng), uniform(rng), uniform(rng));
      faces.emplace_back(f % 2 ? 1 : 0, f % 2 ? 0 : 1, 2 + f);
    }
    const Mesh mesh = MakeMesh(vertices, faces);
    // The halves at the apexes, summed in face order.
    double face_order = 0.0;
    std::vector<double> halves;
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3d a = mesh.vertices.col(faces[f][0]) - mesh.vertices.col(2 + f);
      const Eigen::Vector3d b = mesh.vertices.col(faces[f][1]) - mesh.vertices.col(2 + f);
      const double cross = a.cross(b).norm();
      halves.push_back(0.5 * (cross > 0.0 ? a.dot(b) / cross : 0.0));
      face_order += halves.back();
    }
    const double expected = PreviousMetricsWeights(mesh).at({0, 1});
    if (std::max(face_order, 0.0) != expected) ++order_sensitive;
    EXPECT_EQ(Weight(ComputeCotangentWeights(mesh), 0, 1), expected) << "trial " << trial;
  }
  EXPECT_GT(order_sensitive, 0);
}

// Symmetric, >= 0, one weight per undirected edge, and bit for bit the
// metrics' previous numbers (table 2's ARAP cells did not move), on
// procedural meshes with acute, right and obtuse corners.
TEST(CotangentWeightsTest, SymmetricAndEqualToThePreviousMetricsFormula) {
  const std::vector<Mesh> meshes = {MakeSphere(1.0, 13, 7), MakeBar(5, 1.0, 3),
                                    MakeCylinder(0.7, 3.0, 11, 4), MakeFork(0.5, 1.0, 2),
                                    ThreeFacesOnOneEdge()};
  for (size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    const CotangentWeights weights = ComputeCotangentWeights(mesh);
    const std::map<std::pair<int, int>, double> previous = PreviousMetricsWeights(mesh);
    ASSERT_EQ(weights.weight.size(), weights.adjacency.neighbors.size()) << "mesh " << m;
    ASSERT_EQ(static_cast<size_t>(NumEdges(weights)), previous.size()) << "mesh " << m;
    int obtuse = 0;
    for (int i = 0; i < mesh.num_vertices(); ++i) {
      for (int s = weights.adjacency.offsets[i]; s < weights.adjacency.offsets[i + 1]; ++s) {
        const int k = weights.adjacency.neighbors[s];
        const double w = weights.weight[s];
        EXPECT_EQ(w, Weight(weights, k, i)) << "mesh " << m << " edge " << i << "-" << k;
        EXPECT_GE(w, 0.0);
        EXPECT_EQ(w, previous.at({std::min(i, k), std::max(i, k)}))
            << "mesh " << m << " edge " << i << "-" << k;
        if (w == 0.0) ++obtuse;
      }
    }
    // The sphere's poles and the fork's squeezed column have clamped edges.
    if (m == 0 || m == 3) {
      EXPECT_GT(obtuse, 0) << "mesh " << m;
    }
  }
}

}  // namespace
}  // namespace msdeform
