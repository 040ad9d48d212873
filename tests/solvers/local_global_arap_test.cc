#include "msdeform/solvers/local_global_arap.h"

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/metrics.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/solvers/gauss_newton_solver.h"

namespace msdeform {
namespace {

// The vertices with x below `below` or above `above`.
std::vector<int> Ends(const Mesh& mesh, double below, double above) {
  std::vector<int> ends;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const double x = mesh.vertices(0, v);
    if (x < below || x > above) ends.push_back(v);
  }
  return ends;
}

Eigen::Matrix3Xd Targets(const Mesh& mesh, const std::vector<int>& vertices,
                         const Eigen::Affine3d& transform) {
  Eigen::Matrix3Xd targets(3, vertices.size());
  for (size_t j = 0; j < vertices.size(); ++j) {
    targets.col(j) = transform * mesh.vertices.col(vertices[j]);
  }
  return targets;
}

Eigen::Affine3d SomeRigidMotion() {
  return Eigen::Translation3d(0.3, -1.2, 2.0) *
         Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -1, 2).normalized());
}

// A bar of 8 voxels; the vertices of its left end held at rest and the right
// end's lifted by a quarter turn about the z axis through the right end.
struct BentBar {
  Mesh mesh = MakeBar(8, 1.0, 2);
  std::vector<int> left = Ends(mesh, 0.01, 1e9);
  std::vector<int> constrained = Ends(mesh, 0.01, 7.99);
  Eigen::Matrix3Xd Targets() const {
    const Eigen::Affine3d lift = Eigen::Translation3d(8.0, 0.0, 0.0) *
                                 Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                 Eigen::Translation3d(-8.0, 0.0, 0.0);
    Eigen::Matrix3Xd targets(3, constrained.size());
    for (size_t j = 0; j < constrained.size(); ++j) {
      const Eigen::Vector3d rest = mesh.vertices.col(constrained[j]);
      targets.col(j) = rest.x() < 0.01 ? rest : Eigen::Vector3d(lift * rest);
    }
    return targets;
  }
};

TEST(LocalGlobalArapTest, RigidMotionOfTheConstraintsIsReachedExactly) {
  const BentBar bar;
  const Eigen::Affine3d motion = SomeRigidMotion();
  LocalGlobalArapOptions options;
  LocalGlobalArap arap;
  std::string error;
  ASSERT_TRUE(arap.Setup(bar.mesh, bar.constrained, options, &error)) << error;
  Eigen::Matrix3Xd deformed = bar.mesh.vertices;
  const LocalGlobalArapSummary summary =
      arap.Solve(Targets(bar.mesh, bar.constrained, motion), &deformed);
  EXPECT_TRUE(summary.converged);
  const Eigen::Matrix3Xd expected = motion * bar.mesh.vertices;
  EXPECT_LT((deformed - expected).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT(summary.final_energy, 1e-18);
}

TEST(LocalGlobalArapTest, EnergyIsTheMetricsArapEnergy) {
  const Mesh mesh = MakeSphere(1.0, 12, 8);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  Eigen::Matrix3Xd deformed = mesh.vertices;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    deformed.col(v) = 1.3 * deformed.col(v) + Eigen::Vector3d(jitter(random), jitter(random),
                                                               jitter(random));
  }
  LocalGlobalArap arap;
  std::string error;
  ASSERT_TRUE(arap.Setup(mesh, {0}, LocalGlobalArapOptions(), &error)) << error;
  const double expected = NormalisedArapEnergy(ArapEnergyPerVertex(mesh, deformed));
  EXPECT_NEAR(arap.Energy(deformed), expected, 1e-12 * expected);
}

