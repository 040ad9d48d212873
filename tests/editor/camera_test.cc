#include "apps/editor/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace msdeform {
namespace editor {
namespace {

OrbitCamera FittedCamera(const Viewport& viewport) {
  OrbitCamera camera;
  camera.set_yaw_deg(30.0);
  camera.set_pitch_deg(-20.0);
  camera.Fit(Eigen::AlignedBox3d(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(3, 5, 4)), viewport);
  return camera;
}

TEST(OrbitCameraTest, ProjectIsTheMatricesAndTheViewportConvention) {
  const Viewport viewport{1280, 800};
  const OrbitCamera camera = FittedCamera(viewport);
  const Eigen::Matrix4d clip_from_world = camera.Projection(viewport) * camera.View();
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 1, 3), Eigen::Vector3d(2.5, 4, 2.2)}) {
    const Eigen::Vector4d clip = clip_from_world * p.homogeneous();
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    const Eigen::Vector3d pixel = camera.Project(p, viewport);
    EXPECT_NEAR(pixel.x(), (ndc.x() + 1) / 2 * 1280, 1e-9);
    EXPECT_NEAR(pixel.y(), (1 - ndc.y()) / 2 * 800, 1e-9);
    EXPECT_NEAR(pixel.z(), (ndc.z() + 1) / 2, 1e-12);
  }
  // The target is at the centre of the viewport.
  const Eigen::Vector3d centre = camera.Project(camera.target(), viewport);
  EXPECT_NEAR(centre.x(), 640.0, 1e-9);
  EXPECT_NEAR(centre.y(), 400.0, 1e-9);
}

TEST(OrbitCameraTest, FitShowsTheWholeBox) {
  const Viewport viewport{800, 600};
  const OrbitCamera camera = FittedCamera(viewport);
  const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(3, 5, 4));
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d pixel =
        camera.Project(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner)), viewport);
    EXPECT_GT(pixel.x(), 0.0);
    EXPECT_LT(pixel.x(), 800.0);
    EXPECT_GT(pixel.y(), 0.0);
    EXPECT_LT(pixel.y(), 600.0);
    EXPECT_GT(pixel.z(), 0.0);
    EXPECT_LT(pixel.z(), 1.0);
  }
}

TEST(OrbitCameraTest, ViewPlaneDeltaMovesThePointByThePixels) {
  const Viewport viewport{1280, 800};
  const OrbitCamera camera = FittedCamera(viewport);
  const Eigen::Vector3d at(0.5, 3.0, 2.5);
  const Eigen::Vector3d delta = camera.ViewPlaneDelta(Eigen::Vector2d(12.0, -7.0), at, viewport);
  const Eigen::Vector3d before = camera.Project(at, viewport);
  const Eigen::Vector3d after = camera.Project(at + delta, viewport);
  EXPECT_NEAR(after.x() - before.x(), 12.0, 1e-9);
  EXPECT_NEAR(after.y() - before.y(), -7.0, 1e-9);
  EXPECT_NEAR(after.z(), before.z(), 1e-12);  // in the view plane
}

TEST(OrbitCameraTest, EyeDepthInvertsTheDepthBuffer) {
  const Viewport viewport{640, 480};
  const OrbitCamera camera = FittedCamera(viewport);
  const Eigen::Vector3d p(2.0, 1.0, 3.5);
  const double window_depth = camera.Project(p, viewport).z();
  EXPECT_NEAR(camera.EyeDepth(window_depth), (p - camera.Eye()).dot(camera.Forward()), 1e-9);
}

TEST(OrbitCameraTest, FrameIsOrthonormalAndGesturesKeepTheTarget) {
  const Viewport viewport{640, 480};
  OrbitCamera camera = FittedCamera(viewport);
  const Eigen::Vector3d target = camera.target();
  const double distance = camera.distance();
  camera.Orbit(40.0, 1000.0);  // pitch is clamped short of the pole
  EXPECT_LE(camera.pitch_deg(), camera.options().max_pitch_deg);
  EXPECT_TRUE(camera.target().isApprox(target));
  EXPECT_NEAR((camera.Eye() - camera.target()).norm(), distance, 1e-9);
  EXPECT_NEAR(camera.Right().dot(camera.Up()), 0.0, 1e-12);
  EXPECT_NEAR(camera.Forward().dot(camera.Up()), 0.0, 1e-12);
  EXPECT_NEAR(camera.Up().norm(), 1.0, 1e-12);
  camera.Zoom(2.0);
  EXPECT_NEAR(camera.distance(), distance / (1.12 * 1.12), 1e-9);
  // Panning moves the target under the cursor: the old target moves by the pixels.
  const Eigen::Vector3d old_target = camera.target();
  camera.Pan(10.0, 5.0, viewport);
  const Eigen::Vector3d moved = camera.Project(old_target, viewport);
  EXPECT_NEAR(moved.x(), 320.0 + 10.0, 1e-9);
  EXPECT_NEAR(moved.y(), 240.0 + 5.0, 1e-9);
}

