// The editor's OpenGL 3.3 core renderer: the mesh (flat or smooth shading
// with a headlight, per-vertex colours, an optional wireframe), the nodes of
// the selected scale as instanced spheres and its edges as lines.
//
// The scene is drawn into an offscreen framebuffer of the viewport's size
// (colour and depth), then copied to the window (Present). Reading it back
// (depth for picking, colour for screenshots) therefore works for a hidden
// window too, and the UI can be drawn into it or not.

#ifndef MSDEFORM_APPS_EDITOR_RENDERER_H_
#define MSDEFORM_APPS_EDITOR_RENDERER_H_

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "apps/editor/camera.h"
#include "apps/editor/gl.h"
#include "apps/editor/overlays.h"
#include "apps/editor/selection.h"

namespace msdeform {
namespace editor {

struct RenderSettings {
  bool flat_shading = false;  // one normal per triangle (else the vertex normals)
  bool wireframe = false;     // triangle edges over the surface
  bool nodes = false;         // node spheres (SetGraph)
  bool edges = false;         // graph edges (SetGraph), seen through the surface
  double node_radius = 0.01;  // world units
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();
};

class Renderer {
 public:
  Renderer() = default;
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Compiles the shaders and makes the buffers; needs a current 3.3 core
  // context. False with the compiler's or linker's log.
  bool Init(std::string* error);

  // The mesh: triangles once per mesh, positions and normals (3 by #V) per
  // pose, colours per label or overlay change.
  void SetTopology(const Eigen::Matrix3Xi& faces, int num_vertices);
  void SetGeometry(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals);
  void SetColors(const std::vector<Rgb>& colors);
  // The graph overlay: node centres (3 by #nodes), one colour per node, and
  // edges as node pairs.
  void SetGraph(const Eigen::Matrix3Xd& nodes, const std::vector<Rgb>& colors,
                const std::vector<std::pair<int, int>>& edges);

  // Draws the scene into the offscreen framebuffer, resized to `viewport`,
  // and leaves it bound (the UI may be drawn over it next).
  void DrawScene(const Viewport& viewport, const RenderSettings& settings);
  // Copies the offscreen framebuffer to the window's (framebuffer pixels).
  void Present(const Viewport& window);

  // The offscreen framebuffer's depth (window depths, row 0 at the top) and
  // colour (RGB bytes, row 0 at the top, width * height * 3).
  DepthMap ReadDepth() const;
  std::vector<std::uint8_t> ReadColor() const;
  const Viewport& viewport() const { return viewport_; }

 private:
  void ResizeOffscreen(const Viewport& viewport);

  GLuint mesh_program_ = 0, sphere_program_ = 0, line_program_ = 0;
  GLuint mesh_vao_ = 0, position_vbo_ = 0, normal_vbo_ = 0, color_vbo_ = 0, index_ebo_ = 0;
  GLsizei num_indices_ = 0;
  GLuint sphere_vao_ = 0, sphere_vbo_ = 0, sphere_ebo_ = 0, instance_vbo_ = 0;
  GLsizei sphere_indices_ = 0, num_nodes_ = 0;
  GLuint line_vao_ = 0, line_vbo_ = 0, line_ebo_ = 0;
  GLsizei line_indices_ = 0;
  GLuint fbo_ = 0, color_rbo_ = 0, depth_rbo_ = 0;
  Viewport viewport_{0, 0};
};

}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_RENDERER_H_
