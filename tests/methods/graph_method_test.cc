#include "msdeform/methods/graph_method.h"

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/mesh_io.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/core/scenario.h"
#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/session.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

void InitOrDie(GraphMethod* graph_method, const Mesh& mesh, const DeformerOptions& options,
               const HandleLayout& layout) {
  std::string error;
  ASSERT_TRUE(graph_method->Precompute(mesh, options, &error)) << error;
  ASSERT_TRUE(graph_method->SetHandles(layout, &error)) << error;
}

TEST(GraphMethodTest, IdentityTargetLeavesTheMeshUnchanged) {
  const BarEdit bar;
  for (Method method : kAllMethods) {
    GraphMethod graph_method(method);
    InitOrDie(&graph_method, bar.mesh, OptionsFor(method), bar.layout);
    std::string error;
    ASSERT_TRUE(graph_method.Drag(Eigen::Affine3d::Identity(), nullptr, &error)) << error;
    EXPECT_LT(MaxDistance(graph_method.deformed_vertices(), bar.mesh.vertices), 1e-9)
        << MethodName(method);
  }
}

TEST(GraphMethodTest, RigidMotionOfAWholeMeshHandleMovesTheMeshRigidly) {
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
      GraphMethod graph_method(method);
      InitOrDie(&graph_method, bar.mesh, OptionsFor(method), everything);
      std::string error;
      for (const Eigen::Affine3d& frame :
           InterpolateDragPath(motion, bar.mesh.vertices.rowwise().mean(), 3)) {
        ASSERT_TRUE(graph_method.Drag(frame, nullptr, &error)) << error;
      }
      const Eigen::Matrix3Xd expected = motion * bar.mesh.vertices;
      EXPECT_LT(MaxDistance(graph_method.deformed_vertices(), expected), 1e-6)
          << MethodName(method);
      // Normals turn with the mesh.
      const Eigen::Matrix3Xd normals = VertexNormals(bar.mesh);
      EXPECT_LT(MaxDistance(graph_method.deformed_normals(), motion.linear() * normals), 1e-6)
          << MethodName(method);
    }
  }
}

// Half Free nodes hold fixed vertices, so these tests of them keep the fixed
// region unpinned (ScaleSelectionOptions::pin_fixed_region, the paper's classes).
DeformerOptions UnpinnedOptions() {
  DeformerOptions options = OptionsFor(Method::kMultiScale);
  options.selection.pin_fixed_region = false;
  return options;
}

