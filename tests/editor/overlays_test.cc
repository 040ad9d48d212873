// The editor's overlay colours (apps/editor/overlays.h).

#include "apps/editor/overlays.h"

#include <gtest/gtest.h>

#include <vector>

namespace msdeform {
namespace editor {
namespace {

// The e' map colours the free vertices; the fixed and handle vertices keep
// their label colours over it.
TEST(OverlaysTest, TheRigidityMapKeepsTheHandleColours) {
  const std::vector<VertexLabel> labels = {VertexLabel::kFixed, VertexLabel::kFree,
                                           VertexLabel::kHandle, VertexLabel::kFree};
  Eigen::VectorXd rigidity(4);
  rigidity << 0.0, 0.2, 1.0, 0.9;
  const std::vector<Rgb> colors = VertexColors(labels, rigidity);
  ASSERT_EQ(colors.size(), 4u);
  EXPECT_EQ(colors[0], kFixedColor);
  EXPECT_EQ(colors[1], RigidityColor(0.2));
  EXPECT_EQ(colors[2], kHandleColor);
  EXPECT_EQ(colors[3], RigidityColor(0.9));
  // Without e', every vertex by its label.
  const std::vector<Rgb> plain = VertexColors(labels, Eigen::VectorXd());
  EXPECT_EQ(plain[0], kFixedColor);
  EXPECT_EQ(plain[1], kFreeColor);
  EXPECT_EQ(plain[2], kHandleColor);
  EXPECT_EQ(plain[3], kFreeColor);
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
