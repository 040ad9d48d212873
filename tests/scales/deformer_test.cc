#include "scales/deformer.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "core/drag_path.h"
#include "core/handles.h"
#include "core/mesh_io.h"
#include "core/procedural_meshes.h"
#include "core/scenario.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

// A 12 x 1 x 1 bar, the first voxel fixed and the last one the handle.
struct BarEdit {
  Mesh mesh = MakeBar(12, 1.0, 4);
  HandleLayout layout;
  BarEdit() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.vertices(0, v) <= 1.0) layout.fixed.push_back(v);
      if (mesh.vertices(0, v) >= 11.0) layout.moveable.push_back(v);
    }
  }
};

void InitOrDie(Deformer* deformer, const Mesh& mesh, const DeformerOptions& options,
               const HandleLayout& layout) {
  std::string error;
  ASSERT_TRUE(deformer->Init(mesh, options, &error)) << error;
  ASSERT_TRUE(deformer->SetHandles(layout, &error)) << error;
}

TEST(DeformerTest, IdentityTargetLeavesTheMeshUnchanged) {
  const BarEdit bar;
  for (Method method : kAllMethods) {
    Deformer deformer;
    InitOrDie(&deformer, bar.mesh, OptionsFor(method), bar.layout);
    std::string error;
    ASSERT_TRUE(deformer.Drag(Eigen::Affine3d::Identity(), nullptr, &error)) << error;
    EXPECT_LT(MaxDistance(deformer.deformed_vertices(), bar.mesh.vertices), 1e-9)
        << MethodName(method);
  }
}

TEST(DeformerTest, RigidMotionOfAWholeMeshHandleMovesTheMeshRigidly) {
  const BarEdit bar;
  HandleLayout everything;
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) everything.moveable.push_back(v);
  Eigen::Affine3d translation = Eigen::Affine3d::Identity();
  translation.translation() << 0.3, -1.0, 2.0;
  Eigen::Affine3d rotation = Eigen::Affine3d::Identity();
  rotation.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 2, 2).normalized()));
  rotation.pretranslate(Eigen::Vector3d(1, 0, 0));
  for (Method method : kAllMethods) {
    for (const Eigen::Affine3d& motion : {translation, rotation}) {
      Deformer deformer;
      InitOrDie(&deformer, bar.mesh, OptionsFor(method), everything);
      std::string error;
      for (const Eigen::Affine3d& frame :
           InterpolateDragPath(motion, bar.mesh.vertices.rowwise().mean(), 3)) {
        ASSERT_TRUE(deformer.Drag(frame, nullptr, &error)) << error;
      }
      const Eigen::Matrix3Xd expected = motion * bar.mesh.vertices;
      EXPECT_LT(MaxDistance(deformer.deformed_vertices(), expected), 1e-6)
          << MethodName(method);
      // Normals turn with the mesh.
      const Eigen::Matrix3Xd normals = VertexNormals(bar.mesh);
      EXPECT_LT(MaxDistance(deformer.deformed_normals(), motion.linear() * normals), 1e-6)
          << MethodName(method);
    }
  }
}

TEST(DeformerTest, ClassesAreParameterBlockFixing) {
  const BarEdit bar;
  Deformer deformer;
  InitOrDie(&deformer, bar.mesh, OptionsFor(Method::kMultiScale), bar.layout);
  const ScaleSelection& selection = deformer.selection();
  int m = 0, q = 0;
  for (NodeClass c : deformer.node_classes()) {
    m += c == NodeClass::kTotallyFree;
    q += c == NodeClass::kHalfFree;
  }
  EXPECT_GT(m, 0);
  EXPECT_GT(q, 0);
  EXPECT_EQ(m, selection.num_totally_free);
  EXPECT_EQ(q, selection.num_half_free);
  EXPECT_EQ(deformer.num_variables(), 12 * m + 9 * q);
  // After a drag the Fixed nodes are still the identity and the Half Free
  // nodes still have t = 0.
  std::string error;
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 2.0, 0.0;
  ASSERT_TRUE(deformer.Drag(lift, nullptr, &error)) << error;
  const NodeTransforms& transforms = deformer.transforms();
  bool some_free_node_moved = false;
  for (int j = 0; j < deformer.active().num_nodes(); ++j) {
    const NodeClass c = deformer.node_classes()[j];
    if (c != NodeClass::kTotallyFree) {
      EXPECT_EQ(transforms.translations.col(j).norm(), 0.0);
    }
    if (c == NodeClass::kFixed) {
      EXPECT_TRUE(transforms.rotation(j).isIdentity(0.0));
    }
    if (c == NodeClass::kTotallyFree) {
      some_free_node_moved |= transforms.translations.col(j).norm() > 0.1;
    }
  }
  EXPECT_TRUE(some_free_node_moved);
}