TEST(GraphMethodTest, ClassesAreParameterBlockFixing) {
  const BarEdit bar;
  GraphMethod graph_method(UnpinnedOptions().method);
  InitOrDie(&graph_method, bar.mesh, UnpinnedOptions(), bar.layout);
  const ScaleSelection& selection = graph_method.selection();
  int m = 0, q = 0;
  for (NodeClass c : graph_method.node_classes()) {
    m += c == NodeClass::kTotallyFree;
    q += c == NodeClass::kHalfFree;
  }
  EXPECT_GT(m, 0);
  EXPECT_GT(q, 0);
  EXPECT_EQ(m, selection.num_totally_free);
  EXPECT_EQ(q, selection.num_half_free);
  EXPECT_EQ(graph_method.variables(), 12 * m + 9 * q);
  // After a drag the Fixed nodes are still the identity and the Half Free
  // nodes still have t = 0.
  std::string error;
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 2.0, 0.0;
  ASSERT_TRUE(graph_method.Drag(lift, nullptr, &error)) << error;
  const NodeTransforms& transforms = graph_method.transforms();
  bool some_free_node_moved = false;
  for (int j = 0; j < graph_method.active().num_nodes(); ++j) {
    const NodeClass c = graph_method.node_classes()[j];
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
// or Fixed: the terms docs/method.md §5 leaves out.
int LeftOutTerms(const GraphMethod& graph_method) {
  int count = 0;
  const auto& classes = graph_method.node_classes();
  for (const auto& [a, b] : graph_method.active().edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      count += classes[j] == NodeClass::kHalfFree && classes[k] != NodeClass::kTotallyFree;
    }
  }
  return count;
}

TEST(GraphMethodTest, LeftOutTermsAreAbsentAndBackUnderTheAblation) {
  const BarEdit bar;
  GraphMethod graph_method(UnpinnedOptions().method);
  InitOrDie(&graph_method, bar.mesh, UnpinnedOptions(), bar.layout);
  int expected = 0;
  const auto& classes = graph_method.node_classes();
  for (const auto& [a, b] : graph_method.active().edges) {
    for (const auto& [j, k] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      expected += classes[j] == NodeClass::kTotallyFree || classes[k] == NodeClass::kTotallyFree;
    }
  }
  EXPECT_EQ(graph_method.num_coherence_terms(), expected);
  const int left_out = LeftOutTerms(graph_method);
  ASSERT_GT(left_out, 0);

  DeformerOptions ablation = UnpinnedOptions();
  ablation.keep_left_out_terms = true;
  GraphMethod with_terms(ablation.method);
  InitOrDie(&with_terms, bar.mesh, ablation, bar.layout);
  EXPECT_EQ(with_terms.node_classes(), graph_method.node_classes());
  EXPECT_EQ(with_terms.num_coherence_terms(), expected + left_out);

  // The other ablation: fixed-handle nodes lose their rotation.
  ablation = UnpinnedOptions();
  ablation.fix_fixed_handle_nodes = true;
  GraphMethod fixed_nodes(ablation.method);
  InitOrDie(&fixed_nodes, bar.mesh, ablation, bar.layout);
  for (NodeClass c : fixed_nodes.node_classes()) EXPECT_NE(c, NodeClass::kHalfFree);
  EXPECT_LT(fixed_nodes.variables(), graph_method.variables());
}

TEST(GraphMethodTest, StaticBaselinesFreeEveryNodeOfTheirGraph) {
  const BarEdit bar;
  for (Method method : {Method::kStatic, Method::kStaticDense}) {
    GraphMethod graph_method(method);
    InitOrDie(&graph_method, bar.mesh, OptionsFor(method), bar.layout);
    const int n = graph_method.active().num_nodes();
    EXPECT_EQ(n, method == Method::kStatic ? 40 : graph_method.graphs()[0].num_nodes());
    EXPECT_EQ(graph_method.variables(), 12 * n);
    EXPECT_EQ(graph_method.num_coherence_terms(),
              2 * static_cast<int>(graph_method.active().edges.size()));
    EXPECT_EQ(graph_method.num_position_terms(), static_cast<int>(bar.layout.moveable.size()));
  }
}

std::string DataPath(const std::string& name) {
  return std::string(MSDEFORM_DATA_DIR) + "/" + name;
}

// Handle rms and the largest fixed-vertex displacement, both relative to the
// diagonal, after dragging the Botsch-Sorkine cactus to its .def over 30 frames.
std::pair<double, double> CactusErrors(Method method, Solver backend,
                                       const DeformerOptions& base = DeformerOptions()) {
  Mesh mesh;
  HandleLayout layout;
  Eigen::Affine3d target;
  std::string error;
  EXPECT_TRUE(ReadMesh(DataPath("meshes/cactus.off"), &mesh, &error)) << error;
  EXPECT_TRUE(ReadSel(DataPath("meshes/cactus.sel"), mesh.num_vertices(), &layout, &error))
      << error;
  EXPECT_TRUE(ReadDef(DataPath("meshes/cactus.def"), &target, &error)) << error;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : layout.moveable) centroid += mesh.vertices.col(v);
  centroid /= layout.moveable.size();
  DeformerOptions options = base;
  options.method = method;
  options.backend = backend;
  options.num_threads = 1;
  GraphMethod graph_method(options.method);
  InitOrDie(&graph_method, mesh, options, layout);
  for (const Eigen::Affine3d& frame : InterpolateDragPath(target, centroid, 30)) {
    EXPECT_TRUE(graph_method.Drag(frame, nullptr, &error)) << error;
  }
  double squared = 0.0;
  for (int v : layout.moveable) {
    squared +=
        (graph_method.deformed_vertices().col(v) - target * mesh.vertices.col(v)).squaredNorm();
  }
  double fixed_max = 0.0;
  for (int v : layout.fixed) {
    fixed_max = std::max(fixed_max,
                         (graph_method.deformed_vertices().col(v) - mesh.vertices.col(v)).norm());
  }
  return {std::sqrt(squared / layout.moveable.size()) / graph_method.diagonal(),
          fixed_max / graph_method.diagonal()};
}

