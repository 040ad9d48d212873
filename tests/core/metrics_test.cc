#include "msdeform/core/metrics.h"

#include <cmath>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"


namespace msdeform {
namespace {

// A unit right triangle pair forming a square in the z = 0 plane, and a
// closed octahedron; both small enough to check by hand.
Mesh Square() {
  Mesh mesh;
  mesh.vertices.resize(3, 4);
  mesh.vertices << 0, 1, 1, 0,  //
      0, 0, 1, 1,               //
      0, 0, 0, 0;
  mesh.faces.resize(3, 2);
  mesh.faces << 0, 0,  //
      1, 2,            //
      2, 3;
  return mesh;
}

TEST(MetricsTest, ArapEnergyIsZeroForARigidMotion) {
  for (const Mesh& mesh : {Square(), MakeOctahedron()}) {
    Eigen::Affine3d motion = Eigen::Affine3d::Identity();
    motion.rotate(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -2, 0.5).normalized()));
    motion.pretranslate(Eigen::Vector3d(3, -1, 2));
    const ArapTerms terms = ArapEnergyPerVertex(mesh, motion * mesh.vertices);
    EXPECT_NEAR(NormalisedArapEnergy(terms), 0.0, 1e-20);
    EXPECT_GT(terms.normaliser.sum(), 0.0);
    EXPECT_NEAR(MeanEdgeStrain(mesh, motion * mesh.vertices), 0.0, 1e-12);
  }
}

TEST(MetricsTest, UniformScaleGivesTheHandValue) {
  // Scaling by s: the best rotation is I and every edge error is (s - 1) e,
  // so E / N = (s - 1)^2 and the strain is |s - 1|.
  for (const Mesh& mesh : {Square(), MakeOctahedron()}) {
    const double s = 1.1;
    const ArapTerms terms = ArapEnergyPerVertex(mesh, s * mesh.vertices);
    EXPECT_NEAR(NormalisedArapEnergy(terms), 0.01, 1e-12);
    EXPECT_NEAR(MeanEdgeStrain(mesh, s * mesh.vertices), 0.1, 1e-12);
  }
}

TEST(MetricsTest, SquareStretchedAlongXByHand) {
  // Square split along its diagonal 0-2. Both triangles are right isosceles:
  // the corners at 45 degrees have cot = 1, the right angles cot = 0. Edge
  // weights (half the sum of the opposite cots): boundary edges 1/2, the
  // diagonal 0. Stretching x by 2 at each vertex: the covariance of the two
  // boundary edges is diag(2, 1)/2 (positive, symmetric), so R = I and the
  // error is the x-edge stretched by 1: E = 2 vertices of each x edge x 1/2 x 1
  // summed over the 2 x edges = 2; N = 4 edges x 2 ends x 1/2 x 1 = 4.
  const Mesh mesh = Square();
  Eigen::Matrix3Xd stretched = mesh.vertices;
  stretched.row(0) *= 2.0;
  const ArapTerms terms = ArapEnergyPerVertex(mesh, stretched);
  EXPECT_NEAR(terms.normaliser.sum(), 4.0, 1e-12);
  EXPECT_NEAR(terms.energy.sum(), 2.0, 1e-12);
  EXPECT_NEAR(NormalisedArapEnergy(terms), 0.5, 1e-12);
  // Strain: x edges 1, y edges 0, the diagonal sqrt(5)/sqrt(2) - 1.
  EXPECT_NEAR(MeanEdgeStrain(mesh, stretched), (2.0 + std::sqrt(2.5) - 1.0) / 5.0, 1e-12);
  // Restricted to vertex 1 only: E_1 = 1/2 (edge 0-1), N_1 = 1.
  EXPECT_NEAR(NormalisedArapEnergy(terms, {1}), 0.5, 1e-12);
}

TEST(MetricsTest, HandleErrorAndDisplacement) {
  const Mesh mesh = MakeOctahedron();
  Eigen::Matrix3Xd deformed = mesh.vertices;
  deformed(0, 0) += 0.3;  // vertex 0 moves 0.3
  deformed(1, 2) += 0.4;  // vertex 2 moves 0.4
  const Displacement d = VertexDisplacement(mesh, deformed, {0, 2, 4});
  EXPECT_NEAR(d.mean, 0.7 / 3.0, 1e-12);
  EXPECT_NEAR(d.max, 0.4, 1e-12);
  EXPECT_EQ(VertexDisplacement(mesh, deformed, {}).max, 0.0);
  // The handle {0, 2} should have moved by (0.3, 0, 0): errors 0 and 0.5.
  Eigen::Affine3d target = Eigen::Affine3d::Identity();
  target.translation() << 0.3, 0, 0;
  EXPECT_NEAR(HandleRmsError(mesh, deformed, {0, 2}, target), std::sqrt(0.25 / 2.0), 1e-12);
}

TEST(MetricsTest, OrthogonalityError) {
  NodeTransforms transforms = NodeTransforms::Identity(3);
  transforms.rotation(1) = Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  transforms.rotation(2) = 2.0 * Eigen::Matrix3d::Identity();  // R^T R - I = 3 I, |.|_F = 3 sqrt(3)
  EXPECT_NEAR(OrthogonalityError(transforms, {0, 1}), 0.0, 1e-12);
  EXPECT_NEAR(OrthogonalityError(transforms, {0, 1, 2}), std::sqrt(27.0) / 3.0, 1e-12);
}

TEST(MetricsTest, VerticesNearFollowEdges) {
  const Mesh mesh = Square();  // edges 0-1, 1-2, 2-3, 3-0 (length 1) and 0-2 (sqrt 2)
  EXPECT_EQ(VerticesNear(mesh, {0}, 1.0), (std::vector<int>{1, 3}));
  EXPECT_EQ(VerticesNear(mesh, {0}, 1.5), (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(VerticesNear(mesh, {0}, 0.5).empty());
}

}  // namespace
}  // namespace msdeform
