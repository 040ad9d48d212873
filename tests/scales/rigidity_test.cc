#include "msdeform/scales/rigidity.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "msdeform/core/lattice.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/scales/polar_decomposition.h"
#include "tests/core/lattice_test_util.h"

namespace msdeform {
namespace {

Eigen::Matrix3d RandomRotation(std::mt19937* rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(*rng), normal(*rng), normal(*rng), normal(*rng));
  return q.normalized().toRotationMatrix();
}

// max |a - b| over all entries (a plain loop: Eigen's vectorised max
// reduction trips GCC 12's -Wmaybe-uninitialized with AVX-512).
template <typename A, typename B>
double MaxAbsDifference(const A& a, const B& b) {
  EXPECT_EQ(a.size(), b.size());
  double max = 0.0;
  for (Eigen::Index k = 0; k < a.size(); ++k) {
    max = std::max(max, std::abs(a.data()[k] - b.data()[k]));
  }
  return max;
}

// ---------------------------------------------------------------------------
// Polar decomposition.

void ExpectProperRotation(const Eigen::Matrix3d& r) {
  EXPECT_TRUE((r.transpose() * r).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

TEST(PolarDecompositionTest, RandomMatricesMatchSvd) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  int compared = 0, negative_determinants = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix3d a;
    for (int k = 0; k < 9; ++k) a.data()[k] = uniform(rng);
    // The SO(3) answer is ill-conditioned when s2 + sign(det) s3 is small
    // (e.g. s2 = s3 with det < 0); such matrices have no well-defined answer.
    const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3d>(a).singularValues();
    const double sign = a.determinant() < 0.0 ? -1.0 : 1.0;
    if (s[1] + sign * s[2] < 0.05 * s[0]) continue;
    ++compared;
    negative_determinants += sign < 0.0;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    const int iterations = ExtractRotation(a, 2000, 1e-14, &q);
    EXPECT_LT(iterations, 2000) << "no convergence for\n" << a;
    const Eigen::Matrix3d expected = RotationBySvd(a);
    ExpectProperRotation(expected);
    ExpectProperRotation(q.toRotationMatrix());
    EXPECT_LT((q.toRotationMatrix() - expected).norm(), 1e-9) << a;
  }
  EXPECT_GT(compared, 1500);
  EXPECT_GT(negative_determinants, 500);
}

TEST(PolarDecompositionTest, NearSingularMatricesMatchSvd) {
  // A = U diag(1, 0.5, e) V^T with U, V rotations: for either sign of e the
  // rotation in SO(3) maximising tr(R^T A) is U V^T.
  std::mt19937 rng(11);
  for (double third : {1e-3, 1e-6, 1e-10, 0.0, -1e-10, -1e-6, -1e-3}) {
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::Matrix3d u = RandomRotation(&rng), v = RandomRotation(&rng);
      const Eigen::Matrix3d a = u * Eigen::Vector3d(1.0, 0.5, third).asDiagonal() * v.transpose();
      Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
      ExtractRotation(a, 2000, 1e-14, &q);
      EXPECT_LT((q.toRotationMatrix() - u * v.transpose()).norm(), 1e-9) << third;
      EXPECT_LT((RotationBySvd(a) - u * v.transpose()).norm(), 1e-9) << third;
    }
  }
}