TEST(GraphMethodTest, BotschSorkineCactusReachesItsTarget) {
  // The handle travels about 0.6 diagonals and turns 70 degrees. The
  // harmonic estimate frees the whole trunk (scale 5 of 5), and the handle
  // comes within 1.13% of the diagonal; but at that scale the cactus's
  // 620 vertices give nodes that skin fixed and free vertices together, and
  // the fixed vertices drift (3.4%; experiments/results/README.md, claim 2).
  // The paper's procedure holds the lower trunk Fixed (R = I, t = 0): its
  // fixed vertices stay within 0.3%, its handle at about 1.7% (1.67% with
  // the file's coordinates read exactly, 1.47% when they were rounded to
  // float, 1.5-1.6% with each coordinate moved by 1e-12 relative: which edges
  // the coarse graph keeps turns on near-ties; docs/decisions/exact-coordinates.md,
  // "Coordinates read exactly".)
  const auto [multiscale_rms, multiscale_fixed] =
      CactusErrors(Method::kMultiScale, Solver::kCeres);
  EXPECT_LT(multiscale_rms, 0.015);
  const auto [paper_rms, paper_fixed] =
      CactusErrors(Method::kMultiScale, Solver::kCeres, PaperProcedure(DeformerOptions()));
  EXPECT_LT(paper_rms, 0.02);
  EXPECT_LT(paper_fixed, 3e-3);
  EXPECT_LT(multiscale_rms, paper_rms);
  // The same minimum as Ceres (tests/solvers/gauss_newton_solver_test.cc), faster.
  EXPECT_LT(CactusErrors(Method::kStaticDense, Solver::kGaussNewton).first,
            0.005);
}

// The classic bending test (Botsch and Sorkine 2008): a cylinder of radius 1
// and height 10 along z, fixed below z = 1, its top (z > 9) rotated 90 degrees
// about x and moved so that the free length 8 could lie on a quarter circle
// of radius 16 / pi. The right answer bends the whole free length: its middle
// third turns by about 45 degrees.
struct CylinderBend {
  static constexpr double kFreeBottom = 1.0, kFreeTop = 9.0;
  Mesh mesh = MakeCylinder(1.0, 10.0, 32, 60);
  HandleLayout layout;
  Eigen::Affine3d target = Eigen::Affine3d::Identity();
  CylinderBend() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.vertices(2, v) < kFreeBottom) layout.fixed.push_back(v);
      if (mesh.vertices(2, v) > kFreeTop) layout.moveable.push_back(v);
    }
    const double radius = 2.0 * (kFreeTop - kFreeBottom) / M_PI;
    target.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
    // (0, 0, 9) -> (0, -radius, 1 + radius): the end of the quarter circle.
    target.translation() = Eigen::Vector3d(0.0, -radius, kFreeBottom + radius) -
                           target.linear() * Eigen::Vector3d(0, 0, kFreeTop);
  }

  // Angle (degrees) of the best-fit rotation of the vertices with z in
  // [from, to] (Kabsch), from rest to `deformed`.
  double TurnOf(const Eigen::Matrix3Xd& deformed, double from, double to) const {
    std::vector<int> ids;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      if (mesh.vertices(2, v) >= from && mesh.vertices(2, v) <= to) ids.push_back(v);
    }
    Eigen::Vector3d rest_mean = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
    for (int v : ids) {
      rest_mean += mesh.vertices.col(v);
      mean += deformed.col(v);
    }
    rest_mean /= ids.size();
    mean /= ids.size();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int v : ids) {
      covariance += (deformed.col(v) - mean) * (mesh.vertices.col(v) - rest_mean).transpose();
    }
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Eigen::Matrix3d rotation = svd.matrixU() * d * svd.matrixV().transpose();
    return Eigen::AngleAxisd(rotation).angle() * 180.0 / M_PI;
  }
};

