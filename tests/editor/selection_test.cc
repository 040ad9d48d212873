#include "apps/editor/selection.h"

#include <gtest/gtest.h>

namespace msdeform {
namespace editor {
namespace {

// A camera looking down -z at the origin from distance 10.
OrbitCamera FrontCamera() {
  OrbitCamera camera;
  camera.Fit(Eigen::AlignedBox3d(Eigen::Vector3d(-2, -2, -2), Eigen::Vector3d(2, 2, 2)),
             Viewport{200, 100});
  camera.set_distance(10.0);
  return camera;
}

// The depth buffer of a wall at z = wall_z filling the view.
DepthMap Wall(const OrbitCamera& camera, const Viewport& viewport, double wall_z) {
  DepthMap map;
  map.width = viewport.width;
  map.height = viewport.height;
  const float depth =
      static_cast<float>(camera.Project(Eigen::Vector3d(0, 0, wall_z), viewport).z());
  map.depth.assign(static_cast<size_t>(map.width) * map.height, depth);
  return map;
}

TEST(SelectionTest, PointInPolygonEvenOdd) {
  const std::vector<Eigen::Vector2d> square = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  EXPECT_TRUE(PointInPolygon({5, 5}, square));
  EXPECT_FALSE(PointInPolygon({15, 5}, square));
  // A concave "C": the notch is outside.
  const std::vector<Eigen::Vector2d> c = {{0, 0}, {10, 0}, {10, 3},  {3, 3},
                                          {3, 7}, {10, 7}, {10, 10}, {0, 10}};
  EXPECT_TRUE(PointInPolygon({1, 5}, c));
  EXPECT_FALSE(PointInPolygon({6, 5}, c));
}

TEST(SelectionTest, HiddenVerticesAreLeftUnlessThrough) {
  const Viewport viewport{200, 100};
  const OrbitCamera camera = FrontCamera();
  // Vertex 0 on the wall z = 0.5, vertex 1 behind it, vertex 2 outside the view.
  Eigen::Matrix3Xd vertices(3, 3);
  vertices << 0.0, 0.1, 50.0,  //
      0.0, 0.0, 0.0,           //
      0.5, -1.5, 0.5;
  const ScreenVertices screen =
      ProjectVertices(vertices, camera, viewport, Wall(camera, viewport, 0.5));
  EXPECT_TRUE(screen.visible[0]);
  EXPECT_FALSE(screen.visible[1]);
  EXPECT_TRUE(screen.in_view[1]);
  EXPECT_FALSE(screen.in_view[2]);
  const Eigen::Vector2d centre(100, 50);
  EXPECT_EQ(VerticesInBrush(screen, centre, 10.0, false), std::vector<int>({0}));
  EXPECT_EQ(VerticesInBrush(screen, centre, 10.0, true), std::vector<int>({0, 1}));
  // Without a depth buffer, everything in view is visible.
  const ScreenVertices no_depth = ProjectVertices(vertices, camera, viewport, DepthMap());
  EXPECT_EQ(VerticesInBrush(no_depth, centre, 10.0, false), std::vector<int>({0, 1}));
}

TEST(SelectionTest, BrushStrokeAndLassoSelectWhatTheyCover) {
  const Viewport viewport{200, 100};
  const OrbitCamera camera = FrontCamera();
  // A row of vertices on the plane z = 0, 0.2 apart along x.
  Eigen::Matrix3Xd vertices = Eigen::Matrix3Xd::Zero(3, 11);
  for (int i = 0; i < 11; ++i) vertices(0, i) = -1.0 + 0.2 * i;
  const ScreenVertices screen = ProjectVertices(vertices, camera, viewport, DepthMap());
  // A stroke from vertex 2 to vertex 5 with a radius under the spacing.
  const std::vector<int> stroke =
      VerticesAlongStroke(screen, screen.pixels.col(2), screen.pixels.col(5),
                          0.25 * (screen.pixels(0, 1) - screen.pixels(0, 0)), false);
  EXPECT_EQ(stroke, std::vector<int>({2, 3, 4, 5}));
  // A lasso around vertices 7..9.
  const double x0 = 0.5 * (screen.pixels(0, 6) + screen.pixels(0, 7));
  const double x1 = 0.5 * (screen.pixels(0, 9) + screen.pixels(0, 10));
  const std::vector<Eigen::Vector2d> lasso = {{x0, 40}, {x1, 40}, {x1, 60}, {x0, 60}};
  EXPECT_EQ(VerticesInLasso(screen, lasso, false), std::vector<int>({7, 8, 9}));
  EXPECT_TRUE(VerticesInLasso(screen, {{0, 0}, {1, 1}}, false).empty());
}

TEST(SelectionTest, LabelsAndLayoutsRoundTrip) {
  const std::vector<VertexLabel> labels = {VertexLabel::kFree, VertexLabel::kHandle,
                                           VertexLabel::kFixed, VertexLabel::kHandle,
                                           VertexLabel::kFixed};
  const HandleLayout layout = LayoutFromLabels(labels);
  EXPECT_EQ(layout.fixed, std::vector<int>({2, 4}));
  EXPECT_EQ(layout.moveable, std::vector<int>({1, 3}));
  EXPECT_EQ(LabelsFromLayout(layout, 5), labels);
  VertexLabel label;
  EXPECT_TRUE(ParseVertexLabel("handle", &label));
  EXPECT_EQ(label, VertexLabel::kHandle);
  EXPECT_FALSE(ParseVertexLabel("moveable", &label));
  // The .sel status values.
  EXPECT_EQ(static_cast<int>(VertexLabel::kFixed), 0);
  EXPECT_EQ(static_cast<int>(VertexLabel::kFree), 1);
  EXPECT_EQ(static_cast<int>(VertexLabel::kHandle), 2);
}

}  // namespace
}  // namespace editor
}  // namespace msdeform