TEST(PolarDecompositionTest, WarmStartConvergesFasterThanColdStart) {
  std::mt19937 rng(13);
  int warm_total = 0, cold_total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Matrix3d u = RandomRotation(&rng), v = RandomRotation(&rng);
    const Eigen::Matrix3d a = u * Eigen::Vector3d(1.0, 0.8, 0.6).asDiagonal() * v.transpose();
    const Eigen::Matrix3d expected = u * v.transpose();
    // Warm start: the answer turned by 0.01 rad, as between two steps.
    const Eigen::Vector3d axis = RandomRotation(&rng).col(0);
    Eigen::Quaterniond warm(Eigen::AngleAxisd(0.01, axis) * expected);
    Eigen::Quaterniond cold = Eigen::Quaterniond::Identity();
    const int warm_iterations = ExtractRotation(a, 200, 1e-10, &warm);
    const int cold_iterations = ExtractRotation(a, 200, 1e-10, &cold);
    EXPECT_LE(warm_iterations, 25);
    EXPECT_LT((warm.toRotationMatrix() - expected).norm(), 1e-9);
    EXPECT_LT((cold.toRotationMatrix() - expected).norm(), 1e-9);
    warm_total += warm_iterations;
    cold_total += cold_iterations;
  }
  EXPECT_LT(warm_total, cold_total);
}

TEST(PolarDecompositionTest, RotationAndZeroMatrixNeedNoUpdate) {
  std::mt19937 rng(17);
  const Eigen::Matrix3d r = RandomRotation(&rng);
  Eigen::Quaterniond q(r);
  EXPECT_EQ(ExtractRotation(2.0 * r, 20, 1e-12, &q), 0);
  Eigen::Quaterniond unchanged(r);
  EXPECT_EQ(ExtractRotation(Eigen::Matrix3d::Zero(), 20, 1e-12, &unchanged), 0);
  EXPECT_TRUE(unchanged.toRotationMatrix().isApprox(r));
}

// ---------------------------------------------------------------------------
// Options and input checks.

TEST(RigidityOptionsTest, CheckAcceptsDefaultsAndRejectsBadValues) {
  std::string error;
  EXPECT_TRUE(RigidityOptions().Check(&error)) << error;
  const std::vector<void (*)(RigidityOptions*)> breakers = {
      [](RigidityOptions* o) { o->num_steps = 0; },
      [](RigidityOptions* o) { o->time_step = 0.0; },
      [](RigidityOptions* o) { o->time_step = std::nan(""); },
      [](RigidityOptions* o) { o->external_stiffness = -0.1; },
      [](RigidityOptions* o) { o->external_stiffness = INFINITY; },
      [](RigidityOptions* o) { o->external_stiffness = 2.0; },  // k h^2 > 1
      [](RigidityOptions* o) { o->initial_speed = 0.0; },
      [](RigidityOptions* o) { o->damping = 1.0; },
      [](RigidityOptions* o) { o->damping = -0.1; },
      [](RigidityOptions* o) { o->region_half_width = 0; },
      // 2^31 - 1 overflowed the ring loop and hung.
      [](RigidityOptions* o) { o->region_half_width = kMaxRegionHalfWidth + 1; },
      [](RigidityOptions* o) { o->region_half_width = 2147483647; },
      [](RigidityOptions* o) { o->max_rotation_iterations = 0; },
      [](RigidityOptions* o) { o->rotation_tolerance = 0.0; },
  };
  for (std::size_t k = 0; k < breakers.size(); ++k) {
    RigidityOptions options;
    breakers[k](&options);
    error.clear();
    EXPECT_FALSE(options.Check(&error)) << "breaker " << k;
    EXPECT_FALSE(error.empty()) << "breaker " << k;
    RigidityEstimator estimator;
    EXPECT_FALSE(estimator.Init(BuildTestLattice(MakeBar(4)), options, &error)) << "breaker " << k;
  }
}

TEST(RigidityTest, ParticlesOfVerticesAreUniqueAndChecked) {
  const Mesh bar = MakeBar(4);
  const Lattice lattice = BuildTestLattice(bar);
  std::vector<int> particles;
  std::string error;
  ASSERT_TRUE(ParticlesOfVertices(lattice, {0, 0, 1, 2}, &particles, &error)) << error;
  std::vector<int> expected = {lattice.particle_of_vertex(0), lattice.particle_of_vertex(1),
                               lattice.particle_of_vertex(2)};
  std::sort(expected.begin(), expected.end());
  expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
  EXPECT_EQ(particles, expected);
  EXPECT_FALSE(ParticlesOfVertices(lattice, {0, bar.num_vertices()}, &particles, &error));
  EXPECT_NE(error.find(std::to_string(bar.num_vertices())), std::string::npos) << error;
  EXPECT_FALSE(ParticlesOfVertices(lattice, {-1}, &particles, &error));
}