TEST(GraphMethodTest, CylinderBendsOverItsWholeLength) {
  const CylinderBend bend;
  const double third = (CylinderBend::kFreeTop - CylinderBend::kFreeBottom) / 3.0;
  DeformerOptions options;
  options.backend = Solver::kGaussNewton;
  options.num_threads = 1;
  GraphMethod graph_method(options.method);
  InitOrDie(&graph_method, bend.mesh, options, bend.layout);
  // Group 1 reaches from the handle down into the lowest quarter of the free
  // length (e' falls off linearly along a prism; T = 0.1).
  const DeformationGraph& dg1 = graph_method.graphs()[0];
  double lowest_group1 = CylinderBend::kFreeTop;
  for (int i = 0; i < dg1.num_nodes(); ++i) {
    if (graph_method.rigidity().relative_extent[i] > graph_method.selection().threshold) {
      lowest_group1 = std::min(lowest_group1, dg1.positions(2, i));
    }
  }
  EXPECT_LT(lowest_group1, CylinderBend::kFreeBottom + 0.25 * 3.0 * third);
  std::string error;
  const Eigen::Vector3d centroid = [&] {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int v : bend.layout.moveable) sum += bend.mesh.vertices.col(v);
    return Eigen::Vector3d(sum / bend.layout.moveable.size());
  }();
  for (const Eigen::Affine3d& frame : InterpolateDragPath(bend.target, centroid, 10)) {
    ASSERT_TRUE(graph_method.Drag(frame, nullptr, &error)) << error;
  }
  // The middle third turns by about half the handle's 90 degrees, and the
  // lowest third by less than the highest.
  const double lowest = CylinderBend::kFreeBottom;
  const double middle_turn =
      bend.TurnOf(graph_method.deformed_vertices(), lowest + third, lowest + 2 * third);
  EXPECT_GT(middle_turn, 30.0);
  EXPECT_LT(middle_turn, 60.0);
  EXPECT_LT(bend.TurnOf(graph_method.deformed_vertices(), lowest, lowest + third),
            bend.TurnOf(graph_method.deformed_vertices(), lowest + 2 * third, lowest + 3 * third));
}

