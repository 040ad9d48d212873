// The editor's status line (apps/editor/status_line.h): a message about the
// handle layout goes when what it says stops being true.

#include "apps/editor/status_line.h"

#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "apps/editor/edit_inputs.h"
#include "apps/editor/inline_scenario.h"
#include "tests/editor/editor_test_util.h"

namespace msdeform {
namespace editor {
namespace {

// What the window does on a stroke's end: commit, and show why not.
void EndStroke(EditSession* session, StatusLine* status) {
  std::string why;
  if (!session->CommitLayout(&why)) status->Show(why, Until::kMoveableHandle);
  status->Update(*session);
}

// Paint the fixed region, then the handle, then drag: the "no moveable
// handle" of the first stroke is gone by the drag.
TEST(StatusLineTest, NoMoveableHandleGoesOnceAHandleIsPainted) {
  EditSession session;
  ASSERT_NO_FATAL_FAILURE(OpenCactusMesh(&session));
  std::string error;
  StatusLine status;

  std::vector<int> fixed, handle;
  ASSERT_TRUE(SelectInlineRegion({{"slab", {{"axis", "y"}, {"from", 0}, {"to", 0.1}}}},
                                 session.mesh(), "t", &fixed, &error))
      << error;
  session.Label(fixed, VertexLabel::kFixed);
  EndStroke(&session, &status);
  EXPECT_EQ(status.text(), "no moveable handle: paint one (tool Handle) to drag");
  session.Poll();
  status.Update(session);  // a frame later: still no handle
  EXPECT_EQ(status.text(), "no moveable handle: paint one (tool Handle) to drag");

  ASSERT_TRUE(SelectInlineRegion({{"sphere", {{"center_vertex", 95}, {"radius_rel", 0.1}}}},
                                 session.mesh(), "t", &handle, &error))
      << error;
  session.Label(handle, VertexLabel::kHandle);
  EndStroke(&session, &status);
  session.Wait();
  ASSERT_TRUE(session.ready()) << session.error();
  Eigen::Affine3d lift = Eigen::Affine3d::Identity();
  lift.translate(Eigen::Vector3d(0, 0.05, 0));
  ASSERT_TRUE(session.Drag(lift, &error)) << error;
  session.Poll();
  status.Update(session);
  EXPECT_EQ(status.text(), "");

  // Erasing the handle brings the message back.
  session.Label(handle, VertexLabel::kFree);
  EndStroke(&session, &status);
  EXPECT_EQ(status.text(), "no moveable handle: paint one (tool Handle) to drag");
}

TEST(StatusLineTest, OtherMessagesStayUntilReplaced) {
  EditSession session;  // no mesh: not busy, no handle
  StatusLine status;
  status.Show("wrote /tmp/a.png");
  status.Update(session);
  EXPECT_EQ(status.text(), "wrote /tmp/a.png");
  status.Show("wait: the new layout is being set up", Until::kSetUp);
  status.Update(session);  // nothing is being set up
  EXPECT_EQ(status.text(), "");
  status.Show("paint a moveable handle (H) before dragging", Until::kMoveableHandle);
  status.Update(session);
  EXPECT_EQ(status.text(), "paint a moveable handle (H) before dragging");
  status.Clear();
  EXPECT_EQ(status.text(), "");
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