// Closed unit cubes (counter-clockwise faces seen from outside), the k-th
// with its lowest corner at (3 k, 0, 0); vertex 8 k + (x + 2 y + 4 z) is at
// corner (x, y, z) of cube k.
Mesh Cubes(int count) {
  Mesh mesh;
  mesh.vertices.resize(3, 8 * count);
  mesh.faces.resize(3, 12 * count);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (int k = 0; k < count; ++k) {
    for (int c = 0; c < 8; ++c) {
      mesh.vertices.col(8 * k + c) = Eigen::Vector3d(3 * k + (c & 1), (c >> 1) & 1, (c >> 2) & 1);
    }
    for (int q = 0; q < 6; ++q) {
      const int* v = quads[q];
      mesh.faces.col(12 * k + 2 * q) = Eigen::Vector3i(v[0], v[1], v[2]).array() + 8 * k;
      mesh.faces.col(12 * k + 2 * q + 1) = Eigen::Vector3i(v[0], v[2], v[3]).array() + 8 * k;
    }
  }
  return mesh;
}

TEST(FirstViewTest, FacingDirectionIsTheMeanNormalOfTheVertices) {
  const Mesh cube = Cubes(1);
  // Every face normal points out of the cube (the faces are consistent).
  for (int f = 0; f < cube.num_faces(); ++f) {
    const Eigen::Vector3d a = cube.vertices.col(cube.faces(0, f));
    const Eigen::Vector3d n = (cube.vertices.col(cube.faces(1, f)) - a)
                                  .cross(cube.vertices.col(cube.faces(2, f)) - a);
    EXPECT_GT(n.dot(a - Eigen::Vector3d(0.5, 0.5, 0.5)), 0.0) << "face " << f;
  }
  // The top face (y = 1): its side faces cancel in pairs.
  EXPECT_TRUE(FacingDirection(cube, {2, 3, 6, 7}).isApprox(Eigen::Vector3d(0, 1, 0), 1e-12));
  // One corner: the three faces around it count alike.
  EXPECT_TRUE(FacingDirection(cube, {7}).isApprox(Eigen::Vector3d(1, 1, 1).normalized(), 1e-12));
  // The whole closed surface, or nothing, faces no side.
  EXPECT_TRUE(FacingDirection(cube, {0, 1, 2, 3, 4, 5, 6, 7}).isZero(1e-12));
  EXPECT_TRUE(FacingDirection(cube, {}).isZero());
}

TEST(FirstViewTest, LookFromTurnsTheEyeToThatSide) {
  const Viewport viewport{1280, 800};
  OrbitCamera camera = FittedCamera(viewport);
  const double distance = camera.distance();
  const Eigen::Vector3d target = camera.target();
  const Eigen::Vector3d side = Eigen::Vector3d(1.0, 0.5, -2.0);
  camera.LookFrom(3.0 * side);
  EXPECT_TRUE((camera.Eye() - target).normalized().isApprox(side.normalized(), 1e-12));
  EXPECT_NEAR(camera.distance(), distance, 1e-12);
  EXPECT_TRUE(camera.target().isApprox(target));
  // Straight down: the pitch stops at -look_max_pitch_deg, the yaw is kept.
  camera.LookFrom(Eigen::Vector3d(0.0, -1.0, 0.0));
  EXPECT_NEAR(camera.pitch_deg(), -camera.options().look_max_pitch_deg, 1e-12);
  EXPECT_NEAR(camera.yaw_deg(), std::atan2(1.0, -2.0) * 180.0 / 3.14159265358979323846, 1e-9);
  // No side: nothing changes.
  camera.LookFrom(Eigen::Vector3d::Zero());
  EXPECT_NEAR(camera.pitch_deg(), -camera.options().look_max_pitch_deg, 1e-12);
}

TEST(FirstViewTest, AHandleFacingDownIsSeenFromItsSideOfTheMesh) {
  // Two cubes side by side along x; the handle is the second one's bottom
  // face: its normal is straight down, so the heading is the side of the
  // mesh it is on (+x), and the eye looks up at it from below.
  const Mesh cubes = Cubes(2);
  const std::vector<int> bottom = {8, 9, 12, 13};
  const Eigen::Vector3d direction = FirstViewDirection(cubes, bottom);
  EXPECT_NEAR(direction.norm(), 1.0, 1e-12);
  EXPECT_GT(direction.x(), 0.1);
  EXPECT_LT(direction.y(), -0.9);
  EXPECT_NEAR(direction.z(), 0.0, 1e-12);
  OrbitCamera camera;
  camera.LookFrom(direction);
  EXPECT_NEAR(camera.yaw_deg(), 90.0, 1e-9);
  EXPECT_NEAR(camera.pitch_deg(), -camera.options().look_max_pitch_deg, 1e-12);
  // The second cube's +z face: seen from +z, level.
  const Eigen::Vector3d front = FirstViewDirection(cubes, {12, 13, 14, 15});
  EXPECT_TRUE(front.isApprox(Eigen::Vector3d(0, 0, 1), 1e-12)) << front.transpose();
  // No handle: no preference.
  EXPECT_TRUE(FirstViewDirection(cubes, {}).isZero());
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