// The multi-scale Init connects DG1 only; SetHandles connects the scale it
// selects, the same graph an eager build makes, and a bounded cache keeps the
// others. A scale dropped and connected again gives the same drag bit for bit.
TEST(GraphMethodTest, CoarseScalesAreConnectedWhenUsedAndCachedBounded) {
  const CylinderBend bend;
  DeformerOptions options = OptionsFor(Method::kMultiScale);
  options.cached_scales = 2;
  GraphMethod graph_method(options.method);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bend.mesh, options, &error)) << error;
  const int num_graphs = static_cast<int>(graph_method.graphs().size());
  ASSERT_GE(num_graphs, 5);
  EXPECT_TRUE(graph_method.graphs()[0].is_connected());
  for (int i = 1; i < num_graphs; ++i) EXPECT_FALSE(graph_method.graphs()[i].is_connected()) << i;

  ASSERT_TRUE(graph_method.SetHandles(bend.layout, &error)) << error;
  const int active = graph_method.active_graph();
  ASSERT_GT(active, 0) << "the bend should select a coarse scale";
  std::vector<DeformationGraph> eager;
  ASSERT_TRUE(
      BuildMultiScaleGraphs(bend.mesh, *graph_method.lattice(), options.graph, &eager, &error))
      << error;
  const DeformationGraph& lazy = graph_method.graphs()[active];
  ASSERT_TRUE(lazy.is_connected());
  EXPECT_EQ(lazy.edges, eager[active].edges);
  EXPECT_EQ(lazy.neighbors.values, eager[active].neighbors.values);
  EXPECT_TRUE(lazy.weights == eager[active].weights);
  ASSERT_TRUE(graph_method.Drag(bend.target, nullptr, &error)) << error;
  const Eigen::Matrix3Xd first = graph_method.deformed_vertices();

  // Using every other scale keeps at most cached_scales coarse graphs
  // connected, and never drops the one being solved on.
  for (int i = 1; i < num_graphs; ++i) {
    graph_method.ConnectedGraph(i);
    int connected = 0;
    for (int j = 1; j < num_graphs; ++j) connected += graph_method.graphs()[j].is_connected();
    EXPECT_LE(connected, options.cached_scales + 1) << i;
    EXPECT_TRUE(graph_method.graphs()[active].is_connected()) << i;
  }
  // A scale connected, dropped and connected again drags identically.
  options.cached_scales = 1;
  GraphMethod again(options.method);
  ASSERT_TRUE(again.Precompute(bend.mesh, options, &error)) << error;
  again.ConnectedGraph(active);
  for (int i = 1; i < num_graphs; ++i) {
    if (i != active) again.ConnectedGraph(i);
  }
  ASSERT_FALSE(again.graphs()[active].is_connected());
  ASSERT_TRUE(again.SetHandles(bend.layout, &error)) << error;
  ASSERT_EQ(again.active_graph(), active);
  ASSERT_TRUE(again.Drag(bend.target, nullptr, &error)) << error;
  EXPECT_EQ(again.deformed_vertices(), first);
}

TEST(GraphMethodTest, LargeFixedRegionGetsHalfFreeNodesOnlyAtItsBorder) {
  // The cylinder fixed up to z = 7 (70% of it), its top dragged sideways.
  CylinderBend bend;
  bend.layout.fixed.clear();
  for (int v = 0; v < bend.mesh.num_vertices(); ++v) {
    if (bend.mesh.vertices(2, v) < 7.0) bend.layout.fixed.push_back(v);
  }
  DeformerOptions options;
  options.num_threads = 1;
  options.selection.pin_fixed_region = false;  // Half Free nodes hold fixed vertices
  GraphMethod graph_method(options.method);
  InitOrDie(&graph_method, bend.mesh, options, bend.layout);
  const DeformationGraph& graph = graph_method.active();
  const std::vector<NodeClass>& classes = graph_method.node_classes();
  int half_free = 0;
  for (int j = 0; j < graph.num_nodes(); ++j) {
    if (classes[j] != NodeClass::kHalfFree) continue;
    ++half_free;
    bool next_to_free = false;
    for (const int* k = graph.neighbors.begin(j); k != graph.neighbors.end(j); ++k) {
      next_to_free |= classes[*k] == NodeClass::kTotallyFree;
    }
    EXPECT_TRUE(next_to_free) << "Half Free node " << j << " has no Totally Free neighbour";
  }
  EXPECT_GT(half_free, 0);
  // The paper's rule makes every node of the fixed part Half Free.
  GraphMethod paper(PaperProcedure(options).method);
  InitOrDie(&paper, bend.mesh, PaperProcedure(options), bend.layout);
  EXPECT_GT(paper.selection().num_half_free, 3 * half_free);
  EXPECT_LT(graph_method.variables(), paper.variables());
}

TEST(GraphMethodTest, LargeArmadilloEditKeepsOptimisedNodesNearP) {
  Scenario scenario;
  Mesh mesh;
  HandleLayout layout;
  std::vector<int> watch;
  HandleTransforms target;
  std::string error;
  ASSERT_TRUE(ReadScenario(DataPath("scenarios/armadillo_claw.json"), &scenario, &error)) << error;
  ASSERT_TRUE(ReadMesh(scenario.mesh_path, &mesh, &error)) << error;
  ASSERT_TRUE(ResolveScenario(scenario, mesh, &layout, &watch, &target, &error)) << error;
  DeformerOptions options;
  options.num_threads = 1;
  GraphMethod graph_method(options.method);
  InitOrDie(&graph_method, mesh, options, layout);
  const ScaleSelection& selection = graph_method.selection();
  EXPECT_GT(selection.group1_size, options.graph.nodes_per_scale);
  EXPECT_GT(selection.scale, 1);
  EXPECT_LE(selection.num_totally_free, 2 * options.graph.nodes_per_scale);
  EXPECT_GE(selection.num_totally_free, options.graph.nodes_per_scale / 2);
  EXPECT_LT(graph_method.variables(), 12 * graph_method.graphs()[0].num_nodes() / 5);
}

