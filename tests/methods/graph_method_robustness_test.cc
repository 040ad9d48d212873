// Robustness of the graph_method (issue 9): meshes with several components,
// singular systems, failed solves, random rigid motions, determinism. Kept
// apart from graph_method_test.cc, which checks the method itself.

#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/core/drag_path.h"
#include "msdeform/core/handles.h"
#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/graph_method.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

// Two bars side by side along y; the first (y < 1) has its first voxel fixed
// and its last voxel as the handle; the second has no handle at all.
struct TwoBars {
  Mesh mesh = MakeTwoBars(8, 2, 1.0, 2);
  HandleLayout layout;
  std::vector<int> second_bar;
  TwoBars() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double x = mesh.vertices(0, v), y = mesh.vertices(1, v);
      if (y > 1.5) {
        second_bar.push_back(v);
      } else if (x <= 1.0) {
        layout.fixed.push_back(v);
      } else if (x >= 7.0) {
        layout.moveable.push_back(v);
      }
    }
  }
};

TEST(GraphMethodRobustnessTest, ComponentWithoutHandleStaysAndHasNoVariables) {
  const TwoBars bars;
  ASSERT_GT(bars.second_bar.size(), 0u);
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 0.0, 2.0;
  lift.rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  for (Method method : kAllMethods) {
    GraphMethod graph_method(method);
    std::string error;
    ASSERT_TRUE(graph_method.Precompute(bars.mesh, OptionsFor(method), &error)) << error;
    ASSERT_TRUE(graph_method.SetHandles(bars.layout, &error)) << error;
    const Eigen::Vector3d handle_centre(7.5, 0.5, 0.5);
    for (const Eigen::Affine3d& frame : InterpolateDragPath(lift, handle_centre, 3)) {
      ASSERT_TRUE(graph_method.Drag(frame, nullptr, &error)) << error;
    }
    const Eigen::Matrix3Xd& deformed = graph_method.deformed_vertices();
    ASSERT_TRUE(deformed.allFinite()) << MethodName(method);
    for (int v : bars.second_bar) {
      ASSERT_EQ(deformed.col(v), bars.mesh.vertices.col(v))
          << MethodName(method) << " vertex " << v;
    }
    // The handle did move.
    EXPECT_GT(MaxDistance(deformed, bars.mesh.vertices), 1.0) << MethodName(method);
    // Every node of the second bar is Fixed: its node sits on a second-bar vertex.
    const DeformationGraph& graph = graph_method.active();
    for (int j = 0; j < graph.num_nodes(); ++j) {
      if (bars.mesh.vertices(1, graph.node_vertex[j]) > 1.5) {
        EXPECT_EQ(graph_method.node_classes()[j], NodeClass::kFixed)
            << MethodName(method) << " " << j;
      }
    }
  }
}

// A static graph of one node spans both bars (edge collapse merges across
// components once no edge is left): the node moves with the handle, and the
// second bar still stays at rest, bit for bit.
TEST(GraphMethodRobustnessTest, ComponentWithoutHandleStaysWhenANodeSpansBothComponents) {
  const TwoBars bars;
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 0.0, 2.0;
  for (int static_nodes : {1, 2, 3}) {
    DeformerOptions options = OptionsFor(Method::kStatic);
    options.static_nodes = static_nodes;
    GraphMethod graph_method(options.method);
    std::string error;
    ASSERT_TRUE(graph_method.Precompute(bars.mesh, options, &error)) << error;
    ASSERT_TRUE(graph_method.SetHandles(bars.layout, &error)) << error;
    ASSERT_TRUE(graph_method.Drag(lift, nullptr, &error)) << error;
    const Eigen::Matrix3Xd& deformed = graph_method.deformed_vertices();
    for (int v : bars.second_bar) {
      ASSERT_EQ(deformed.col(v), bars.mesh.vertices.col(v)) << static_nodes << " vertex " << v;
    }
    EXPECT_GT(MaxDistance(deformed, bars.mesh.vertices), 0.5) << static_nodes;
  }
}

// An isolated vertex (in no face) is a mesh component of its own: without a
// moveable-handle vertex it stays at rest, even inside the dragged end.
TEST(GraphMethodRobustnessTest, IsolatedVertexIsAComponentOfItsOwn) {
  TwoBars bars;
  Mesh& mesh = bars.mesh;
  const int isolated = mesh.num_vertices();
  mesh.vertices.conservativeResize(3, isolated + 1);
  mesh.vertices.col(isolated) << 7.5, 0.5, 0.5;  // inside the handle end of the first bar
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 0.0, 2.0;
  for (Method method : kAllMethods) {
    GraphMethod graph_method(method);
    std::string error;
    ASSERT_TRUE(graph_method.Precompute(mesh, OptionsFor(method), &error)) << error;
    ASSERT_TRUE(graph_method.SetHandles(bars.layout, &error)) << error;
    ASSERT_TRUE(graph_method.Drag(lift, nullptr, &error)) << error;
    const Eigen::Matrix3Xd& deformed = graph_method.deformed_vertices();
    EXPECT_EQ(deformed.col(isolated), mesh.vertices.col(isolated)) << MethodName(method);
    EXPECT_GT(MaxDistance(deformed, mesh.vertices), 1.0) << MethodName(method);
    for (int v : bars.second_bar) {
      ASSERT_EQ(deformed.col(v), mesh.vertices.col(v)) << MethodName(method) << " vertex " << v;
    }
  }
}