TEST(RigidityTest, HandleGroupsOfParticlesFollowOneGroupAndYieldToFixed) {
  const Mesh bar = MakeBar(4, 1.0, 4);
  const Lattice lattice = BuildTestLattice(bar, /*cell_width=*/1.0);  // 16+ vertices a cell
  // a, b and a third vertex (fixed below) of one cell, and c of another.
  std::vector<std::vector<int>> of_particle(lattice.num_particles());
  for (int v = 0; v < bar.num_vertices(); ++v) {
    of_particle[lattice.particle_of_vertex(v)].push_back(v);
  }
  const auto crowded = std::find_if(of_particle.begin(), of_particle.end(),
                                    [](const std::vector<int>& list) { return list.size() >= 3; });
  ASSERT_NE(crowded, of_particle.end());
  const int a = (*crowded)[0], b = (*crowded)[1];
  const int c = of_particle[crowded == of_particle.begin() ? 1 : 0].empty()
                    ? -1
                    : of_particle[crowded == of_particle.begin() ? 1 : 0][0];
  ASSERT_GE(c, 0);
  std::vector<int> group;
  std::string error;
  HandleLayout layout;
  layout.moveable = {a, b, c};
  std::sort(layout.moveable.begin(), layout.moveable.end());
  for (int v : layout.moveable) layout.group.push_back(v == a ? 0 : 1);  // a alone in group 0
  // a and b share a cell but not a group: refused, naming both.
  EXPECT_FALSE(HandleGroupOfParticles(lattice, layout, &group, &error));
  EXPECT_NE(error.find("a lattice cell holds vertices of handle groups"), std::string::npos)
      << error;
  // The shared cell also holding a fixed vertex stays fixed: no conflict; but
  // then group 0 (a alone) has no cell that moves.
  for (int v = 0; v < bar.num_vertices(); ++v) {
    if (v != a && v != b && lattice.particle_of_vertex(v) == lattice.particle_of_vertex(a)) {
      layout.fixed = {v};
      break;
    }
  }
  ASSERT_EQ(layout.fixed.size(), 1u);
  EXPECT_FALSE(HandleGroupOfParticles(lattice, layout, &group, &error));
  EXPECT_EQ(error, "every lattice cell of handle group 0 also holds a fixed vertex: that handle "
                   "cannot move; separate the handles");
  // One group: it moves by c's cell; the shared cell is fixed.
  layout.group.clear();
  ASSERT_TRUE(HandleGroupOfParticles(lattice, layout, &group, &error)) << error;
  EXPECT_EQ(group[lattice.particle_of_vertex(a)], kFixedParticle);
  EXPECT_EQ(group[lattice.particle_of_vertex(c)], 0);
}

TEST(RigidityTest, EstimateRejectsBadHandles) {
  const Lattice lattice = BuildTestLattice(MakeBar(4));
  RigidityEstimator estimator;
  std::string error;
  ASSERT_TRUE(estimator.Init(lattice, RigidityOptions(), &error)) << error;
  RigidityEstimate estimate;
  const int n = lattice.num_particles();
  EXPECT_FALSE(estimator.Estimate({0}, {}, &estimate, &error));
  EXPECT_FALSE(estimator.Estimate({n}, {1}, &estimate, &error));
  EXPECT_FALSE(estimator.Estimate({0}, {-1}, &estimate, &error));
  // Every moveable particle also fixed: nothing moves.
  EXPECT_FALSE(estimator.Estimate({0, 1}, {1}, &estimate, &error));
  EXPECT_NE(error.find("does not move"), std::string::npos) << error;
  EXPECT_TRUE(estimator.Estimate({0}, {1}, &estimate, &error)) << error;
}

