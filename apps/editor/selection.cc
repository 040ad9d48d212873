#include "apps/editor/selection.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace msdeform {
namespace editor {

const char* VertexLabelName(VertexLabel label) {
  switch (label) {
    case VertexLabel::kFixed:
      return "fixed";
    case VertexLabel::kFree:
      return "free";
    case VertexLabel::kHandle:
      return "handle";
  }
  return IsHandle(label) ? "handle" : "free";
}

bool ParseVertexLabel(const std::string& name, VertexLabel* label) {
  for (VertexLabel candidate : {VertexLabel::kFixed, VertexLabel::kFree, VertexLabel::kHandle}) {
    if (name == VertexLabelName(candidate)) {
      *label = candidate;
      return true;
    }
  }
  return false;
}

ScreenVertices ProjectVertices(const Eigen::Matrix3Xd& vertices, const OrbitCamera& camera,
                               const Viewport& viewport, const DepthMap& depth,
                               const VisibilityOptions& options) {
  const int n = static_cast<int>(vertices.cols());
  ScreenVertices screen;
  screen.pixels.setZero(2, n);
  screen.in_view.assign(n, 0);
  screen.visible.assign(n, 0);
  const Eigen::Matrix4d clip_from_world = camera.Projection(viewport) * camera.View();
  const bool use_depth =
      !depth.empty() && depth.width == viewport.width && depth.height == viewport.height;
  const double tolerance = options.tolerance_rel * camera.scene_radius();
  for (int v = 0; v < n; ++v) {
    const Eigen::Vector4d clip = clip_from_world * vertices.col(v).homogeneous();
    if (!(clip.w() > 0.0)) continue;  // behind the eye
    const Eigen::Vector3d ndc = clip.head<3>() / clip.w();
    const double x = 0.5 * (ndc.x() + 1.0) * viewport.width;
    const double y = 0.5 * (1.0 - ndc.y()) * viewport.height;
    screen.pixels.col(v) << x, y;
    if (x < 0.0 || y < 0.0 || x >= viewport.width || y >= viewport.height) continue;
    if (ndc.z() < -1.0 || ndc.z() > 1.0) continue;  // outside the near/far planes
    screen.in_view[v] = 1;
    if (use_depth) {
      const int px = static_cast<int>(x), py = static_cast<int>(y);
      float farthest = 0.0f;
      for (int dy = -options.window; dy <= options.window; ++dy) {
        for (int dx = -options.window; dx <= options.window; ++dx) {
          const int sx = std::clamp(px + dx, 0, depth.width - 1);
          const int sy = std::clamp(py + dy, 0, depth.height - 1);
          farthest = std::max(farthest, depth.at(sx, sy));
        }
      }
      const double vertex_depth = camera.EyeDepth(0.5 * (ndc.z() + 1.0));
      if (vertex_depth > camera.EyeDepth(farthest) + tolerance) continue;
    }
    screen.visible[v] = 1;
  }
  return screen;
}

namespace {

bool OnScreen(const ScreenVertices& screen, int v, bool through) {
  return through ? screen.in_view[v] : screen.visible[v];
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_squared = ab.squaredNorm();
  const double t =
      length_squared > 0.0 ? std::clamp((p - a).dot(ab) / length_squared, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

std::vector<int> VerticesInBrush(const ScreenVertices& screen, const Eigen::Vector2d& center,
                                 double radius, bool through) {
  return VerticesAlongStroke(screen, center, center, radius, through);
}

std::vector<int> VerticesAlongStroke(const ScreenVertices& screen, const Eigen::Vector2d& a,
                                     const Eigen::Vector2d& b, double radius, bool through) {
  std::vector<int> ids;
  for (int v = 0; v < static_cast<int>(screen.visible.size()); ++v) {
    if (!OnScreen(screen, v, through)) continue;
    if (SegmentDistance(screen.pixels.col(v), a, b) <= radius) ids.push_back(v);
  }
  return ids;
}

bool PointInPolygon(const Eigen::Vector2d& point, const std::vector<Eigen::Vector2d>& polygon) {
  bool inside = false;
  const size_t n = polygon.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > point.y()) != (b.y() > point.y()) &&
        point.x() < (b.x() - a.x()) * (point.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

std::vector<int> VerticesInLasso(const ScreenVertices& screen,
                                 const std::vector<Eigen::Vector2d>& polygon, bool through) {
  std::vector<int> ids;
  if (polygon.size() < 3) return ids;
  Eigen::AlignedBox2d box;
  for (const Eigen::Vector2d& p : polygon) box.extend(p);
  for (int v = 0; v < static_cast<int>(screen.visible.size()); ++v) {
    if (!OnScreen(screen, v, through)) continue;
    const Eigen::Vector2d p = screen.pixels.col(v);
    if (box.contains(p) && PointInPolygon(p, polygon)) ids.push_back(v);
  }
  return ids;
}

HandleLayout LayoutFromLabels(const std::vector<VertexLabel>& labels) {
  HandleLayout layout;
  std::vector<int> label_group;  // per moveable vertex
  std::vector<int> number(256, -1);  // layout group of each label group
  for (int v = 0; v < static_cast<int>(labels.size()); ++v) {
    if (labels[v] == VertexLabel::kFixed) layout.fixed.push_back(v);
    if (IsHandle(labels[v])) {
      layout.moveable.push_back(v);
      label_group.push_back(HandleGroupOf(labels[v]));
      number[label_group.back()] = 0;
    }
  }
  int groups = 0;
  for (int& n : number) {
    if (n == 0) n = groups++;
  }
  if (groups > 1) {
    for (int g : label_group) layout.group.push_back(number[g]);
  }
  return layout;
}

std::vector<VertexLabel> LabelsFromLayout(const HandleLayout& layout, int num_vertices) {
  std::vector<VertexLabel> labels(num_vertices, VertexLabel::kFree);
  for (int v : layout.fixed) labels[v] = VertexLabel::kFixed;
  for (int i = 0; i < static_cast<int>(layout.moveable.size()); ++i) {
    labels[layout.moveable[i]] = HandleLabel(layout.group_of(i));
  }
  return labels;
}

}  // namespace editor
}  // namespace msdeform
