// Handle selection on the screen: every vertex gets a label (held fixed,
// free to deform, or in the moveable handle), and the mouse tools label the
// vertices they cover. Vertices hidden behind the surface are left alone
// unless the tool selects through the mesh.
//
// Visibility comes from the renderer's depth buffer (DepthMap): a vertex is
// visible when it is no farther from the eye than the surface the buffer saw
// around its pixel, up to a tolerance.

#ifndef MSDEFORM_APPS_EDITOR_SELECTION_H_
#define MSDEFORM_APPS_EDITOR_SELECTION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "apps/editor/camera.h"
#include "msdeform/core/handles.h"

namespace msdeform {
namespace editor {

// The .sel status values (core/handles.h): 0 fixed, 1 free, 2 handle; and,
// as in Python's statuses, 2 + g for handle group g (kHandle is group 0).
enum class VertexLabel : std::uint8_t { kFixed = 0, kFree = 1, kHandle = 2 };

inline VertexLabel HandleLabel(int group) { return static_cast<VertexLabel>(2 + group); }
inline bool IsHandle(VertexLabel label) { return static_cast<int>(label) >= 2; }
// The handle group of a handle label (-1 for fixed or free).
inline int HandleGroupOf(VertexLabel label) {
  return IsHandle(label) ? static_cast<int>(label) - 2 : -1;
}

// "fixed", "free", "handle" (every handle group); Parse is false for another
// name and gives kHandle (group 0) for "handle".
const char* VertexLabelName(VertexLabel label);
bool ParseVertexLabel(const std::string& name, VertexLabel* label);

// A depth buffer read back from the renderer: window depths in [0, 1], row 0
// at the top. Empty (width 0) means "no depth": every vertex in the viewport
// counts as visible.
struct DepthMap {
  int width = 0;
  int height = 0;
  std::vector<float> depth;  // width * height, row-major from the top row

  bool empty() const { return width == 0; }
  float at(int x, int y) const { return depth[static_cast<size_t>(y) * width + x]; }
};

struct VisibilityOptions {
  // A vertex is visible when its eye depth exceeds the largest eye depth the
  // buffer holds within `window` pixels of it by at most this fraction of the
  // scene radius.
  double tolerance_rel = 0.01;
  int window = 1;  // 1: the 3 x 3 pixels around the vertex
};

// The vertices as the camera sees them.
struct ScreenVertices {
  Eigen::Matrix2Xd pixels;    // 2 by #V, pixel coordinates (camera.h)
  std::vector<char> in_view;  // #V; in the viewport and between the near and far planes
  std::vector<char> visible;  // #V; in view and not hidden by the surface
};

// Projects `vertices` (3 by #V) and tests each against `depth` (same size as
// the viewport, or empty).
ScreenVertices ProjectVertices(const Eigen::Matrix3Xd& vertices, const OrbitCamera& camera,
                               const Viewport& viewport, const DepthMap& depth,
                               const VisibilityOptions& options = VisibilityOptions());

// Visible vertices (or all in the viewport, with `through`) within `radius`
// pixels of `center`, ascending.
std::vector<int> VerticesInBrush(const ScreenVertices& screen, const Eigen::Vector2d& center,
                                 double radius, bool through);
// Every vertex within `radius` pixels of the segment from `a` to `b` (a brush
// swept along one mouse move), ascending.
std::vector<int> VerticesAlongStroke(const ScreenVertices& screen, const Eigen::Vector2d& a,
                                     const Eigen::Vector2d& b, double radius, bool through);
// Visible vertices (or all in the viewport) inside `polygon` (pixels, closed
// implicitly; even-odd rule), ascending. Fewer than 3 points select nothing.
std::vector<int> VerticesInLasso(const ScreenVertices& screen,
                                 const std::vector<Eigen::Vector2d>& polygon, bool through);
bool PointInPolygon(const Eigen::Vector2d& point, const std::vector<Eigen::Vector2d>& polygon);

// Labels <-> layouts. The layout's handle groups are the labels' groups in
// increasing order, numbered without gaps (labels of groups 0 and 3 give
// layout groups 0 and 1). LayoutFromLabels gives sorted lists (it may have no
// moveable vertex: check with ValidateHandles before using it).
HandleLayout LayoutFromLabels(const std::vector<VertexLabel>& labels);
std::vector<VertexLabel> LabelsFromLayout(const HandleLayout& layout, int num_vertices);

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SELECTION_H_