// ---------------------------------------------------------------------------
// Shape matching.

class RigidMotionTest : public testing::TestWithParam<std::tuple<RegionSummation, int>> {};

TEST_P(RigidMotionTest, GoalsOfARigidMotionAreTheMovedPositions) {
  // The comb has surface cells with few L-neighbours (thin teeth) and an
  // interior; a rigid motion must still be matched exactly by every region.
  // (Subdivided finely enough that the surface cells close the solid.)
  RigidityOptions options;
  options.region_summation = std::get<0>(GetParam());
  options.region_half_width = std::get<1>(GetParam());
  options.max_rotation_iterations = 500;
  options.rotation_tolerance = 1e-13;
  for (const Mesh& mesh : {MakeComb(4, 6, 1.0, 6), MakeBar(10, 1.0, 4)}) {
    const Lattice lattice = BuildTestLattice(mesh);
    RigidityEstimator estimator;
    std::string error;
    ASSERT_TRUE(estimator.Init(lattice, options, &error)) << error;
    if (options.region_summation == RegionSummation::kBox) {
      EXPECT_GT(estimator.num_box_particles(), 0);
    }
    const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(1.2, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
    const Eigen::Vector3d translation(3.0, -1.0, 7.0);
    const Eigen::Matrix3Xd moved =
        (rotation * lattice.rest_positions()).colwise() + translation;
    Eigen::Matrix3Xd goals;
    estimator.ComputeGoals(moved, &goals);
    EXPECT_LT(MaxAbsDifference(goals, moved), 1e-9 * lattice.cell_width());
    // And a non-rigid motion is not matched exactly (the check can fail).
    Eigen::Matrix3Xd stretched = lattice.rest_positions();
    stretched.row(0) *= 1.5;
    estimator.ComputeGoals(stretched, &goals);
    EXPECT_GT(MaxAbsDifference(goals, stretched), 1e-3 * lattice.cell_width());

    // Warm starts carry the rotations over calls (methods/fastlsm.h): with
    // one polar update a call, a cold start misses the 1.2 rad rotation, and
    // repeated warm-started calls reach it.
    RigidityOptions one_update = options;
    one_update.max_rotation_iterations = 1;
    RigidityEstimator stepwise;
    ASSERT_TRUE(stepwise.Init(lattice, one_update, &error)) << error;
    stepwise.ComputeGoals(moved, &goals);
    EXPECT_GT(MaxAbsDifference(goals, moved), 1e-3 * lattice.cell_width());
    for (int call = 0; call < 100; ++call) stepwise.ComputeGoals(moved, &goals, true);
    EXPECT_LT(MaxAbsDifference(goals, moved), 1e-9 * lattice.cell_width());
  }
}

INSTANTIATE_TEST_SUITE_P(
    SummationsAndHalfWidths, RigidMotionTest,
    testing::Combine(testing::Values(RegionSummation::kPerRegion, RegionSummation::kBox),
                     testing::Values(1, 2)));

TEST(RigidityTest, RegionsAreRingsOfTheAdjacency) {
  const Lattice lattice = BuildTestLattice(MakeComb(3, 4));
  RigidityOptions options;
  options.region_half_width = 1;
  RigidityEstimator estimator;
  std::string error;
  ASSERT_TRUE(estimator.Init(lattice, options, &error)) << error;
  const CompressedLists& adjacency = lattice.particle_adjacency();
  for (int i = 0; i < lattice.num_particles(); ++i) {
    std::vector<int> expected(adjacency.begin(i), adjacency.end(i));
    expected.push_back(i);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(std::vector<int>(estimator.regions().begin(i), estimator.regions().end(i)),
              expected);
  }
  options.region_half_width = 2;
  ASSERT_TRUE(estimator.Init(lattice, options, &error)) << error;
  for (int i = 0; i < lattice.num_particles(); ++i) {
    std::set<int> expected = {i};
    for (const int* j = adjacency.begin(i); j != adjacency.end(i); ++j) {
      expected.insert(*j);
      expected.insert(adjacency.begin(*j), adjacency.end(*j));
    }
    EXPECT_EQ(std::vector<int>(estimator.regions().begin(i), estimator.regions().end(i)),
              std::vector<int>(expected.begin(), expected.end()));
  }
}

// ---------------------------------------------------------------------------
// Rigidity of a bar fixed at one end and kicked at the other.

// The paper's estimate: S steps of lattice shape matching after a kick.
RigidityOptions PaperOptions() {
  RigidityOptions options;
  options.model = RigidityModel::kShapeMatching;
  return options;
}

struct BarSetup {
  // A solid bar: 12 voxels along x, w = diag / 48 = voxel / 4, vertices a
  // quarter voxel apart so that the surface cells close (49 x 5 x 5 cells).
  static constexpr int kLength = 12;
  Mesh mesh = MakeBar(kLength, 1.0, 4);
  Lattice lattice = BuildTestLattice(mesh);
  std::vector<int> fixed, moveable;  // particles

  BarSetup() {
    std::vector<int> fixed_vertices, moveable_vertices;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.vertices(0, v) < 1.0) fixed_vertices.push_back(v);
      if (mesh.vertices(0, v) > kLength - 1.0) moveable_vertices.push_back(v);
    }
    std::string error;
    EXPECT_TRUE(ParticlesOfVertices(lattice, fixed_vertices, &fixed, &error));
    EXPECT_TRUE(ParticlesOfVertices(lattice, moveable_vertices, &moveable, &error));
    EXPECT_GT(lattice.num_interior_particles(), 0);
  }

  // Mean e' over the particles in each unit slice along x.
  std::vector<double> SliceMeans(const Eigen::VectorXd& relative_extent) const {
    std::vector<double> sum(kLength, 0.0);
    std::vector<int> count(kLength, 0);
    for (int p = 0; p < lattice.num_particles(); ++p) {
      const int slice = std::clamp(static_cast<int>(std::floor(lattice.rest_positions()(0, p))),
                                   0, kLength - 1);
      sum[slice] += relative_extent[p];
      ++count[slice];
    }
    for (int s = 0; s < kLength; ++s) sum[s] /= count[s];
    return sum;
  }

  RigidityEstimate Estimate(const RigidityOptions& options) const {
    RigidityEstimate estimate;
    std::string error;
    EXPECT_TRUE(EstimateRigidity(lattice, fixed, moveable, options, &estimate, &error))
        << error;
    return estimate;
  }
};

