// The ARAP solver lab (experiments/arap_lab.h) on a bent bar, where every
// variant must reach the reference's minimum: known gap reads from a known
// trace, every variant's final energy at E* to 1e-9, the 1e-6 gap never
// before the 1e-3 one, Anderson never above plain at the end (the full mesh's
// energy and the subspace's), and the options' checks.

#include "experiments/arap_lab.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "msdeform/core/procedural_meshes.h"

namespace msdeform {
namespace {

TEST(ArapLabTest, FirstIterationWithinReadsAKnownTrace) {
  const std::vector<double> energy = {2.0, 1.5, 1.0009, 1.0000009, 1.0};
  const std::vector<double> ms = {0.0, 1.0, 2.0, 3.0, 4.0};
  int iteration = -1;
  double at = -1.0;
  ASSERT_TRUE(FirstIterationWithin(energy, ms, 1.0, 1e-3, &iteration, &at));
  EXPECT_EQ(iteration, 2);
  EXPECT_EQ(at, 2.0);
  ASSERT_TRUE(FirstIterationWithin(energy, ms, 1.0, 1e-6, &iteration, &at));
  EXPECT_EQ(iteration, 3);
  EXPECT_EQ(at, 3.0);
  EXPECT_FALSE(FirstIterationWithin({2.0, 1.5}, {0.0, 1.0}, 1.0, 1e-3, &iteration, &at));
}

// A bar of 10 voxels, its left end fixed and its right end (the handle)
// turned about z through the right end, a quarter turn over 4 frames.
struct BentBar {
  Mesh mesh = MakeBar(10, 1.0, 2);
  HandleLayout layout;
  std::vector<HandleTransforms> path;
  BentBar() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double x = mesh.vertices(0, v);
      if (x < 0.01) layout.fixed.push_back(v);
      if (x > 9.99) layout.moveable.push_back(v);
    }
    for (int f = 1; f <= 4; ++f) {
      path.emplace_back(Eigen::Affine3d(
          Eigen::Translation3d(10.0, 0.0, 0.0) *
          Eigen::AngleAxisd(0.25 * f * M_PI / 2, Eigen::Vector3d::UnitZ()) *
          Eigen::Translation3d(-10.0, 0.0, 0.0)));
    }
  }
};

TEST(ArapLabTest, EveryFullArapVariantReachesTheMinimum) {
  const BentBar bar;
  ArapLabOptions options;
  options.measured_frames = {1, 4};
  options.anderson_windows = {3, 5};
  options.max_iterations = 5000;
  std::vector<ArapLabFrame> frames;
  std::string error;
  ASSERT_TRUE(MeasureFullArap(bar.mesh, bar.layout, bar.path, options, &frames, &error))
      << error;
  ASSERT_EQ(frames.size(), 3u * 2u);  // plain, anderson_3, anderson_5 x frames 1 and 4
  std::map<int, double> plain_final;
  for (const ArapLabFrame& f : frames) {
    SCOPED_TRACE(f.variant + " frame " + std::to_string(f.frame));
    EXPECT_TRUE(f.frame == 1 || f.frame == 4);
    EXPECT_GT(f.minimum, 1e-6);  // a real bend, not a rigid motion
    EXPECT_NEAR(f.final_energy / f.minimum, 1.0, 1e-9);
    EXPECT_LT(f.iterations, options.max_iterations);  // stopped at no decrease
    ASSERT_GE(f.loose_iterations, 0);
    ASSERT_GE(f.tight_iterations, f.loose_iterations);
    EXPECT_GE(f.tight_ms, f.loose_ms);
    EXPECT_LE(f.tight_iterations, f.iterations);
    if (f.variant == "plain") {
      plain_final[f.frame] = f.final_energy;
    } else {
      ASSERT_EQ(plain_final.count(f.frame), 1u);
      // Never ends above plain's energy (beyond rounding).
      EXPECT_LE(f.final_energy, plain_final[f.frame] * (1.0 + 1e-12));
    }
  }
}

// The subspace energy's variants (local/global plain and with each Anderson
// window, Gauss-Newton) minimise one energy over one subspace: each ends at
// the reference's minimum, and an accelerated run never ends above plain.
TEST(ArapLabTest, EverySubspaceVariantReachesTheMinimum) {
  const BentBar bar;
  ArapLabOptions options;
  options.measured_frames = {1, 4};
  options.anderson_windows = {3, 5};
  options.deformer.graph.nodes_per_scale = 20;
  options.deformer.static_nodes = 40;
  std::vector<ArapLabFrame> frames;
  std::string error;
  ASSERT_TRUE(MeasureSubspaceArap(bar.mesh, bar.layout, bar.path, options, &frames, &error))
      << error;
  // local_global, local_global_anderson_{3,5}, gauss_newton x frames 1 and 4.
  ASSERT_EQ(frames.size(), 4u * 2u);
  std::map<std::string, int> variants;
  std::map<int, double> plain_final;
  for (const ArapLabFrame& f : frames) {
    SCOPED_TRACE(f.variant + " frame " + std::to_string(f.frame));
    ++variants[f.variant];
    EXPECT_TRUE(f.frame == 1 || f.frame == 4);
    EXPECT_GT(f.minimum, 1e-6);  // a real bend, not a rigid motion
    EXPECT_NEAR(f.final_energy / f.minimum, 1.0, 1e-6);
    ASSERT_GE(f.tight_iterations, f.loose_iterations);
    if (f.variant == "local_global") {
      plain_final[f.frame] = f.final_energy;
    } else if (f.variant != "gauss_newton") {
      ASSERT_EQ(plain_final.count(f.frame), 1u);
      EXPECT_LE(f.final_energy, plain_final[f.frame] * (1.0 + 1e-12));
    }
  }
  EXPECT_EQ(variants, (std::map<std::string, int>{{"local_global", 2},
                                                  {"local_global_anderson_3", 2},
                                                  {"local_global_anderson_5", 2},
                                                  {"gauss_newton", 2}}));
}

TEST(ArapLabTest, FramesOutsideTheDragAreLeftOut) {
  const BentBar bar;
  ArapLabOptions options;
  options.measured_frames = {2, 30};
  options.anderson_windows = {5};
  std::vector<ArapLabFrame> frames;
  std::string error;
  ASSERT_TRUE(MeasureFullArap(bar.mesh, bar.layout, bar.path, options, &frames, &error))
      << error;
  ASSERT_EQ(frames.size(), 2u);
  for (const ArapLabFrame& f : frames) EXPECT_EQ(f.frame, 2);
  options.measured_frames = {30};
  EXPECT_FALSE(MeasureFullArap(bar.mesh, bar.layout, bar.path, options, &frames, &error));
  EXPECT_NE(error.find("no measured frame"), std::string::npos) << error;
}

TEST(ArapLabTest, OptionsNameTheBadField) {
  ArapLabOptions options;
  options.scenario_dir = "scenarios";
  options.out_dir = "out";
  std::string error;
  EXPECT_TRUE(options.Check(&error)) << error;
  options.anderson_windows = {0};
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("anderson_windows"), std::string::npos) << error;
  options.anderson_windows = {5};
  options.measured_frames = {0};
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("measured_frames"), std::string::npos) << error;
  options.measured_frames = {1};
  options.full_arap = false;
  options.subspace = false;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_NE(error.find("nothing to measure"), std::string::npos) << error;
}

}  // namespace
}  // namespace msdeform
