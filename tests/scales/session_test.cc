// The per-drag stage (scales/session.h): sessions of one set-up are
// independent, and a bad frame is refused without losing the last good one.
// That GraphMethod drags as its session: tests/methods/graph_method_test.cc.

#include <limits>
#include <memory>
#include <type_traits>
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

// The stages cannot be made but from the one before (no default, no copy).
static_assert(!std::is_default_constructible<Precompute>::value);
static_assert(!std::is_default_constructible<HandleSetup>::value);
static_assert(!std::is_default_constructible<Session>::value);
static_assert(!std::is_copy_constructible<HandleSetup>::value);
static_assert(!std::is_copy_constructible<Session>::value);

// Two sessions of one set-up: the second starts at rest whatever the first
// did, and drags exactly like a session of its own precompute.
TEST(SessionTest, SessionsOfOneSetupAreIndependent) {
  const CylinderLayouts cylinder;
  const DeformerOptions options = CylinderOptions(Method::kMultiScale);
  const std::vector<Eigen::Affine3d> path = TurnPath(3);
  std::string error;
  std::shared_ptr<const Precompute> precompute =
      Precompute::Create(cylinder.mesh, options, &error);
  ASSERT_NE(precompute, nullptr) << error;
  std::shared_ptr<const HandleSetup> setup =
      HandleSetup::Create(precompute, cylinder.bottom_fixed, &error);
  ASSERT_NE(setup, nullptr) << error;
  std::unique_ptr<Session> first = Session::Create(setup, &error);
  ASSERT_NE(first, nullptr) << error;
  for (const Eigen::Affine3d& step : path) ASSERT_TRUE(first->Drag(step, nullptr, &error)) << error;

  std::unique_ptr<Session> second = Session::Create(setup, &error);
  ASSERT_NE(second, nullptr) << error;
  EXPECT_EQ(second->deformed_vertices(), cylinder.mesh.vertices);
  std::unique_ptr<Session> alone = MakeSession(cylinder.mesh, options, cylinder.bottom_fixed);
  ASSERT_TRUE(second->Drag(path[0], nullptr, &error)) << error;
  ASSERT_TRUE(alone->Drag(path[0], nullptr, &error)) << error;
  EXPECT_EQ(second->deformed_vertices(), alone->deformed_vertices());
  // The first session goes on from its own frames, untouched by the second:
  // as a session that made the same frames alone.
  std::unique_ptr<Session> same_frames = MakeSession(cylinder.mesh, options, cylinder.bottom_fixed);
  for (const Eigen::Affine3d& step : path) {
    ASSERT_TRUE(same_frames->Drag(step, nullptr, &error)) << error;
  }
  ASSERT_TRUE(first->Drag(path[0], nullptr, &error)) << error;
  ASSERT_TRUE(same_frames->Drag(path[0], nullptr, &error)) << error;
  EXPECT_EQ(first->deformed_vertices(), same_frames->deformed_vertices());
  EXPECT_EQ(first->transforms().rotations, same_frames->transforms().rotations);
}

// A non-finite handle is refused with a message and keeps the last frame.
TEST(SessionTest, NonFiniteHandleIsRefusedAndKeepsTheLastFrame) {
  const CylinderLayouts cylinder;
  std::unique_ptr<Session> session =
      MakeSession(cylinder.mesh, CylinderOptions(Method::kStatic), cylinder.bottom_fixed);
  std::string error;
  ASSERT_TRUE(session->Drag(TurnPath(1)[0], nullptr, &error)) << error;
  const Eigen::Matrix3Xd good = session->deformed_vertices();
  Eigen::Affine3d bad = Eigen::Affine3d::Identity();
  bad.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(session->Drag(bad, nullptr, &error));
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
  EXPECT_EQ(session->deformed_vertices(), good);
}

}  // namespace
}  // namespace msdeform