// Directed edges (j, k) of the active graph with j Half Free and k Half Free
// or Fixed: the terms METHOD.md §5 leaves out.
int LeftOutTerms(const Deformer& deformer) {
  int count = 0;
  const auto& classes = deformer.node_classes();
  for (const auto& [a, b] : deformer.active().edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      count += classes[j] == NodeClass::kHalfFree && classes[k] != NodeClass::kTotallyFree;
    }
  }
  return count;
}

TEST(DeformerTest, LeftOutTermsAreAbsentAndBackUnderTheAblation) {
  const BarEdit bar;
  Deformer deformer;
  InitOrDie(&deformer, bar.mesh, OptionsFor(Method::kMultiScale), bar.layout);
  int expected = 0;
  const auto& classes = deformer.node_classes();
  for (const auto& [a, b] : deformer.active().edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      expected += classes[j] == NodeClass::kTotallyFree || classes[k] == NodeClass::kTotallyFree;
    }
  }
  EXPECT_EQ(deformer.num_coherence_terms(), expected);
  const int left_out = LeftOutTerms(deformer);
  ASSERT_GT(left_out, 0);

  DeformerOptions ablation = OptionsFor(Method::kMultiScale);
  ablation.keep_left_out_terms = true;
  Deformer with_terms;
  InitOrDie(&with_terms, bar.mesh, ablation, bar.layout);
  EXPECT_EQ(with_terms.node_classes(), deformer.node_classes());
  EXPECT_EQ(with_terms.num_coherence_terms(), expected + left_out);

  // The other ablation: fixed-handle nodes lose their rotation.
  ablation = OptionsFor(Method::kMultiScale);
  ablation.fix_fixed_handle_nodes = true;
  Deformer fixed_nodes;
  InitOrDie(&fixed_nodes, bar.mesh, ablation, bar.layout);
  for (NodeClass c : fixed_nodes.node_classes()) EXPECT_NE(c, NodeClass::kHalfFree);
  EXPECT_LT(fixed_nodes.num_variables(), deformer.num_variables());
}

TEST(DeformerTest, StaticBaselinesFreeEveryNodeOfTheirGraph) {
  const BarEdit bar;
  for (Method method : {Method::kStatic, Method::kStaticDense}) {
    Deformer deformer;
    InitOrDie(&deformer, bar.mesh, OptionsFor(method), bar.layout);
    const int n = deformer.active().num_nodes();
    EXPECT_EQ(n, method == Method::kStatic ? 40 : deformer.graphs()[0].num_nodes());
    EXPECT_EQ(deformer.num_variables(), 12 * n);
    EXPECT_EQ(deformer.num_coherence_terms(), 2 * static_cast<int>(deformer.active().edges.size()));
    EXPECT_EQ(deformer.num_position_terms(), static_cast<int>(bar.layout.moveable.size()));
  }
}

std::string DataPath(const std::string& name) { return std::string(MSDEFORM_DATA_DIR) + "/" + name; }