TEST(GraphMethodRobustnessTest, FailedSolveKeepsTheLastGoodFrame) {
  const TwoBars bars;
  GraphMethod graph_method(Method::kMultiScale);
  std::string error;
  ASSERT_TRUE(graph_method.Precompute(bars.mesh, OptionsFor(Method::kMultiScale), &error)) << error;
  ASSERT_TRUE(graph_method.SetHandles(bars.layout, &error)) << error;
  Eigen::Affine3d good = Eigen::Affine3d::Identity();
  good.translation() << 0.0, 0.0, 1.0;
  ASSERT_TRUE(graph_method.Drag(good, nullptr, &error)) << error;
  const Eigen::Matrix3Xd good_vertices = graph_method.deformed_vertices();

  // A finite but absurd target overflows the cost: the solve fails.
  Eigen::Affine3d absurd = Eigen::Affine3d::Identity();
  absurd.translation() << 1e300, 1e300, 0.0;
  EXPECT_FALSE(graph_method.Drag(absurd, nullptr, &error));
  EXPECT_NE(error.find("kept the last good frame"), std::string::npos) << error;
  EXPECT_EQ(graph_method.deformed_vertices(), good_vertices);
  EXPECT_TRUE(graph_method.transforms().rotations.allFinite());
  EXPECT_TRUE(graph_method.transforms().translations.allFinite());

  // A non-finite target is refused before solving.
  Eigen::Affine3d nan_target = Eigen::Affine3d::Identity();
  nan_target.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(graph_method.Drag(nan_target, nullptr, &error));
  EXPECT_EQ(graph_method.deformed_vertices(), good_vertices);

  // And the drag goes on from the last good frame.
  Eigen::Affine3d next = good;
  next.translation().z() = 1.5;
  ASSERT_TRUE(graph_method.Drag(next, nullptr, &error)) << error;
  EXPECT_TRUE(graph_method.deformed_vertices().allFinite());
}

TEST(GraphMethodRobustnessTest, RandomRigidMotionsOfAWholeMeshHandleAreRigid) {
  const Mesh mesh = MakeBar(8, 1.0, 2);
  HandleLayout everything;
  for (int v = 0; v < mesh.num_vertices(); ++v) everything.moveable.push_back(v);
  std::mt19937 random(20080101);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (Method method : kAllMethods) {
    GraphMethod graph_method(method);
    std::string error;
    ASSERT_TRUE(graph_method.Precompute(mesh, OptionsFor(method), &error)) << error;
    for (int trial = 0; trial < 3; ++trial) {
      ASSERT_TRUE(graph_method.SetHandles(everything, &error)) << error;
      const Eigen::Vector3d axis =
          Eigen::Vector3d(uniform(random), uniform(random), uniform(random)).normalized();
      Eigen::Affine3d motion = Eigen::Affine3d::Identity();
      motion.translation() << 3.0 * uniform(random), 3.0 * uniform(random), 3.0 * uniform(random);
      motion.rotate(Eigen::AngleAxisd(1.5 * uniform(random), axis));
      for (const Eigen::Affine3d& frame :
           InterpolateDragPath(motion, mesh.vertices.rowwise().mean(), 3)) {
        ASSERT_TRUE(graph_method.Drag(frame, nullptr, &error)) << error;
      }
      EXPECT_LT(MaxDistance(graph_method.deformed_vertices(), motion * mesh.vertices), 1e-6)
          << MethodName(method) << " trial " << trial;
    }
  }
}

TEST(GraphMethodRobustnessTest, SameInputsGiveBitIdenticalResults) {
  const TwoBars bars;
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translation() << 0.0, 0.5, 1.0;
  Eigen::Matrix3Xd first;
  for (int run = 0; run < 2; ++run) {
    GraphMethod graph_method(Method::kMultiScale);
    std::string error;
    DeformerOptions options = OptionsFor(Method::kMultiScale);
    options.num_threads = 2;
    ASSERT_TRUE(graph_method.Precompute(bars.mesh, options, &error)) << error;
    ASSERT_TRUE(graph_method.SetHandles(bars.layout, &error)) << error;
    ASSERT_TRUE(graph_method.Drag(lift, nullptr, &error)) << error;
    if (run == 0) {
      first = graph_method.deformed_vertices();
    } else {
      EXPECT_EQ(graph_method.deformed_vertices(), first);
    }
  }
}

}  // namespace
}  // namespace msdeform
