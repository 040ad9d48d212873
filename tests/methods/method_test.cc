// Every registered method through the one interface (methods/method.h):
// stage order, and small edits of a procedural bar with known answers.

#include "msdeform/methods/method.h"

#include <cmath>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "msdeform/core/procedural_meshes.h"
#include "msdeform/methods/graph_method.h"
#include "msdeform/methods/method_options.h"
#include "msdeform/methods/registry.h"
#include "tests/scales/deformer_test_util.h"
#include "tests/test_util.h"

namespace msdeform {
namespace {

Eigen::Affine3d RigidMotion() {
  Eigen::Affine3d motion = Eigen::Affine3d::Identity();
  motion.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()));
  motion.pretranslate(Eigen::Vector3d(0.3, -1.2, 2.0));
  return motion;
}

class MethodTest : public testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<EditingMethod> Create() {
    std::string error;
    std::unique_ptr<EditingMethod> method = CreateMethod(GetParam(), &error);
    EXPECT_NE(method, nullptr) << error;
    return method;
  }
  MethodOptions options_;
  std::string error_;
};

TEST_P(MethodTest, CallsOutOfOrderAreRefused) {
  const BarEdit bar(8, 2);
  std::unique_ptr<EditingMethod> method = Create();
  EXPECT_FALSE(method->SetHandles(bar.layout, &error_));
  EXPECT_EQ(error_, GetParam() + ": SetHandles before a successful Precompute");
  EXPECT_FALSE(method->Drag(Lift(1.0), nullptr, &error_));
  EXPECT_EQ(error_, GetParam() + ": Drag before a successful SetHandles");
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  EXPECT_FALSE(method->Drag(Lift(1.0), nullptr, &error_));
  EXPECT_EQ(error_, GetParam() + ": Drag before a successful SetHandles");
  // An invalid layout (a vertex both fixed and moveable) leaves no layout.
  HandleLayout overlapping = bar.layout;
  overlapping.fixed.push_back(bar.layout.moveable[0]);
  std::sort(overlapping.fixed.begin(), overlapping.fixed.end());
  ASSERT_TRUE(method->SetHandles(bar.layout, &error_)) << error_;
  EXPECT_FALSE(method->SetHandles(overlapping, &error_));
  EXPECT_FALSE(method->handles_set());
  EXPECT_FALSE(method->Drag(Lift(1.0), nullptr, &error_));
  // A failed Precompute (a mesh with no faces) leaves the method empty.
  Mesh empty;
  EXPECT_FALSE(method->Precompute(empty, options_, &error_));
  EXPECT_FALSE(method->precomputed());
  EXPECT_FALSE(method->SetHandles(bar.layout, &error_));
}

TEST_P(MethodTest, WholeMeshAsHandleMovesRigidly) {
  const BarEdit bar(8, 2);
  HandleLayout all;
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) all.moveable.push_back(v);
  std::unique_ptr<EditingMethod> method = Create();
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(method->SetHandles(all, &error_)) << error_;
  MethodStats stats;
  ASSERT_TRUE(method->Drag(RigidMotion(), &stats, &error_)) << error_;
  const Eigen::Matrix3Xd expected = RigidMotion() * bar.mesh.vertices;
  // The bar's diagonal is about 8.1; 1e-6 of it.
  EXPECT_LT((method->deformed_vertices() - expected).cwiseAbs().maxCoeff(), 1e-5);
  // A method whose unknowns are the free vertices has none here: nothing to iterate.
  if (method->variables() > 0) {
    EXPECT_GT(stats.iterations, 0);
  }
  EXPECT_GE(stats.frame_ms, stats.solve_ms);
}