// Handle rms and the largest fixed-vertex displacement, both relative to the
// diagonal, after dragging the Botsch-Sorkine cactus to its .def over 30 frames.
std::pair<double, double> CactusErrors(Method method, Solver backend,
                                       const DeformerOptions& base = DeformerOptions()) {
  Mesh mesh;
  HandleLayout layout;
  Eigen::Affine3d target;
  std::string error;
  EXPECT_TRUE(ReadMesh(DataPath("meshes/cactus.off"), &mesh, &error)) << error;
  EXPECT_TRUE(ReadSel(DataPath("meshes/cactus.sel"), mesh.num_vertices(), &layout, &error)) << error;
  EXPECT_TRUE(ReadDef(DataPath("meshes/cactus.def"), &target, &error)) << error;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : layout.moveable) centroid += mesh.vertices.col(v);
  centroid /= layout.moveable.size();
  DeformerOptions options = base;
  options.method = method;
  options.backend = backend;
  options.num_threads = 1;
  Deformer deformer;
  InitOrDie(&deformer, mesh, options, layout);
  for (const Eigen::Affine3d& frame : InterpolateDragPath(target, centroid, 30)) {
    EXPECT_TRUE(deformer.Drag(frame, nullptr, &error)) << error;
  }
  double squared = 0.0;
  for (int v : layout.moveable) {
    squared += (deformer.deformed_vertices().col(v) - target * mesh.vertices.col(v)).squaredNorm();
  }
  double fixed_max = 0.0;
  for (int v : layout.fixed) {
    fixed_max = std::max(fixed_max, (deformer.deformed_vertices().col(v) - mesh.vertices.col(v)).norm());
  }
  return {std::sqrt(squared / layout.moveable.size()) / deformer.diagonal(),
          fixed_max / deformer.diagonal()};
}

TEST(DeformerTest, BotschSorkineCactusReachesItsTarget) {
  // The handle travels about 0.6 diagonals and turns 70 degrees. The
  // harmonic estimate frees the whole trunk (scale 5 of 5), and the handle
  // comes within 1.13% of the diagonal; but at that scale the cactus's
  // 620 vertices give nodes that skin fixed and free vertices together, and
  // the fixed vertices drift (3.4%; experiments/results/README.md, claim 2).
  // The paper's procedure holds the lower trunk Fixed (R = I, t = 0): its
  // fixed vertices stay within 0.3%, its handle at 1.47%.
  const auto [multiscale_rms, multiscale_fixed] =
      CactusErrors(Method::kMultiScale, Solver::kCeres);
  EXPECT_LT(multiscale_rms, 0.015);
  DeformerOptions paper;
  paper.rigidity.model = RigidityModel::kShapeMatching;
  paper.selection.half_free = HalfFreeRule::kEveryFixedHandleNode;
  paper.selection.border = BorderRule::kFixed;
  paper.hold_fixed_vertices = false;
  const auto [paper_rms, paper_fixed] = CactusErrors(Method::kMultiScale, Solver::kCeres, paper);
  EXPECT_LT(paper_rms, 0.015);
  EXPECT_LT(paper_fixed, 3e-3);
  EXPECT_LT(multiscale_rms, paper_rms);
  // The same minimum as Ceres (tests/scales/gauss_newton_solver_test.cc), faster.
  EXPECT_LT(CactusErrors(Method::kStaticDense, Solver::kGaussNewton).first,
            0.005);
}

TEST(DeformerTest, LargeArmadilloEditKeepsOptimisedNodesNearP) {
  Scenario scenario;
  Mesh mesh;
  HandleLayout layout;
  std::vector<int> watch;
  Eigen::Affine3d target;
  std::string error;
  ASSERT_TRUE(ReadScenario(DataPath("scenarios/armadillo_claw.json"), &scenario, &error)) << error;
  ASSERT_TRUE(ReadMesh(scenario.mesh_path, &mesh, &error)) << error;
  ASSERT_TRUE(ResolveScenario(scenario, mesh, &layout, &watch, &target, &error)) << error;
  DeformerOptions options;
  options.num_threads = 1;
  Deformer deformer;
  InitOrDie(&deformer, mesh, options, layout);
  const ScaleSelection& selection = deformer.selection();
  EXPECT_GT(selection.group1_size, options.selection.nodes_per_scale);
  EXPECT_GT(selection.scale, 1);
  EXPECT_LE(selection.num_totally_free, 2 * options.selection.nodes_per_scale);
  EXPECT_GE(selection.num_totally_free, options.selection.nodes_per_scale / 2);
  EXPECT_LT(deformer.num_variables(), 12 * deformer.graphs()[0].num_nodes() / 5);
}

}  // namespace
}  // namespace msdeform