TEST(RigidityTest, BarExtentDecreasesAwayFromTheKickedEnd) {
  const BarSetup bar;
  for (RegionSummation summation : {RegionSummation::kPerRegion, RegionSummation::kBox}) {
    for (std::uint64_t seed : {1, 2, 3, 4, 5}) {
      RigidityOptions options = PaperOptions();
      options.seed = seed;
      options.region_summation = summation;
      const RigidityEstimate estimate = bar.Estimate(options);
      const std::vector<double> means = bar.SliceMeans(estimate.relative_extent);
      // Monotone from the kicked end (slice 11) to the fixed end (slice 0),
      // within a tolerance.
      for (int s = 0; s + 1 < BarSetup::kLength; ++s) {
        EXPECT_LE(means[s], means[s + 1] + 0.02) << "seed " << seed << " slice " << s;
      }
      EXPECT_GT(means.back(), 0.5) << "seed " << seed;
      EXPECT_LT(means.front(), 0.05) << "seed " << seed;
      for (int p : bar.fixed) {
        EXPECT_LT(estimate.relative_extent[p], 0.5) << "seed " << seed << " particle " << p;
      }
      double handle_max = 0.0;
      for (int p : bar.moveable) handle_max = std::max(handle_max, estimate.relative_extent[p]);
      EXPECT_DOUBLE_EQ(handle_max, 1.0);
      EXPECT_GT(estimate.handle_extent, 0.0);
    }
  }
}

