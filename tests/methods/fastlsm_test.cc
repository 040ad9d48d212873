#include "msdeform/methods/fastlsm.h"

#include <string>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/method_options.h"

namespace msdeform {
namespace {

// A bar along x (8 x 1 x 1) with its last voxel as the handle, nothing fixed.
HandleLayout EndHandle(const Mesh& mesh) {
  HandleLayout layout;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(0, v) >= 7.0) layout.moveable.push_back(v);
  }
  return layout;
}

Eigen::Affine3d Translation(const Eigen::Vector3d& offset) {
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.translation() = offset;
  return motion;
}

// A translated handle with nothing fixed: the damped steps settle on the
// rigid translation of the whole bar (shape matching is exact for it). A
// coarse lattice (16 cells per diagonal, the bar 16 cells long) so that
// 5000 steps settle the bar's soft bending mode; on the default lattice (48
// cells long) it takes far longer.
TEST(FastLsmTest, TranslatedHandleWithNothingFixedSettlesOnTheTranslation) {
  const Mesh bar = MakeBar(8, 1.0, 2);
  MethodOptions options;
  options.deformer.lattice.cells_per_diagonal = 16.0;
  options.fastlsm.steps_per_frame = 1000;
  FastLsm method;
  std::string error;
  ASSERT_TRUE(method.Precompute(bar, options, &error)) << error;
  ASSERT_TRUE(method.SetHandles(EndHandle(bar), &error)) << error;
  const Eigen::Vector3d offset(0.0, 0.5, 1.0);
  for (int frame = 0; frame < 5; ++frame) {
    ASSERT_TRUE(method.Drag(Translation(offset), nullptr, &error)) << error;
  }
  const Eigen::Matrix3Xd expected = bar.vertices.colwise() + offset;
  // Shape matching's polar decompositions stop at 1e-6 rad per update
  // (RigidityOptions' rotation_tolerance): 1e-3 of the bar's length of 8.
  EXPECT_LT((method.deformed_vertices() - expected).cwiseAbs().maxCoeff(), 8e-3);
}

// One frame of few steps has not reached the far end yet: the steps per
// frame are the method's budget, and more of them get closer.
TEST(FastLsmTest, MoreStepsPerFrameGetCloserToTheRigidAnswer) {
  const Mesh bar = MakeBar(8, 1.0, 2);
  const Eigen::Vector3d offset(0.0, 0.0, 2.0);
  const Eigen::Matrix3Xd expected = bar.vertices.colwise() + offset;
  double previous = 1e300;
  for (int steps : {1, 5, 40}) {
    MethodOptions options;
    options.fastlsm.steps_per_frame = steps;
    FastLsm method;
    std::string error;
    ASSERT_TRUE(method.Precompute(bar, options, &error)) << error;
    ASSERT_TRUE(method.SetHandles(EndHandle(bar), &error)) << error;
    MethodStats stats;
    ASSERT_TRUE(method.Drag(Translation(offset), &stats, &error)) << error;
    EXPECT_EQ(stats.iterations, steps);
    const double distance = (method.deformed_vertices() - expected).colwise().norm().mean();
    EXPECT_LT(distance, previous) << steps << " steps";
    previous = distance;
  }
}

TEST(FastLsmTest, InvalidOptionsAndInseparableHandlesAreOneLineErrors) {
  const Mesh bar = MakeBar(8, 1.0, 2);
  std::string error;
  FastLsm method;
  MethodOptions options;
  options.fastlsm.steps_per_frame = 0;
  EXPECT_FALSE(method.Precompute(bar, options, &error));
  EXPECT_EQ(error, "fastlsm.steps_per_frame=0: expected an integer in 1..100000");
  options.fastlsm = FastLsmOptions();
  options.fastlsm.damping = 1.0;
  EXPECT_FALSE(method.Precompute(bar, options, &error));
  EXPECT_EQ(error, "fastlsm.damping=1: expected a number in [0, 1)");
  // One cell holds the whole bar, so the handle's cell also holds fixed
  // vertices and stays fixed: the handle cannot move.
  options.fastlsm = FastLsmOptions();
  options.deformer.lattice.cell_width = 100.0;
  ASSERT_TRUE(method.Precompute(bar, options, &error)) << error;
  HandleLayout shared;
  shared.moveable = {0};
  for (int v = 1; v < bar.num_vertices(); ++v) shared.fixed.push_back(v);
  EXPECT_FALSE(method.SetHandles(shared, &error));
  EXPECT_NE(error.find("cannot move"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