TEST_P(MethodTest, IdentityDragLeavesTheMeshAtRest) {
  const BarEdit bar(8, 2);
  std::unique_ptr<EditingMethod> method = Create();
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(method->SetHandles(bar.layout, &error_)) << error_;
  ASSERT_TRUE(method->Drag(Eigen::Affine3d::Identity(), nullptr, &error_)) << error_;
  EXPECT_LT((method->deformed_vertices() - bar.mesh.vertices).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_P(MethodTest, LiftKeepsTheFixedVerticesAndMovesTheHandle) {
  const BarEdit bar(8, 2);
  std::unique_ptr<EditingMethod> method = Create();
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(method->SetHandles(bar.layout, &error_)) << error_;
  EXPECT_GT(method->nodes_optimized(), 0);
  EXPECT_GT(method->variables(), 0);
  for (int frame = 1; frame <= 3; ++frame) {
    ASSERT_TRUE(method->Drag(Lift(0.5 * frame), nullptr, &error_)) << error_;
  }
  const Eigen::Matrix3Xd& deformed = method->deformed_vertices();
  // The fixed vertices: exactly at rest, but for the static baselines, whose
  // fixed handle is held by position terms (GraphMethod::fixed_region_exact).
  const GraphMethod* deformer = method->graph_method();
  const bool exact = deformer == nullptr || deformer->fixed_region_exact();
  double fixed_moved = 0.0;
  for (int v : bar.layout.fixed) {
    fixed_moved = std::max(fixed_moved, (deformed.col(v) - bar.mesh.vertices.col(v)).norm());
  }
  if (exact) {
    EXPECT_EQ(fixed_moved, 0.0);
  } else {
    EXPECT_LT(fixed_moved, 0.1 * 1.5);  // held by w_con = 100 against a 1.5 lift
  }
  // The handle follows the lift: exactly for CGAL and FastLSM (driven), by
  // position terms for the graph methods.
  double handle_error = 0.0;
  for (int v : bar.layout.moveable) {
    handle_error = std::max(
        handle_error, (deformed.col(v) - Lift(1.5) * bar.mesh.vertices.col(v)).norm());
  }
  EXPECT_LT(handle_error, deformer == nullptr ? 1e-12 : 0.1 * 1.5);
  // The free middle moves up but less than the handle.
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
    if (std::abs(bar.mesh.vertices(0, v) - 4.0) > 0.01) continue;
    const double rise = deformed(2, v) - bar.mesh.vertices(2, v);
    EXPECT_GT(rise, 0.0) << "vertex " << v;
    EXPECT_LT(rise, 1.5) << "vertex " << v;
  }
}

// Two handle groups on a bar (core/handles.h): the middle fixed, the left
// end lifted and the right end lowered, each by its own transform.
struct TwoHandleBar {
  Mesh mesh = MakeBar(12, 1.0, 2);
  HandleLayout layout;
  HandleTransforms transforms{{Lift(1.0), Lift(-1.0)}};
  TwoHandleBar() {
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      const double x = mesh.vertices(0, v);
      if (std::abs(x - 6.0) <= 1.0) layout.fixed.push_back(v);
      if (x <= 1.0 || x >= 11.0) {
        layout.moveable.push_back(v);
        layout.group.push_back(x <= 1.0 ? 0 : 1);
      }
    }
  }
  // Largest distance of a handle vertex from its group's target.
  double HandleError(const Eigen::Matrix3Xd& deformed) const {
    double error = 0.0;
    for (size_t i = 0; i < layout.moveable.size(); ++i) {
      const int v = layout.moveable[i];
      error = std::max(error, (deformed.col(v) - transforms[layout.group[i]] *
                                                     Eigen::Vector3d(mesh.vertices.col(v)))
                                  .norm());
    }
    return error;
  }
};

TEST_P(MethodTest, TwoHandleGroupsEachFollowTheirOwnTransform) {
  const TwoHandleBar bar;
  std::unique_ptr<EditingMethod> method = Create();
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(method->SetHandles(bar.layout, &error_)) << error_;
  EXPECT_EQ(method->num_handle_groups(), 2);
  // Three transforms for two groups: refused, the pose kept.
  EXPECT_FALSE(method->Drag(HandleTransforms({Lift(1.0), Lift(1.0), Lift(1.0)}), nullptr,
                            &error_));
  EXPECT_EQ(error_, "3 handle transforms for a layout of 2 handle groups (give one, or one a "
                    "group)");
  ASSERT_TRUE(method->Drag(bar.transforms, nullptr, &error_)) << error_;
  const Eigen::Matrix3Xd& deformed = method->deformed_vertices();
  // Exact for the methods that place the handle (CGAL, FastLSM, full_arap,
  // rigid_cells), by position terms (w_con = 100) for the graph methods.
  EXPECT_LT(bar.HandleError(deformed), method->graph_method() == nullptr ? 1e-12 : 0.1);
  const GraphMethod* deformer = method->graph_method();
  if (deformer == nullptr || deformer->fixed_region_exact()) {
    for (int v : bar.layout.fixed) EXPECT_EQ(deformed.col(v), bar.mesh.vertices.col(v)) << v;
  }
  // Between the fixed middle and each end the bar follows that end: up on
  // the left, down on the right.
  for (int v = 0; v < bar.mesh.num_vertices(); ++v) {
    const double x = bar.mesh.vertices(0, v), rise = deformed(2, v) - bar.mesh.vertices(2, v);
    if (std::abs(x - 3.0) < 0.01) {
      EXPECT_GT(rise, 0.0) << "vertex " << v;
    }
    if (std::abs(x - 9.0) < 0.01) {
      EXPECT_LT(rise, 0.0) << "vertex " << v;
    }
  }
}