TEST(RigidityTest, SameSeedSameResultOtherSeedSameRanking) {
  const BarSetup bar;
  RigidityOptions options = PaperOptions();
  options.seed = 42;
  const RigidityEstimate first = bar.Estimate(options);
  const RigidityEstimate again = bar.Estimate(options);
  EXPECT_EQ(first.relative_extent, again.relative_extent);  // bitwise
  EXPECT_EQ(first.initial_direction, again.initial_direction);

  auto far_near = [&](const RigidityEstimate& estimate) {
    const std::vector<double> means = bar.SliceMeans(estimate.relative_extent);
    const double far = std::accumulate(means.begin(), means.begin() + 6, 0.0) / 6.0;
    const double near = std::accumulate(means.begin() + 6, means.end(), 0.0) / 6.0;
    return std::make_pair(far, near);
  };
  const auto [far, near] = far_near(first);
  EXPECT_LT(far, near);
  for (std::uint64_t seed : {43, 1000, 123456789}) {
    options.seed = seed;
    const RigidityEstimate other = bar.Estimate(options);
    EXPECT_GT((other.initial_direction - first.initial_direction).norm(), 1e-3);
    EXPECT_NE(other.relative_extent, first.relative_extent);
    const auto [other_far, other_near] = far_near(other);
    EXPECT_LT(other_far, other_near) << "seed " << seed;
  }
}

TEST(RigidityTest, ThreadCountDoesNotChangeTheEstimate) {
  // The bar's 1,225 particles make five chunks of the per-particle loops.
  const BarSetup bar;
  ASSERT_GT(bar.lattice.num_particles(), 4 * 256);
  for (RigidityModel model : {RigidityModel::kShapeMatching, RigidityModel::kHarmonic}) {
    for (RegionSummation summation : {RegionSummation::kBox, RegionSummation::kPerRegion}) {
      RigidityOptions options = PaperOptions();
      options.model = model;
      options.region_summation = summation;
      RigidityEstimate serial;
      CompressedLists serial_regions;
      for (int threads : {1, 2, 3}) {
        RigidityEstimator estimator;
        RigidityEstimate estimate;
        std::string error;
        ASSERT_TRUE(estimator.Init(bar.lattice, options, &error, threads)) << error;
        ASSERT_TRUE(estimator.Estimate(bar.fixed, bar.moveable, &estimate, &error)) << error;
        if (threads == 1) {
          serial = estimate;
          serial_regions = estimator.regions();
          continue;
        }
        EXPECT_EQ(estimate.extent, serial.extent) << threads << " threads";  // bitwise
        EXPECT_EQ(estimate.rotation_iterations, serial.rotation_iterations);
        EXPECT_EQ(estimator.regions().offsets, serial_regions.offsets);
        EXPECT_EQ(estimator.regions().values, serial_regions.values);
      }
    }
  }
}

TEST(RigidityTest, BoxAndPerRegionSummationsAgree) {
  const BarSetup bar;
  for (int half_width : {1, 2}) {
    RigidityOptions options = PaperOptions();
    options.region_half_width = half_width;
    options.region_summation = RegionSummation::kPerRegion;
    const RigidityEstimate listed = bar.Estimate(options);
    options.region_summation = RegionSummation::kBox;
    const RigidityEstimate boxed = bar.Estimate(options);
    EXPECT_LT(MaxAbsDifference(listed.relative_extent, boxed.relative_extent), 1e-8);
  }
}

