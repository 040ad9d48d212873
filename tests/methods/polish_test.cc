// Polish on release (methods/polish.h) with known answers: a rigid motion
// stays exact, a converged full_arap result does not move, a multi-scale
// result's energy goes down and never up, the constraints end exactly at
// their targets, the budgets and the cancel flag are obeyed.

#include "msdeform/methods/polish.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "msdeform/core/metrics.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

Eigen::Affine3d SomeRigidMotion() {
  return Eigen::Translation3d(0.3, -1.2, 2.0) *
         Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized());
}

// A quarter turn of the handle end about the z axis through the bar's end.
Eigen::Affine3d Bend(double length) {
  return Eigen::Translation3d(length, 0.0, 0.0) *
         Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()) *
         Eigen::Translation3d(-length, 0.0, 0.0);
}

double Energy(const Mesh& rest, const Eigen::Matrix3Xd& deformed) {
  return NormalisedArapEnergy(ArapEnergyPerVertex(rest, deformed));
}

// `name` dragged to `transform` in `frames` steps on the bar; its vertices.
Eigen::Matrix3Xd DragMethod(const std::string& name, const BarEdit& bar,
                            const Eigen::Affine3d& transform, int frames) {
  std::string error;
  std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
  EXPECT_NE(method, nullptr) << error;
  MethodOptions options;
  options.deformer = OptionsFor(Method::kMultiScale);
  EXPECT_TRUE(method->Precompute(bar.mesh, options, &error)) << error;
  EXPECT_TRUE(method->SetHandles(bar.layout, &error)) << error;
  const Eigen::AngleAxisd turn(transform.rotation());
  for (int f = 1; f <= frames; ++f) {
    const double s = static_cast<double>(f) / frames;
    const Eigen::Affine3d step = Eigen::Translation3d(s * transform.translation()) *
                                 Eigen::AngleAxisd(s * turn.angle(), turn.axis());
    MethodStats stats;
    EXPECT_TRUE(method->Drag(step, &stats, &error)) << error;
  }
  return method->deformed_vertices();
}