TEST(LocalGlobalArapTest, ConstraintsExactAndAndersonReachesThePlainMinimum) {
  const BentBar bar;
  const Eigen::Matrix3Xd targets = bar.Targets();
  LocalGlobalArapOptions plain_options;
  plain_options.anderson_window = 0;
  plain_options.relative_tolerance = 1e-12;
  plain_options.max_iterations = 100000;
  LocalGlobalArapOptions anderson_options = plain_options;
  anderson_options.anderson_window = 5;

  LocalGlobalArap plain, accelerated;
  std::string error;
  ASSERT_TRUE(plain.Setup(bar.mesh, bar.constrained, plain_options, &error)) << error;
  ASSERT_TRUE(accelerated.Setup(bar.mesh, bar.constrained, anderson_options, &error)) << error;
  Eigen::Matrix3Xd plain_result = bar.mesh.vertices, accelerated_result = bar.mesh.vertices;
  const LocalGlobalArapSummary plain_summary = plain.Solve(targets, &plain_result);
  const LocalGlobalArapSummary accelerated_summary =
      accelerated.Solve(targets, &accelerated_result);
  ASSERT_TRUE(plain_summary.converged);
  ASSERT_TRUE(accelerated_summary.converged);

  for (size_t j = 0; j < bar.constrained.size(); ++j) {
    EXPECT_EQ(plain_result.col(bar.constrained[j]), targets.col(j));
    EXPECT_EQ(accelerated_result.col(bar.constrained[j]), targets.col(j));
  }
  // One minimum, reached by both; the energy never rises along the way.
  EXPECT_NEAR(accelerated_summary.final_energy, plain_summary.final_energy,
              1e-6 * plain_summary.final_energy);
  EXPECT_LT((accelerated_result - plain_result).cwiseAbs().maxCoeff(), 1e-3);
  for (size_t k = 1; k < accelerated_summary.energy_trace.size(); ++k) {
    EXPECT_LE(accelerated_summary.energy_trace[k], accelerated_summary.energy_trace[k - 1]);
  }
  for (size_t k = 1; k < plain_summary.energy_trace.size(); ++k) {
    EXPECT_LE(plain_summary.energy_trace[k], plain_summary.energy_trace[k - 1] * (1 + 1e-12));
  }
  EXPECT_LT(accelerated_summary.iterations, plain_summary.iterations);
  // A bent bar is not a rigid motion: a positive energy, measured as metrics do.
  EXPECT_GT(accelerated_summary.final_energy, 1e-4);
  const double measured = NormalisedArapEnergy(ArapEnergyPerVertex(bar.mesh, accelerated_result));
  EXPECT_NEAR(accelerated_summary.final_energy, measured, 1e-9 * measured);
}

