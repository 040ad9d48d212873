// The subspace ARAP energy (solvers/subspace_arap.h) and its local/global
// solver (solvers/arap_solver.h) against answers known without the reduced
// algebra: a full-mesh evaluation written from the energy's definition (skin
// every vertex, set the exact constraints, then per rotation cluster the best
// rotation by SVD and the cotangent-weighted spokes), a rigid edit whose
// optimum lies inside the subspace (energy 0, every vertex at H * rest), the
// solver's energy never rising, and the options' errors.

#include "msdeform/solvers/subspace_arap_terms.h"
#include "msdeform/solvers/subspace_arap.h"

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gflags/gflags.h>
#include <gtest/gtest.h>

#include "apps/flags/deformer_flags.h"
#include "msdeform/core/metrics.h"
#include "msdeform/solvers/arap_solver.h"
#include "tests/scales/subspace_arap_test_util.h"

namespace msdeform {
namespace {

// The reduced energy at random transforms and a random handle equals the
// full-mesh evaluation to 1e-12 relative, for every cluster option and both
// constraint kinds, on the handle layouts a graph method sets (one mesh with a still
// second component) and with hand-made node classes that mix Totally Free,
// Half Free and Fixed nodes (and a length unit that is not the diagonal).
TEST(SubspaceArapTest, ReducedEnergyEqualsTheFullMeshEvaluation) {
  const BarEdit bar(12, 4);
  const TwoBarEdit two_bars(/*fix_bar0=*/true);
  std::mt19937 rng(29);
  for (const auto& [mesh, handles] :
       {std::make_pair(&bar.mesh, &bar.layout), std::make_pair(&two_bars.mesh, &two_bars.layout)}) {
    for (Method method : {Method::kMultiScale, Method::kStatic}) {
      for (RotationClusters clusters : kAllClusters) {
        for (ArapConstraints constraints : kAllConstraints) {
          const DeformerOptions options = ArapOptionsFor(method, clusters, constraints);
          const std::unique_ptr<GraphMethod> deformer = MakeDeformer(*mesh, options, *handles);
          const HandleSetup& setup = *deformer->setup();
          const double diagonal = deformer->diagonal();
          const std::vector<NodeClass> mixed = MixedClasses(setup.graph().num_nodes());
          const std::shared_ptr<const SubspaceArap> hand =
              BuildWithClasses(setup, mixed, 0.37 * diagonal, options.arap);

          struct Case {
            const SubspaceArap* arap;
            const std::vector<NodeClass>* classes;
            double unit;
          };
          for (const Case& c : {Case{FindSubspaceArap(setup.energy()).get(), &setup.node_classes(), diagonal},
                                Case{hand.get(), &mixed, 0.37 * diagonal}}) {
            ASSERT_NE(c.arap, nullptr);
            const FullMesh full = FullMeshOf(setup, c.unit, options.arap);
            for (int trial = 0; trial < 3; ++trial) {
              const NodeTransforms transforms = RandomTransforms(*c.classes, diagonal, &rng);
              const Eigen::Affine3d handle = RandomRigid(diagonal, &rng);
              SubspaceArap::Slots u;
              c.arap->Gather(transforms, handle, &u);
              const double reduced = c.arap->Cost(u);
              const double expected = full.Energy(full.Positions(transforms, handle), handle,
                                                  c.arap->cluster_of_vertex());
              EXPECT_GT(expected, 0.0);
              EXPECT_NEAR(reduced, expected, 1e-12 * expected)
                  << Name(method, clusters, constraints) << " trial " << trial
                  << (c.arap == hand.get() ? " (mixed classes)" : "");
            }
          }
        }
      }
    }
  }
}

// With clusters=vertices the energy is the ARAP energy core/metrics.h
// measures: sum_i E_i / (2 unit^2) at the full-mesh positions (plus the soft
// terms when the constraints are soft).
TEST(SubspaceArapTest, PerVertexClustersGiveTheMetricsArapEnergy) {
  const TwoBarEdit two_bars(/*fix_bar0=*/true);
  std::mt19937 rng(2007);
  for (Method method : {Method::kMultiScale, Method::kStaticDense}) {
    for (ArapConstraints constraints : kAllConstraints) {
      const DeformerOptions options =
          ArapOptionsFor(method, RotationClusters::kVertices, constraints);
      const std::unique_ptr<GraphMethod> deformer =
          MakeDeformer(two_bars.mesh, options, two_bars.layout);
      const HandleSetup& setup = *deformer->setup();
      const SubspaceArap& arap = *FindSubspaceArap(setup.energy());
      const double unit = deformer->diagonal();
      const FullMesh full = FullMeshOf(setup, unit, options.arap);
      const NodeTransforms transforms = RandomTransforms(setup.node_classes(), unit, &rng);
      const Eigen::Affine3d handle = RandomRigid(unit, &rng);
      const Eigen::Matrix3Xd x = full.Positions(transforms, handle);
      double soft = 0.0;
      if (constraints == ArapConstraints::kSoft) {
        for (int v : two_bars.layout.moveable)
          soft +=
              (x.col(v) - handle * Eigen::Vector3d(two_bars.mesh.vertices.col(v))).squaredNorm();
        for (int v : two_bars.layout.fixed)
          if (!full.IsStill(v)) soft += (x.col(v) - two_bars.mesh.vertices.col(v)).squaredNorm();
        soft *= options.arap.soft_weight;
      }
      const double expected =
          (ArapEnergyPerVertex(two_bars.mesh, x).energy.sum() + soft) / (2.0 * unit * unit);
      SubspaceArap::Slots u;
      arap.Gather(transforms, handle, &u);
      EXPECT_NEAR(arap.Cost(u), expected, 1e-12 * expected)
          << MethodName(method) << " " << ArapConstraintsNames().Name(constraints);
    }
  }
}

// The rigid optimum is a fixed point of the local/global solver: started
// there, it stays (a transposed rotation or a wrong factor in the global
// step would move it), with energy 0 and every vertex at H * rest.
TEST(SubspaceArapTest, RigidOptimumIsAFixedPointOfTheSolver) {
  BarEdit free_bar(12, 4);
  free_bar.layout.fixed.clear();
  const TwoBarEdit two_bars(/*fix_bar0=*/false);
  const Eigen::Affine3d h = Turn();
  for (const FreeEdit& edit : FreeEdits(free_bar, two_bars)) {
    for (Method method : kAllMethods) {
      for (RotationClusters clusters : kAllClusters) {
        for (ArapConstraints constraints : kAllConstraints) {
          const DeformerOptions options = ArapOptionsFor(method, clusters, constraints);
          const std::unique_ptr<GraphMethod> deformer =
              MakeDeformer(*edit.mesh, options, *edit.handles);
          const HandleSetup& setup = *deformer->setup();
          ArapLocalGlobalSolver solver(options.stopping);
          NodeTransforms transforms = RigidTransforms(setup.graph(), setup.node_classes(), h);
          std::string error;
          ASSERT_TRUE(solver.Setup(setup.energy(), transforms, &error)) << error;
          const SolveSummary summary = solver.Solve(h, &transforms);
          const FullMesh full = FullMeshOf(setup, deformer->diagonal(), options.arap);
          const Eigen::Matrix3Xd x = full.Positions(transforms, h);
          const std::string name = Name(method, clusters, constraints);
          EXPECT_FALSE(summary.failed) << name << ": " << summary.message;
          EXPECT_LT(full.Energy(x, h, FindSubspaceArap(setup.energy())->cluster_of_vertex()), 1e-20) << name;
          EXPECT_LE(DistanceFromRigid(setup, x, h), 1e-9) << name;
          // The reduced energy: 0 up to the rounding of its sums (measured:
          // 1e-16 of their size at most).
          EXPECT_LT(std::abs(summary.final_cost), 1e-14 * full.Magnitude(x, h)) << name;
        }
      }
    }
  }
}

// The known optimum through a graph method: the handle moved rigidly, one
// Drag from the rest pose reaches energy 0 and puts every free vertex at
// H * rest. A translation: the local/global solver's first step (the last
// frame's rotations, I at rest) is the optimum. A turn of 0.9 rad with a
// translation: local/global converges linearly from the bent first step
// (0.61 of the diagonal from H * rest after 20 iterations on the free bar),
// so the turn is solved by arap.solver=gauss_newton, which reaches it within
// its default budget.
// Both solvers stop where the reduced energy's rounding (about 1e-13 of the
// rest spokes' sum C, docs/decisions/subspace-arap.md) hides further progress: the result
// is then within about 1e-8 of the diagonal of H * rest at an energy near
// 1e-17, where a misplaced column, a transposed rotation or the handle's
// jump left in place give 1e-3 and more.
constexpr double kRigidEnergy = 1e-15;
constexpr double kRigidDistance = 1e-7;

TEST(SubspaceArapTest, RigidEditReachesTheOptimumInOneDrag) {
  BarEdit free_bar(12, 4);
  free_bar.layout.fixed.clear();
  const TwoBarEdit two_bars(/*fix_bar0=*/false);
  Eigen::Affine3d translation = Eigen::Affine3d::Identity();
  translation.translation() << 1.0, -2.0, 0.5;
  for (const auto& [h, solver] : {std::make_pair(translation, ArapSolver::kLocalGlobal),
                                   std::make_pair(Turn(), ArapSolver::kGaussNewton)}) {
    for (const FreeEdit& edit : FreeEdits(free_bar, two_bars)) {
      for (Method method : kAllMethods) {
        for (RotationClusters clusters : kAllClusters) {
          for (ArapConstraints constraints : kAllConstraints) {
            // Gauss-Newton factorises its filled 3 nv system every iteration
            // (minutes over every DG1 node or one rotation a vertex here):
            // the turn runs on the multi-scale and 220-node graphs with
            // clustered rotations.
            if (solver == ArapSolver::kGaussNewton &&
                (clusters == RotationClusters::kVertices || method == Method::kStaticDense))
              continue;
            DeformerOptions options = ArapOptionsFor(method, clusters, constraints);
            options.arap.solver = solver;
            const std::unique_ptr<GraphMethod> deformer =
                MakeDeformer(*edit.mesh, options, *edit.handles);
            const HandleSetup& setup = *deformer->setup();
            std::string error;
            ASSERT_TRUE(deformer->Drag(h, nullptr, &error)) << error;
            const FullMesh full = FullMeshOf(setup, deformer->diagonal(), options.arap);
            const std::string name = Name(method, clusters, constraints) +
                                     (solver == ArapSolver::kGaussNewton ? " turn" : " translation");
            const Eigen::Matrix3Xd& x = deformer->deformed_vertices();
            EXPECT_LT(full.Energy(x, h, FindSubspaceArap(setup.energy())->cluster_of_vertex()), kRigidEnergy)
                << name;
            EXPECT_LE(DistanceFromRigid(setup, x, h), kRigidDistance) << name;
          }
        }
      }
    }
  }
}

// Along a path, every frame's energy never rises from one iteration to the
// next (each global step minimises exactly over the nodes, each local step
// over the rotations); Fixed nodes stay the identity and Half Free
// translations stay 0 bit for bit; with exact constraints the handle
// vertices are H * rest and the fixed vertices rest, bit for bit; and the
// energy the solver reports is the full-mesh energy of the skinned result.
TEST(SubspaceArapTest, EnergyNeverRisesAndConstraintsHold) {
  const BarEdit bar(12, 4);
  const std::vector<Eigen::Affine3d> path = TurnPath(3);
  for (Method method : {Method::kMultiScale, Method::kStatic}) {
    for (RotationClusters clusters : kAllClusters) {
      for (ArapConstraints constraints : kAllConstraints) {
        DeformerOptions options = ArapOptionsFor(method, clusters, constraints);
        const std::unique_ptr<GraphMethod> deformer = MakeDeformer(bar.mesh, options, bar.layout);
        const HandleSetup& setup = *deformer->setup();
        const FullMesh full = FullMeshOf(setup, deformer->diagonal(), options.arap);
        const std::string name = Name(method, clusters, constraints);
        for (const Eigen::Affine3d& h : path) {
          DragStats stats;
          std::string error;
          ASSERT_TRUE(deformer->Drag(h, &stats, &error)) << error;
          ASSERT_GE(stats.trace.size(), 2u) << name;
          for (size_t t = 1; t < stats.trace.size(); ++t) {
            EXPECT_LE(stats.trace[t].cost, stats.trace[t - 1].cost) << name << " iteration " << t;
          }
          const NodeTransforms& transforms = deformer->transforms();
          for (int j = 0; j < transforms.num_nodes(); ++j) {
            if (setup.node_classes()[j] == NodeClass::kFixed) {
              ASSERT_EQ(transforms.rotation(j), Eigen::Matrix3d::Identity()) << name;
              ASSERT_EQ(transforms.translations.col(j), Eigen::Vector3d::Zero()) << name;
            }
            if (setup.node_classes()[j] == NodeClass::kHalfFree) {
              ASSERT_EQ(transforms.translations.col(j), Eigen::Vector3d::Zero()) << name;
            }
          }
          const Eigen::Matrix3Xd& x = deformer->deformed_vertices();
          if (constraints == ArapConstraints::kExact) {
            for (int v : bar.layout.moveable) {
              ASSERT_EQ(x.col(v), h * Eigen::Vector3d(bar.mesh.vertices.col(v))) << name;
            }
            for (int v : bar.layout.fixed) ASSERT_EQ(x.col(v), bar.mesh.vertices.col(v)) << name;
          }
          // Equal up to the rounding of the reduced form's sums (measured:
          // 2.4e-16 of their size at most).
          const double expected = full.Energy(x, h, FindSubspaceArap(setup.energy())->cluster_of_vertex());
          EXPECT_NEAR(stats.final_cost, expected, 1e-14 * full.Magnitude(x, h)) << name;
        }
      }
    }
  }
}

// The solver on hand-made classes (Totally Free, Half Free and Fixed in
// turn): from random Half Free translations, each stays as given and each
// Fixed node the identity, bit for bit, while the energy falls.
TEST(SubspaceArapTest, SolverKeepsTheConstantBlocks) {
  const BarEdit bar(12, 4);
  std::mt19937 rng(2012);
  for (RotationClusters clusters : kAllClusters) {
    for (ArapConstraints constraints : kAllConstraints) {
      const DeformerOptions options = ArapOptionsFor(Method::kStatic, clusters, constraints);
      const std::unique_ptr<GraphMethod> deformer = MakeDeformer(bar.mesh, options, bar.layout);
      const HandleSetup& setup = *deformer->setup();
      const std::vector<NodeClass> mixed = MixedClasses(setup.graph().num_nodes());
      DeformationEnergy energy;
      energy.families.push_back(std::make_shared<SubspaceArapTerms>(
          BuildWithClasses(setup, mixed, deformer->diagonal(), options.arap)));
      NodeTransforms transforms = NodeTransforms::Identity(setup.graph().num_nodes());
      for (int j = 0; j < transforms.num_nodes(); ++j) {
        if (mixed[j] != NodeClass::kHalfFree) continue;
        for (int d = 0; d < 3; ++d)
          transforms.translations(d, j) = std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
      }
      const NodeTransforms given = transforms;
      ArapLocalGlobalSolver solver(options.stopping);
      std::string error;
      ASSERT_TRUE(solver.Setup(energy, transforms, &error)) << error;
      const SolveSummary summary = solver.Solve(TurnPath(2)[1], &transforms);
      const std::string name = std::string(RotationClustersNames().Name(clusters)) + " " +
                               ArapConstraintsNames().Name(constraints);
      EXPECT_FALSE(summary.failed) << name;
      EXPECT_LT(summary.final_cost, summary.initial_cost) << name;
      for (size_t t = 1; t < summary.trace.size(); ++t) {
        EXPECT_LE(summary.trace[t].cost, summary.trace[t - 1].cost) << name << " iteration " << t;
      }
      for (int j = 0; j < transforms.num_nodes(); ++j) {
        if (mixed[j] == NodeClass::kTotallyFree) continue;
        ASSERT_EQ(transforms.translations.col(j), given.translations.col(j)) << name;
        if (mixed[j] == NodeClass::kFixed) {
          ASSERT_EQ(transforms.rotation(j), Eigen::Matrix3d::Identity()) << name;
        }
      }
    }
  }
}

// Bad options are one-line errors naming the option, from the flags and
// from the options themselves, never an abort.
TEST(SubspaceArapTest, BadOptionsNameTheOption) {
  struct Case {
    const char* flag;
    const char* value;
    const char* message;
  };
  for (const Case& c :
       {Case{"arap_num_clusters", "0", "--arap_num_clusters=0: expected an integer >= 1"},
        Case{"energy", "arapp", "--energy=arapp: expected ed or arap"},
        Case{"arap_clusters", "kmeans",
             "--arap_clusters=kmeans: expected weights, nodes or vertices"},
        Case{"arap_constraints", "hard", "--arap_constraints=hard: expected exact or soft"}}) {
    gflags::FlagSaver saver;
    ASSERT_FALSE(gflags::SetCommandLineOption("energy", "arap").empty());
    ASSERT_FALSE(gflags::SetCommandLineOption(c.flag, c.value).empty()) << c.flag;
    DeformerOptions options;
    std::string error;
    EXPECT_FALSE(DeformerOptionsFromFlags(&options, &error)) << c.flag;
    EXPECT_EQ(error, c.message);
  }
  // The flags that are right reach the options.
  {
    gflags::FlagSaver saver;
    ASSERT_FALSE(gflags::SetCommandLineOption("energy", "arap").empty());
    ASSERT_FALSE(gflags::SetCommandLineOption("arap_clusters", "nodes").empty());
    ASSERT_FALSE(gflags::SetCommandLineOption("arap_num_clusters", "5").empty());
    ASSERT_FALSE(gflags::SetCommandLineOption("arap_constraints", "soft").empty());
    DeformerOptions options;
    std::string error;
    ASSERT_TRUE(DeformerOptionsFromFlags(&options, &error)) << error;
    EXPECT_EQ(options.energy, Energy::kArap);
    EXPECT_EQ(options.arap.clusters, RotationClusters::kNodes);
    EXPECT_EQ(options.arap.num_clusters, 5);
    EXPECT_EQ(options.arap.constraints, ArapConstraints::kSoft);
  }
  // Set in code: the graph method refuses them with the field's name.
  struct Bad {
    void (*set)(ArapOptions*);
    const char* message;
  };
  for (const Bad& bad :
       {Bad{[](ArapOptions* o) { o->num_clusters = 0; }, "arap.num_clusters=0: expected an integer >= 1"},
        Bad{[](ArapOptions* o) { o->kmeans_iterations = -1; },
            "arap.kmeans_iterations=-1: expected an integer >= 0"},
        Bad{[](ArapOptions* o) { o->soft_weight = 0.0; },
            "arap.soft_weight=0: expected a finite weight > 0"},
        Bad{[](ArapOptions* o) { o->soft_weight = std::nan(""); },
            "arap.soft_weight=nan: expected a finite weight > 0"}}) {
    DeformerOptions options =
        ArapOptionsFor(Method::kMultiScale, RotationClusters::kWeights, ArapConstraints::kExact);
    bad.set(&options.arap);
    GraphMethod deformer(options.method);
    std::string error;
    EXPECT_FALSE(deformer.Precompute(BarEdit().mesh, options, &error));
    EXPECT_NE(error.find(bad.message), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

// A rigid handle turn with exact constraints: the handle vertices are
// H * rest, and their normals are R * the rest normals (they are not skinned
// positions, so their normals are not skinned either); the fixed vertices
// keep their rest normals.
TEST(SubspaceArapTest, ExactVerticesHaveTheirExactNormals) {
  const BarEdit bar(12, 4);
  for (Method method : kAllMethods) {
    const DeformerOptions options =
        ArapOptionsFor(method, RotationClusters::kWeights, ArapConstraints::kExact);
    const std::unique_ptr<GraphMethod> deformer = MakeDeformer(bar.mesh, options, bar.layout);
    Eigen::Affine3d h = Eigen::Affine3d::Identity();
    h.linear() = Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()).toRotationMatrix();
    h.translation() << 0.0, 0.0, 2.0;
    std::string error;
    ASSERT_TRUE(deformer->Drag(h, nullptr, &error)) << error;
    const Eigen::Matrix3Xd& normals = deformer->deformed_normals();
    const Eigen::Matrix3Xd& rest = deformer->setup()->precompute().rest_normals();
    for (int v : bar.layout.moveable)
      EXPECT_LE((normals.col(v) - h.linear() * rest.col(v)).norm(), 1e-15) << MethodName(method);
    for (int v : bar.layout.fixed) EXPECT_EQ(normals.col(v), rest.col(v)) << MethodName(method);
  }
}

// A copy of a set-up's energy outlives the method: the energy keeps what it
// reads (the precompute's mesh and cotangent weights, a pin on its graph).
// The sanitizer build catches a read of freed memory here.
TEST(SubspaceArapTest, ACopyOfTheEnergyOutlivesTheMethod) {
  const BarEdit bar(12, 4);
  const DeformerOptions options =
      ArapOptionsFor(Method::kStatic, RotationClusters::kWeights, ArapConstraints::kExact);
  std::unique_ptr<GraphMethod> deformer = MakeDeformer(bar.mesh, options, bar.layout);
  const DeformationEnergy energy = deformer->setup()->energy();
  const NodeTransforms identity = NodeTransforms::Identity(FindSubspaceArap(energy)->num_nodes());
  Eigen::Affine3d h = Eigen::Affine3d::Identity();
  h.translation() << 1.0, 0.0, 0.0;
  const double before = EvaluateEnergy(energy, identity, h);
  deformer.reset();
  EXPECT_EQ(EvaluateEnergy(energy, identity, h), before);
  EXPECT_GT(before, 0.0);  // the handle moved, the rest of the bar did not
}

// Soft constraints with every node Fixed: no vertex can move, no vertex is
// active and there is no cluster (k-means over nothing divided by zero).
TEST(SubspaceArapTest, NoActiveVertexGivesAnEmptyEnergy) {
  const BarEdit bar(12, 4);
  const DeformerOptions options =
      ArapOptionsFor(Method::kStatic, RotationClusters::kWeights, ArapConstraints::kSoft);
  const std::unique_ptr<GraphMethod> deformer = MakeDeformer(bar.mesh, options, bar.layout);
  const HandleSetup& setup = *deformer->setup();
  const std::vector<NodeClass> fixed(setup.graph().num_nodes(), NodeClass::kFixed);
  const std::shared_ptr<const SubspaceArap> arap =
      BuildWithClasses(setup, fixed, deformer->diagonal(), options.arap);
  EXPECT_EQ(arap->num_active_vertices(), 0);
  EXPECT_EQ(arap->num_clusters(), 0);
  EXPECT_EQ(arap->num_variables(), 0);
}

}  // namespace
}  // namespace msdeform
