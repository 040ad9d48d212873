#include "apps/editor/camera.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace editor
}  // namespace msdeform