TEST(PolishTest, RigidMotionOfEveryHandleStaysExact) {
  const BarEdit bar(8, 2);
  // Every constraint (the fixed end included) follows one rigid motion: the
  // fixed end is at rest, so the motion is the identity for it; use a layout
  // whose only constraint is the handle.
  HandleLayout layout;
  layout.moveable = bar.layout.moveable;
  const Eigen::Affine3d motion = SomeRigidMotion();
  Eigen::Matrix3Xd vertices = motion * bar.mesh.vertices;
  const Eigen::Matrix3Xd before = vertices;
  Polisher polisher;
  std::string error;
  ASSERT_TRUE(polisher.Setup(bar.mesh, layout, PolishOptions(), &error)) << error;
  const PolishReport report = polisher.Polish(motion, &vertices);
  EXPECT_LT(report.energy_before, 1e-24);
  EXPECT_LT(report.energy_after, 1e-24);
  EXPECT_LE((vertices - before).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_FALSE(report.cancelled);
}

TEST(PolishTest, ConvergedFullArapDoesNotMove) {
  const BarEdit bar(8, 2);
  const Eigen::Affine3d bend = Bend(8.0);
  const Eigen::Matrix3Xd converged = DragMethod("full_arap", bar, bend, 1);
  Eigen::Matrix3Xd vertices = converged;
  PolishReport report;
  std::string error;
  ASSERT_TRUE(PolishOnce(bar.mesh, bar.layout, bend, PolishOptions(), &vertices, &report, &error))
      << error;
  EXPECT_GT(report.energy_before, 1e-4);
  EXPECT_LE(report.energy_after, report.energy_before);
  EXPECT_LE(report.energy_before - report.energy_after, 1e-8 * report.energy_before);
  EXPECT_LE((vertices - converged).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(PolishTest, LowersTheEnergyOfAMultiscaleBendAndHoldsTheConstraints) {
  const BarEdit bar(12, 4);
  const Eigen::Affine3d bend = Bend(12.0);
  const Eigen::Matrix3Xd multiscale = DragMethod("multiscale", bar, bend, 3);
  const Eigen::Matrix3Xd converged = DragMethod("full_arap", bar, bend, 3);
  const double e_converged = Energy(bar.mesh, converged);

  std::string error;
  Polisher polisher;
  ASSERT_TRUE(polisher.Setup(bar.mesh, bar.layout, PolishOptions(), &error)) << error;
  // Budgets of 0, 1, 2, 5, 30 iterations: from where the constraints are
  // exact (energy_start: above the multi-scale frame's, whose handles are
  // soft) the energy never rises along them, and each report's energies are
  // the metric's.
  double previous = 0.0;
  for (int budget : {0, 1, 2, 5, 30}) {
    PolishOptions options;
    options.max_iterations = budget;
    ASSERT_TRUE(polisher.SetOptions(options, &error)) << error;
    Eigen::Matrix3Xd vertices = multiscale;
    const PolishReport report = polisher.Polish(bend, &vertices);
    EXPECT_NEAR(report.energy_before, Energy(bar.mesh, multiscale), 1e-12);
    EXPECT_NEAR(report.energy_after, Energy(bar.mesh, vertices), 1e-12);
    EXPECT_LE(report.iterations, budget);
    if (budget == 0) previous = report.energy_start;
    EXPECT_LE(report.energy_after, previous * (1.0 + 1e-12)) << budget << " iterations";
    previous = report.energy_after;
    // Exactly at the targets: the fixed end at rest, the handle at bend * rest.
    for (int v : bar.layout.fixed) EXPECT_EQ(vertices.col(v), bar.mesh.vertices.col(v));
    for (int v : bar.layout.moveable) {
      EXPECT_EQ(vertices.col(v), Eigen::Vector3d(bend * bar.mesh.vertices.col(v)));
    }
    if (budget == 0) {
      EXPECT_EQ(report.iterations, 0);
      EXPECT_NEAR(report.energy_start, Energy(bar.mesh, vertices), 1e-12);
      EXPECT_EQ(report.energy_after, report.energy_start);
      EXPECT_GE(report.energy_start, report.energy_before);
      EXPECT_GT(report.energy_before, 1.05 * e_converged);
    }
  }
  // 30 iterations take it within 2% of the converged energy, below the
  // multi-scale frame's.
  EXPECT_LT(previous, 1.02 * e_converged);
  EXPECT_LT(previous, Energy(bar.mesh, multiscale));
  EXPECT_GE(previous, e_converged * (1.0 - 1e-6));
}

TEST(PolishTest, CancelLeavesTheMeshAsGiven) {
  const BarEdit bar(12, 4);
  const Eigen::Affine3d bend = Bend(12.0);
  const Eigen::Matrix3Xd multiscale = DragMethod("multiscale", bar, bend, 2);
  Polisher polisher;
  std::string error;
  ASSERT_TRUE(polisher.Setup(bar.mesh, bar.layout, PolishOptions(), &error)) << error;
  std::atomic<bool> cancel(true);
  Eigen::Matrix3Xd vertices = multiscale;
  const PolishReport report = polisher.Polish(bend, &vertices, &cancel);
  EXPECT_TRUE(report.cancelled);
  EXPECT_EQ(report.iterations, 0);
  EXPECT_EQ(report.energy_after, report.energy_before);
  EXPECT_EQ(vertices, multiscale);
  // Not cancelled: the same polisher polishes.
  cancel = false;
  const PolishReport polished = polisher.Polish(bend, &vertices, &cancel);
  EXPECT_FALSE(polished.cancelled);
  EXPECT_LT(polished.energy_after, polished.energy_before);
}

// A budget shorter than the solve's own set-up (1 ns) refuses the first
// iteration: the mesh comes back at the start (constraints on their targets),
// not converged. (A budget of some milliseconds would make the answer depend
// on the machine's speed: a small bar can converge within it.)
TEST(PolishTest, TimeBudgetStopsBeforeAnIterationThatWouldOverrunIt) {
  const BarEdit bar(12, 4);
  const Eigen::Affine3d bend = Bend(12.0);
  const Eigen::Matrix3Xd multiscale = DragMethod("multiscale", bar, bend, 2);
  PolishOptions options;
  options.max_iterations = 1000000;
  options.relative_tolerance = 0.0;  // only the budgets stop it
  options.time_budget_ms = 1e-6;
  Eigen::Matrix3Xd vertices = multiscale;
  PolishReport report;
  std::string error;
  ASSERT_TRUE(PolishOnce(bar.mesh, bar.layout, bend, options, &vertices, &report, &error))
      << error;
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(report.iterations, 0);
  EXPECT_EQ(report.energy_after, report.energy_start);
}

TEST(PolishTest, BadOptionsAndLayoutsAreRefused) {
  const BarEdit bar(4, 1);
  std::string error;
  PolishOptions options;
  options.max_iterations = -1;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "max_iterations must be >= 0");
  options = PolishOptions();
  options.time_budget_ms = -1.0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "time_budget_ms must be finite and >= 0 (0: no limit)");
  options = PolishOptions();
  options.num_threads = 0;
  EXPECT_FALSE(options.Check(&error));
  EXPECT_EQ(error, "num_threads must be >= 1");
  Polisher polisher;
  EXPECT_FALSE(polisher.SetOptions(PolishOptions(), &error));
  HandleLayout empty;
  EXPECT_FALSE(polisher.Setup(bar.mesh, empty, PolishOptions(), &error));
  EXPECT_FALSE(polisher.ready());
}

}  // namespace
}  // namespace msdeform