// CHOLMOD's supernodal factor solves the same global step as Eigen's
// simplicial one: a rigid motion is reached exactly, and the bent bar's
// iterations agree to rounding (energies to 1e-12; the stopping test may
// fall one iteration apart).
TEST(LocalGlobalArapTest, BothFactorizationsGiveTheSameIterations) {
  const BentBar bar;
  LocalGlobalArapOptions simplicial_options;
  LocalGlobalArapOptions cholmod_options;
  cholmod_options.factorization = LocalGlobalArapOptions::Factorization::kCholmod;
  LocalGlobalArap simplicial, cholmod;
  std::string error;
  if (!GaussNewtonHasCholmod()) {  // a build without CHOLMOD refuses the choice
    EXPECT_FALSE(cholmod.Setup(bar.mesh, bar.constrained, cholmod_options, &error));
    EXPECT_NE(error.find("factorization=cholmod"), std::string::npos) << error;
    return;
  }
  ASSERT_TRUE(simplicial.Setup(bar.mesh, bar.constrained, simplicial_options, &error)) << error;
  ASSERT_TRUE(cholmod.Setup(bar.mesh, bar.constrained, cholmod_options, &error)) << error;

  Eigen::Matrix3Xd moved = bar.mesh.vertices;
  const Eigen::Affine3d motion = SomeRigidMotion();
  ASSERT_TRUE(cholmod.Solve(Targets(bar.mesh, bar.constrained, motion), &moved).converged);
  EXPECT_LT((moved - motion * bar.mesh.vertices).cwiseAbs().maxCoeff(), 1e-9);

  Eigen::Matrix3Xd a = bar.mesh.vertices, b = bar.mesh.vertices;
  const LocalGlobalArapSummary sa = simplicial.Solve(bar.Targets(), &a);
  const LocalGlobalArapSummary sb = cholmod.Solve(bar.Targets(), &b);
  ASSERT_TRUE(sa.converged && sb.converged);
  EXPECT_NEAR(sa.iterations, sb.iterations, 1);
  EXPECT_NEAR(sa.final_energy, sb.final_energy, 1e-12 * sa.final_energy);
  EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(LocalGlobalArapTest, SameResultOnAnyNumberOfThreads) {
  // Large enough for the chunked loops to run in parallel.
  const Mesh mesh = MakeBar(60, 1.0, 10);
  ASSERT_GT(mesh.num_vertices(), 16384);
  const std::vector<int> constrained = Ends(mesh, 0.01, 59.99);
  Eigen::Matrix3Xd targets(3, constrained.size());
  for (size_t j = 0; j < constrained.size(); ++j) {
    const Eigen::Vector3d rest = mesh.vertices.col(constrained[j]);
    targets.col(j) = rest.x() < 0.01 ? rest : Eigen::Vector3d(rest + Eigen::Vector3d(0, 5, 0));
  }
  Eigen::Matrix3Xd results[2];
  for (int threads : {1, 2}) {
    LocalGlobalArapOptions options;
    options.num_threads = threads;
    options.max_iterations = 5;
    LocalGlobalArap arap;
    std::string error;
    ASSERT_TRUE(arap.Setup(mesh, constrained, options, &error)) << error;
    results[threads - 1] = mesh.vertices;
    arap.Solve(targets, &results[threads - 1]);
  }
  EXPECT_EQ(results[0], results[1]);
}

TEST(LocalGlobalArapTest, UnreachedComponentStaysWhereItIs) {
  const Mesh mesh = MakeTwoBars(4, 2, 1.0, 1);
  // The bars lie side by side along y (the first in 0 <= y <= 1, the second
  // from y = 3): constrain the first one's end at x = 0 only, so the second
  // is reached by no constraint.
  std::vector<int> constrained;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(1, v) < 2.0 && mesh.vertices(0, v) < 0.01) constrained.push_back(v);
  }
  ASSERT_FALSE(constrained.empty());
  LocalGlobalArap arap;
  std::string error;
  ASSERT_TRUE(arap.Setup(mesh, constrained, LocalGlobalArapOptions(), &error)) << error;
  EXPECT_LT(arap.num_free(), mesh.num_vertices() / 2);
  Eigen::Matrix3Xd deformed = mesh.vertices;
  const Eigen::Affine3d motion = SomeRigidMotion();
  arap.Solve(Targets(mesh, constrained, motion), &deformed);
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(1, v) > 2.0) {
      EXPECT_EQ(deformed.col(v), mesh.vertices.col(v));
    } else {
      EXPECT_LT((deformed.col(v) - motion * mesh.vertices.col(v)).norm(), 1e-9);
    }
  }
}

TEST(LocalGlobalArapTest, BadInputIsRefusedWithAMessage) {
  const Mesh mesh = MakeBar(2, 1.0, 1);
  LocalGlobalArap arap;
  std::string error;
  EXPECT_FALSE(arap.Setup(mesh, {3, 1}, LocalGlobalArapOptions(), &error));
  EXPECT_EQ(error, "constrained vertices must be sorted and unique");
  EXPECT_FALSE(arap.Setup(mesh, {mesh.num_vertices()}, LocalGlobalArapOptions(), &error));
  EXPECT_NE(error.find("is not a vertex"), std::string::npos) << error;
  LocalGlobalArapOptions options;
  options.relative_tolerance = -1.0;
  EXPECT_FALSE(arap.Setup(mesh, {0}, options, &error));
  EXPECT_EQ(error, "relative_tolerance must be finite and >= 0");
}

}  // namespace
}  // namespace msdeform