TEST(RigidityTest, RelativeExtentDoesNotDependOnMeshUnitsOrTimeStep) {
  const BarSetup bar;
  RigidityOptions options = PaperOptions();
  const RigidityEstimate reference = bar.Estimate(options);

  // The mesh scaled by 2^10 (exact in floating point): the same lattice in
  // other units.
  Mesh scaled = bar.mesh;
  scaled.vertices *= 1024.0;
  const Lattice scaled_lattice = BuildTestLattice(scaled);
  ASSERT_EQ(scaled_lattice.num_particles(), bar.lattice.num_particles());
  RigidityEstimate estimate;
  std::string error;
  ASSERT_TRUE(EstimateRigidity(scaled_lattice, bar.fixed, bar.moveable, options, &estimate,
                               &error))
      << error;
  EXPECT_LT(MaxAbsDifference(estimate.relative_extent, reference.relative_extent), 1e-9);
  EXPECT_NEAR(estimate.handle_extent, 1024.0 * reference.handle_extent,
              1e-9 * estimate.handle_extent);

  // h only sets the unit of time when k_ext h^2 is kept.
  options.time_step = 2.0;
  options.external_stiffness /= 4.0;
  estimate = bar.Estimate(options);
  EXPECT_LT(MaxAbsDifference(estimate.relative_extent, reference.relative_extent), 1e-9);

  // But k_ext h^2 itself matters (the check above can fail).
  options.external_stiffness *= 8.0;
  estimate = bar.Estimate(options);
  EXPECT_GT(MaxAbsDifference(estimate.relative_extent, reference.relative_extent), 1e-3);
}

TEST(RigidityTest, FixedParticlesArePinned) {
  // With every particle but the moveable ones fixed, only the goals within two
  // rings of the handle move (regions of pinned particles match exactly).
  const BarSetup bar;
  std::vector<int> fixed;
  for (int p = 0; p < bar.lattice.num_particles(); ++p) {
    if (!std::binary_search(bar.moveable.begin(), bar.moveable.end(), p)) fixed.push_back(p);
  }
  RigidityEstimate estimate;
  std::string error;
  ASSERT_TRUE(EstimateRigidity(bar.lattice, fixed, bar.moveable, PaperOptions(), &estimate,
                               &error))
      << error;
  for (int p = 0; p < bar.lattice.num_particles(); ++p) {
    if (bar.lattice.rest_positions()(0, p) < BarSetup::kLength - 2.0) {
      EXPECT_LT(estimate.extent[p], 1e-12 * bar.lattice.cell_width()) << p;
    }
  }
}

// ---------------------------------------------------------------------------
// The harmonic estimate (RigidityModel::kHarmonic, the default).

TEST(HarmonicRigidityTest, IsTheDiscreteHarmonicFieldBetweenTheHandles) {
  // The defining equations: u = 0 on fixed particles, 1 on moveable ones, and
  // every other particle at the mean of its adjacent particles.
  const BarSetup bar;
  const RigidityEstimate estimate = bar.Estimate(RigidityOptions());
  const Eigen::VectorXd& u = estimate.relative_extent;
  for (int p : bar.fixed) EXPECT_EQ(u[p], 0.0) << p;
  for (int p : bar.moveable) EXPECT_EQ(u[p], 1.0) << p;
  const CompressedLists& adjacency = bar.lattice.particle_adjacency();
  for (int p = 0; p < bar.lattice.num_particles(); ++p) {
    if (std::binary_search(bar.fixed.begin(), bar.fixed.end(), p) ||
        std::binary_search(bar.moveable.begin(), bar.moveable.end(), p)) {
      continue;
    }
    double mean = 0.0;
    for (const int* q = adjacency.begin(p); q != adjacency.end(p); ++q) mean += u[*q];
    mean /= adjacency.size(p);
    EXPECT_NEAR(u[p], mean, 1e-10) << p;
  }
  EXPECT_EQ(estimate.handle_extent, bar.lattice.cell_width());
}

