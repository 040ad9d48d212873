// The per-handle-layout stage (scales/handle_setup.h): set-ups made from one
// precompute give what separate precomputes give, the graph a set-up solves on
// stays connected however the precompute's cache is used meanwhile, and a
// set-up that cannot be made is refused with a message.

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "msdeform/scales/handle_setup.h"
#include "msdeform/scales/precompute.h"
#include "msdeform/scales/session.h"
#include "tests/scales/deformer_test_util.h"

namespace msdeform {
namespace {

// The frames of one handle layout and path on a precompute of its own:
// vertices after each frame.
std::vector<Eigen::Matrix3Xd> FramesAlone(const Mesh& mesh, const DeformerOptions& options,
                                          const HandleLayout& handles,
                                          const std::vector<Eigen::Affine3d>& path,
                                          int* active_graph) {
  std::shared_ptr<const HandleSetup> setup = MakeHandleSetup(mesh, options, handles);
  if (setup == nullptr) return {};
  *active_graph = setup->active_graph();
  std::string error;
  std::unique_ptr<Session> session = Session::Create(setup, &error);
  EXPECT_NE(session, nullptr) << error;
  if (session == nullptr) return {};
  std::vector<Eigen::Matrix3Xd> frames;
  for (const Eigen::Affine3d& step : path) {
    EXPECT_TRUE(session->Drag(step, nullptr, &error)) << error;
    frames.push_back(session->deformed_vertices());
  }
  return frames;
}

// Two handle layouts of one precompute, both alive and dragged in turns, give
// the frames of two precomputes of their own, bit for bit, for every method. With one cached
// coarse scale, the second layout's scale selection connects other graphs:
// the first layout's graph stays connected (pinned) all the same.
TEST(HandleSetupTest, TwoLayoutsOfOnePrecomputeMatchTwoPrecomputes) {
  const CylinderLayouts cylinder;
  const std::vector<Eigen::Affine3d> path = TurnPath(3);
  for (Method method : kAllMethods) {
    DeformerOptions options = CylinderOptions(method);
    options.cached_scales = 1;
    int bottom_graph = -1, top_graph = -1;
    const std::vector<Eigen::Matrix3Xd> bottom =
        FramesAlone(cylinder.mesh, options, cylinder.bottom_fixed, path, &bottom_graph);
    const std::vector<Eigen::Matrix3Xd> top =
        FramesAlone(cylinder.mesh, options, cylinder.top_fixed, path, &top_graph);

    std::string error;
    std::shared_ptr<const Precompute> precompute =
        Precompute::Create(cylinder.mesh, options, &error);
    ASSERT_NE(precompute, nullptr) << error;
    std::shared_ptr<const HandleSetup> first =
        HandleSetup::Create(precompute, cylinder.bottom_fixed, &error);
    ASSERT_NE(first, nullptr) << error;
    std::shared_ptr<const HandleSetup> second =
        HandleSetup::Create(precompute, cylinder.top_fixed, &error);
    ASSERT_NE(second, nullptr) << error;
    EXPECT_EQ(first->active_graph(), bottom_graph);
    EXPECT_EQ(second->active_graph(), top_graph);
    // Every graph used once more: the cache drops all but the layouts'.
    for (int i = 0; i < static_cast<int>(precompute->graphs().size()); ++i) {
      precompute->ConnectedGraph(i);
    }
    EXPECT_TRUE(first->graph().is_connected());
    EXPECT_TRUE(second->graph().is_connected());

    std::unique_ptr<Session> first_session = Session::Create(first, &error);
    ASSERT_NE(first_session, nullptr) << error;
    std::unique_ptr<Session> second_session = Session::Create(second, &error);
    ASSERT_NE(second_session, nullptr) << error;
    for (size_t f = 0; f < path.size(); ++f) {
      ASSERT_TRUE(first_session->Drag(path[f], nullptr, &error)) << error;
      ASSERT_TRUE(second_session->Drag(path[f], nullptr, &error)) << error;
      EXPECT_EQ(first_session->deformed_vertices(), bottom[f]) << MethodName(method) << " " << f;
      EXPECT_EQ(second_session->deformed_vertices(), top[f]) << MethodName(method) << " " << f;
    }
  }
}

// The multi-scale selection picks a coarse scale for both cylinder layouts,
// so the pin in the test above guards a graph the cache could drop.
TEST(HandleSetupTest, CylinderLayoutsSelectCoarseScales) {
  const CylinderLayouts cylinder;
  std::string error;
  DeformerOptions options = CylinderOptions(Method::kMultiScale);
  options.cached_scales = 1;
  std::shared_ptr<const Precompute> precompute =
      Precompute::Create(cylinder.mesh, options, &error);
  ASSERT_NE(precompute, nullptr) << error;
  std::shared_ptr<const HandleSetup> setup =
      HandleSetup::Create(precompute, cylinder.bottom_fixed, &error);
  ASSERT_NE(setup, nullptr) << error;
  const int active = setup->active_graph();
  ASSERT_GT(active, 0);
  // The scales the selection tried were pinned only while it ran: the cache
  // is back within its bound, the set-up's graph in it.
  int connected = 0;
  for (size_t i = 1; i < precompute->graphs().size(); ++i) {
    connected += precompute->graphs()[i].is_connected();
  }
  EXPECT_EQ(connected, 1);
  EXPECT_TRUE(setup->graph().is_connected());
  const int other = active == 1 ? 2 : 1;
  // Pinned while the set-up lives: another coarse scale does not evict it.
  precompute->ConnectedGraph(other);
  EXPECT_TRUE(precompute->graphs()[active].is_connected());
  // Unpinned once the set-up is gone: the next use of the cache evicts it.
  setup.reset();
  precompute->ConnectedGraph(other);
  EXPECT_FALSE(precompute->graphs()[active].is_connected());
}

// The set-up's own checks: a vertex out of range, a fixed and a moveable
// vertex in one lattice cell; each is refused with a message, and the
// precompute serves the next set-up as before.
TEST(HandleSetupTest, BadLayoutsAreRefusedWithAMessage) {
  const CylinderLayouts cylinder;
  std::string error;
  std::shared_ptr<const Precompute> precompute =
      Precompute::Create(cylinder.mesh, CylinderOptions(Method::kMultiScale), &error);
  ASSERT_NE(precompute, nullptr) << error;
  HandleLayout out_of_range = cylinder.bottom_fixed;
  out_of_range.moveable.push_back(cylinder.mesh.num_vertices());
  EXPECT_EQ(HandleSetup::Create(precompute, out_of_range, &error), nullptr);
  EXPECT_FALSE(error.empty());
  // A fixed vertex made moveable: in one lattice cell with fixed ones.
  HandleLayout shared_cell = cylinder.bottom_fixed;
  const Lattice& lattice = precompute->lattice();
  for (size_t i = 1; i < shared_cell.fixed.size(); ++i) {
    const int v = shared_cell.fixed[i];
    if (lattice.particle_of_vertex(v) != lattice.particle_of_vertex(shared_cell.fixed[0])) continue;
    shared_cell.fixed.erase(shared_cell.fixed.begin() + i);
    shared_cell.moveable.push_back(v);
    std::sort(shared_cell.moveable.begin(), shared_cell.moveable.end());
    break;
  }
  ASSERT_LT(shared_cell.fixed.size(), cylinder.bottom_fixed.fixed.size());
  error.clear();
  EXPECT_EQ(HandleSetup::Create(precompute, shared_cell, &error), nullptr);
  EXPECT_NE(error.find("lattice cell"), std::string::npos) << error;
  EXPECT_NE(HandleSetup::Create(precompute, cylinder.bottom_fixed, &error), nullptr) << error;
}

}  // namespace
}  // namespace msdeform