// What the method's Precompute reports is the precompute's: it is one.
TEST(GraphMethodTest, ItsPrecomputeIsAPrecompute) {
  const CylinderLayouts cylinder;
  for (Method method : kAllMethods) {
    std::string error;
    GraphMethod graph_method(method);
    ASSERT_TRUE(graph_method.Precompute(cylinder.mesh, CylinderOptions(method), &error)) << error;
    std::shared_ptr<const msdeform::Precompute> precompute =
        msdeform::Precompute::Create(cylinder.mesh, CylinderOptions(method), &error);
    ASSERT_NE(precompute, nullptr) << error;
    EXPECT_EQ(precompute->rest_normals(), graph_method.deformed_normals());
    EXPECT_EQ(precompute->diagonal(), graph_method.diagonal());
    EXPECT_EQ(precompute->lattice().num_particles(), graph_method.lattice()->num_particles());
    ASSERT_EQ(precompute->graphs().size(), graph_method.graphs().size());
    for (size_t i = 0; i < graph_method.graphs().size(); ++i) {
      EXPECT_EQ(precompute->graphs()[i].positions, graph_method.graphs()[i].positions) << i;
    }
    EXPECT_EQ(precompute->static_graph() < 0, method == Method::kMultiScale);
  }
}

// Every method and both warm starts that carry state from frame to frame: a
// session made by hand and the method give the same vertices, normals,
// transforms and costs on every frame of a path.
TEST(GraphMethodTest, DragsAsASessionMadeByHand) {
  const CylinderLayouts cylinder;
  const std::vector<Eigen::Affine3d> path = TurnPath(4);
  for (Method method : kAllMethods) {
    for (InitialGuess guess : {InitialGuess::kPrevious, InitialGuess::kExtrapolated}) {
      DeformerOptions options = CylinderOptions(method);
      options.initial_guess = guess;
      GraphMethod graph_method(options.method);
      std::string error;
      ASSERT_TRUE(graph_method.Precompute(cylinder.mesh, options, &error)) << error;
      ASSERT_TRUE(graph_method.SetHandles(cylinder.bottom_fixed, &error)) << error;
      std::unique_ptr<Session> session = MakeSession(cylinder.mesh, options, cylinder.bottom_fixed);
      ASSERT_NE(session, nullptr);
      EXPECT_EQ(session->setup().active_graph(), graph_method.active_graph());
      EXPECT_EQ(session->deformed_vertices(), cylinder.mesh.vertices);
      for (size_t f = 0; f < path.size(); ++f) {
        DragStats by_deformer, by_session;
        ASSERT_TRUE(graph_method.Drag(path[f], &by_deformer, &error)) << error;
        ASSERT_TRUE(session->Drag(path[f], &by_session, &error)) << error;
        EXPECT_EQ(session->deformed_vertices(), graph_method.deformed_vertices()) << f;
        EXPECT_EQ(session->transforms().rotations, graph_method.transforms().rotations) << f;
        EXPECT_EQ(session->transforms().translations, graph_method.transforms().translations) << f;
        EXPECT_EQ(by_session.final_cost, by_deformer.final_cost) << f;
        EXPECT_EQ(by_session.iterations, by_deformer.iterations) << f;
      }
      EXPECT_EQ(session->deformed_normals(), graph_method.deformed_normals());
      EXPECT_NE(session->deformed_vertices(), cylinder.mesh.vertices);
    }
  }
}

}  // namespace
}  // namespace msdeform