TEST(HarmonicRigidityTest, FallsOffLinearlyAlongABar) {
  // A bar fixed at x < 1 and held at x > 11: away from its ends, where the
  // pinned surface cells meet free interior ones, the field of a long
  // prism is the 1D one, linear in x. Not 1 / distance: the middle of the
  // bar is half-way.
  const BarSetup bar;
  const std::vector<double> means = bar.SliceMeans(bar.Estimate(RigidityOptions()).relative_extent);
  for (int s = 0; s + 1 < BarSetup::kLength; ++s) EXPECT_LT(means[s], means[s + 1]) << s;
  // Slopes of the inner slices (2..9) agree within 10% with their mean.
  const double slope = (means[9] - means[2]) / 7.0;
  EXPECT_NEAR(slope, 0.1, 0.01);  // 1 over the 10 units between the handles
  for (int s = 2; s < 9; ++s) EXPECT_NEAR(means[s + 1] - means[s], slope, 0.1 * slope) << s;
  EXPECT_NEAR(means[5] + means[6], 1.0, 0.05);  // symmetric about the middle
}

TEST(HarmonicRigidityTest, NeedsNoSeedAndNoUnits) {
  const BarSetup bar;
  RigidityOptions options;
  const RigidityEstimate reference = bar.Estimate(options);
  options.seed = 12345;
  EXPECT_EQ(bar.Estimate(options).relative_extent, reference.relative_extent);  // bitwise
  Mesh scaled = bar.mesh;
  scaled.vertices *= 1024.0;
  RigidityEstimate estimate;
  std::string error;
  ASSERT_TRUE(EstimateRigidity(BuildTestLattice(scaled), bar.fixed, bar.moveable, options,
                               &estimate, &error))
      << error;
  EXPECT_LT(MaxAbsDifference(estimate.relative_extent, reference.relative_extent), 1e-12);
}

TEST(HarmonicRigidityTest, WithoutAFixedHandleEverythingMovesAndOtherPiecesStay) {
  // Two bars: the handle on the first and nothing fixed. The first moves as a
  // whole (u = 1); nothing moves the second (u = 0).
  const Mesh mesh = MakeTwoBars(8, 2, 1.0, 4);
  const Lattice lattice = BuildTestLattice(mesh);
  std::vector<int> handle_vertices;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices(0, v) > 7.0 && mesh.vertices(1, v) < 1.0) handle_vertices.push_back(v);
  }
  std::vector<int> moveable;
  std::string error;
  ASSERT_TRUE(ParticlesOfVertices(lattice, handle_vertices, &moveable, &error)) << error;
  RigidityEstimate estimate;
  ASSERT_TRUE(EstimateRigidity(lattice, {}, moveable, RigidityOptions(), &estimate, &error))
      << error;
  int first = 0, second = 0;
  for (int p = 0; p < lattice.num_particles(); ++p) {
    if (lattice.rest_positions()(1, p) < 1.0) {
      EXPECT_NEAR(estimate.relative_extent[p], 1.0, 1e-12) << p;
      ++first;
    } else if (lattice.rest_positions()(1, p) > 3.0) {
      EXPECT_EQ(estimate.relative_extent[p], 0.0) << p;
      ++second;
    }
  }
  EXPECT_GT(first, 0);
  EXPECT_GT(second, 0);
}

TEST(HarmonicRigidityTest, ParsesItsName) {
  RigidityModel model = RigidityModel::kHarmonic;
  EXPECT_TRUE(ParseRigidityModel("paper", &model));
  EXPECT_EQ(model, RigidityModel::kShapeMatching);
  EXPECT_TRUE(ParseRigidityModel("harmonic", &model));
  EXPECT_EQ(model, RigidityModel::kHarmonic);
  EXPECT_FALSE(ParseRigidityModel("lsm", &model));
}

}  // namespace
}  // namespace msdeform