TEST_P(MethodTest, OneTransformMovesEveryGroupAsOneHandleWould) {
  // Two groups given one transform, and the same vertices as one group.
  const TwoHandleBar bar;
  HandleLayout one_group = bar.layout;
  one_group.group.clear();
  std::unique_ptr<EditingMethod> two = Create(), one = Create();
  ASSERT_TRUE(two->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(one->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(two->SetHandles(bar.layout, &error_)) << error_;
  ASSERT_TRUE(one->SetHandles(one_group, &error_)) << error_;
  ASSERT_TRUE(two->Drag(Lift(1.0), nullptr, &error_)) << error_;
  ASSERT_TRUE(one->Drag(Lift(1.0), nullptr, &error_)) << error_;
  EXPECT_LT(MaxDistance(two->deformed_vertices(), one->deformed_vertices()), 1e-9);
}

TEST_P(MethodTest, VertexTargetsAreTakenOneByOneOrRefused) {
  // Targets that bend the handle (no transform moves it there): a method
  // that places the handle vertices one by one reaches each exactly; the
  // others refuse them and keep the pose.
  const BarEdit bar(8, 2);
  std::unique_ptr<EditingMethod> method = Create();
  ASSERT_TRUE(method->Precompute(bar.mesh, options_, &error_)) << error_;
  ASSERT_TRUE(method->SetHandles(bar.layout, &error_)) << error_;
  Eigen::Matrix3Xd targets(3, bar.layout.moveable.size());
  for (size_t i = 0; i < bar.layout.moveable.size(); ++i) {
    const Eigen::Vector3d rest = bar.mesh.vertices.col(bar.layout.moveable[i]);
    targets.col(i) = rest + Eigen::Vector3d(0.0, 0.0, 0.5 + 0.3 * rest.y() * rest.y());
  }
  EXPECT_FALSE(method->DragTo(targets.leftCols(3), nullptr, &error_));
  if (method->takes_vertex_targets()) {
    EXPECT_EQ(error_, "3 targets for " + std::to_string(bar.layout.moveable.size()) +
                          " moveable vertices");
    ASSERT_TRUE(method->DragTo(targets, nullptr, &error_)) << error_;
    for (size_t i = 0; i < bar.layout.moveable.size(); ++i) {
      EXPECT_LT((method->deformed_vertices().col(bar.layout.moveable[i]) - targets.col(i)).norm(),
                1e-12);
    }
  } else {
    EXPECT_EQ(error_, GetParam() + " moves the handle by a transform a handle group, not by "
                                   "vertex targets");
    EXPECT_EQ(method->deformed_vertices(), bar.mesh.vertices);
  }
}

TEST(TwoHandleGroupsTest, TheSubspaceArapEnergyHoldsBothGroupsExactly) {
  // --energy=arap places the handle vertices exactly (its exact constraints),
  // each group at its own transform.
  const TwoHandleBar bar;
  for (const char* name : {"multiscale", "static"}) {
    std::string error;
    std::unique_ptr<EditingMethod> method = CreateMethod(name, &error);
    ASSERT_NE(method, nullptr) << error;
    MethodOptions options;
    options.deformer.energy = Energy::kArap;
    ASSERT_TRUE(method->Precompute(bar.mesh, options, &error)) << error;
    ASSERT_TRUE(method->SetHandles(bar.layout, &error)) << error;
    ASSERT_TRUE(method->Drag(bar.transforms, nullptr, &error)) << error;
    EXPECT_LT(bar.HandleError(method->deformed_vertices()), 1e-12) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, MethodTest, testing::ValuesIn(MethodNames()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

}  // namespace
}  // namespace msdeform
