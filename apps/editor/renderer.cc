#include "apps/editor/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "apps/editor/shaders.h"

namespace msdeform {
namespace editor {
namespace {

bool Compile(GLenum stage, const char* source, GLuint* shader, std::string* error) {
  *shader = glCreateShader(stage);
  glShaderSource(*shader, 1, &source, nullptr);
  glCompileShader(*shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(*shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return true;
  char log[2048] = {0};
  glGetShaderInfoLog(*shader, sizeof(log), nullptr, log);
  *error = std::string("OpenGL: a shader did not compile: ") + log;
  glDeleteShader(*shader);
  return false;
}

bool Link(const char* vertex, const char* fragment, GLuint* program, std::string* error) {
  GLuint vs = 0, fs = 0;
  if (!Compile(GL_VERTEX_SHADER, vertex, &vs, error)) return false;
  if (!Compile(GL_FRAGMENT_SHADER, fragment, &fs, error)) {
    glDeleteShader(vs);
    return false;
  }
  *program = glCreateProgram();
  glAttachShader(*program, vs);
  glAttachShader(*program, fs);
  glLinkProgram(*program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(*program, GL_LINK_STATUS, &ok);
  if (ok == GL_TRUE) return true;
  char log[2048] = {0};
  glGetProgramInfoLog(*program, sizeof(log), nullptr, log);
  *error = std::string("OpenGL: a program did not link: ") + log;
  return false;
}

void SetMatrices(GLuint program, const RenderSettings& settings) {
  const Eigen::Matrix4f view = settings.view.cast<float>();
  const Eigen::Matrix4f projection = settings.projection.cast<float>();
  // Eigen is column-major, as GLSL expects.
  glUniformMatrix4fv(glGetUniformLocation(program, "view"), 1, GL_FALSE, view.data());
  glUniformMatrix4fv(glGetUniformLocation(program, "projection"), 1, GL_FALSE, projection.data());
}

// An icosphere: the icosahedron subdivided `levels` times, vertices on the
// unit sphere.
void Icosphere(int levels, std::vector<Eigen::Vector3f>* vertices,
               std::vector<std::array<unsigned, 3>>* triangles) {
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  *vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Eigen::Vector3f& v : *vertices) v.normalize();
  *triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<unsigned, unsigned>, unsigned> midpoints;
    auto midpoint = [&](unsigned a, unsigned b) {
      const auto key = std::minmax(a, b);
      auto it = midpoints.find(key);
      if (it != midpoints.end()) return it->second;
      vertices->push_back(((*vertices)[a] + (*vertices)[b]).normalized());
      const unsigned id = static_cast<unsigned>(vertices->size() - 1);
      midpoints.emplace(key, id);
      return id;
    };
    std::vector<std::array<unsigned, 3>> finer;
    for (const auto& tri : *triangles) {
      const unsigned ab = midpoint(tri[0], tri[1]), bc = midpoint(tri[1], tri[2]),
                     ca = midpoint(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    triangles->swap(finer);
  }
}

}  // namespace

Renderer::~Renderer() {
  if (mesh_program_ == 0) return;  // never initialised (no context)
  glDeleteProgram(mesh_program_);
  glDeleteProgram(sphere_program_);
  glDeleteProgram(line_program_);
  const GLuint buffers[] = {position_vbo_, normal_vbo_,   color_vbo_, index_ebo_, sphere_vbo_,
                            sphere_ebo_,   instance_vbo_, line_vbo_,  line_ebo_};
  glDeleteBuffers(sizeof(buffers) / sizeof(buffers[0]), buffers);
  const GLuint arrays[] = {mesh_vao_, sphere_vao_, line_vao_};
  glDeleteVertexArrays(3, arrays);
  glDeleteFramebuffers(1, &fbo_);
  const GLuint renderbuffers[] = {color_rbo_, depth_rbo_};
  glDeleteRenderbuffers(2, renderbuffers);
}

bool Renderer::Init(std::string* error) {
  if (!Link(shaders::kMeshVertex, shaders::kMeshFragment, &mesh_program_, error) ||
      !Link(shaders::kSphereVertex, shaders::kMeshFragment, &sphere_program_, error) ||
      !Link(shaders::kLineVertex, shaders::kLineFragment, &line_program_, error)) {
    return false;
  }
  // The mesh: three attribute buffers and the triangles.
  glGenVertexArrays(1, &mesh_vao_);
  glBindVertexArray(mesh_vao_);
  glGenBuffers(1, &position_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &normal_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, normal_vbo_);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glGenBuffers(1, &color_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo_);
  glVertexAttribPointer(2, 3, GL_UNSIGNED_BYTE, GL_TRUE, 4, nullptr);
  glEnableVertexAttribArray(2);
  glGenBuffers(1, &index_ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_ebo_);

  // The node spheres: a shared icosphere, instanced.
  std::vector<Eigen::Vector3f> unit;
  std::vector<std::array<unsigned, 3>> triangles;
  Icosphere(2, &unit, &triangles);
  glGenVertexArrays(1, &sphere_vao_);
  glBindVertexArray(sphere_vao_);
  glGenBuffers(1, &sphere_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, sphere_vbo_);
  glBufferData(GL_ARRAY_BUFFER, unit.size() * sizeof(Eigen::Vector3f), unit.data(), GL_STATIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &sphere_ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, sphere_ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, triangles.size() * sizeof(triangles[0]), triangles.data(),
               GL_STATIC_DRAW);
  sphere_indices_ = static_cast<GLsizei>(triangles.size() * 3);
  // Per instance: centre (3 floats) and colour (4 bytes) in 16 bytes.
  glGenBuffers(1, &instance_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 16, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribDivisor(1, 1);
  glVertexAttribPointer(2, 3, GL_UNSIGNED_BYTE, GL_TRUE, 16, reinterpret_cast<void*>(12));
  glEnableVertexAttribArray(2);
  glVertexAttribDivisor(2, 1);

  // The graph edges.
  glGenVertexArrays(1, &line_vao_);
  glBindVertexArray(line_vao_);
  glGenBuffers(1, &line_vbo_);
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glGenBuffers(1, &line_ebo_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, line_ebo_);
  glBindVertexArray(0);

  glGenFramebuffers(1, &fbo_);
  glGenRenderbuffers(1, &color_rbo_);
  glGenRenderbuffers(1, &depth_rbo_);
  const GLenum problem = glGetError();
  if (problem != GL_NO_ERROR) {
    *error = "OpenGL: error " + std::to_string(problem) + " while creating the renderer's objects";
    return false;
  }
  return true;
}

void Renderer::SetTopology(const Eigen::Matrix3Xi& faces, int num_vertices) {
  glBindVertexArray(mesh_vao_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_ebo_);
  const Eigen::Matrix<unsigned, 3, Eigen::Dynamic> indices = faces.cast<unsigned>();
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(unsigned), indices.data(),
               GL_STATIC_DRAW);
  num_indices_ = static_cast<GLsizei>(indices.size());
  glBindVertexArray(0);
  (void)num_vertices;
}

void Renderer::SetGeometry(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals) {
  const Eigen::Matrix3Xf p = positions.cast<float>();
  const Eigen::Matrix3Xf n = normals.cast<float>();
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo_);
  glBufferData(GL_ARRAY_BUFFER, p.size() * sizeof(float), p.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, normal_vbo_);
  glBufferData(GL_ARRAY_BUFFER, n.size() * sizeof(float), n.data(), GL_STREAM_DRAW);
}

void Renderer::SetColors(const std::vector<Rgb>& colors) {
  std::vector<std::uint8_t> padded(colors.size() * 4, 255);
  for (size_t v = 0; v < colors.size(); ++v) {
    std::copy(colors[v].begin(), colors[v].end(), padded.begin() + 4 * v);
  }
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo_);
  glBufferData(GL_ARRAY_BUFFER, padded.size(), padded.data(), GL_DYNAMIC_DRAW);
}

void Renderer::SetGraph(const Eigen::Matrix3Xd& nodes, const std::vector<Rgb>& colors,
                        const std::vector<std::pair<int, int>>& edges) {
  struct Instance {
    float center[3];
    std::uint8_t color[4];
  };
  std::vector<Instance> instances(nodes.cols());
  for (Eigen::Index j = 0; j < nodes.cols(); ++j) {
    for (int c = 0; c < 3; ++c) {
      instances[j].center[c] = static_cast<float>(nodes(c, j));
      instances[j].color[c] = j < static_cast<Eigen::Index>(colors.size()) ? colors[j][c] : 128;
    }
    instances[j].color[3] = 255;
  }
  glBindBuffer(GL_ARRAY_BUFFER, instance_vbo_);
  glBufferData(GL_ARRAY_BUFFER, instances.size() * sizeof(Instance), instances.data(),
               GL_DYNAMIC_DRAW);
  num_nodes_ = static_cast<GLsizei>(instances.size());

  const Eigen::Matrix3Xf points = nodes.cast<float>();
  glBindBuffer(GL_ARRAY_BUFFER, line_vbo_);
  glBufferData(GL_ARRAY_BUFFER, points.size() * sizeof(float), points.data(), GL_DYNAMIC_DRAW);
  std::vector<unsigned> indices;
  indices.reserve(edges.size() * 2);
  for (const auto& [a, b] : edges) {
    indices.push_back(static_cast<unsigned>(a));
    indices.push_back(static_cast<unsigned>(b));
  }
  glBindVertexArray(line_vao_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, line_ebo_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(unsigned), indices.data(),
               GL_DYNAMIC_DRAW);
  line_indices_ = static_cast<GLsizei>(indices.size());
  glBindVertexArray(0);
}

void Renderer::ResizeOffscreen(const Viewport& viewport) {
  if (viewport.width == viewport_.width && viewport.height == viewport_.height) return;
  viewport_ = viewport;
  glBindRenderbuffer(GL_RENDERBUFFER, color_rbo_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, viewport.width, viewport.height);
  glBindRenderbuffer(GL_RENDERBUFFER, depth_rbo_);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, viewport.width, viewport.height);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rbo_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rbo_);
}

void Renderer::DrawScene(const Viewport& viewport, const RenderSettings& settings) {
  ResizeOffscreen(viewport);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, viewport.width, viewport.height);
  glClearColor(kBackgroundColor[0] / 255.0f, kBackgroundColor[1] / 255.0f,
               kBackgroundColor[2] / 255.0f, 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);

  // The surface; pushed back a little when the wireframe goes over it.
  glUseProgram(mesh_program_);
  SetMatrices(mesh_program_, settings);
  glUniform1i(glGetUniformLocation(mesh_program_, "flat_shading"), settings.flat_shading ? 1 : 0);
  glUniform1i(glGetUniformLocation(mesh_program_, "line_pass"), 0);
  glBindVertexArray(mesh_vao_);
  if (settings.wireframe) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
  }
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDrawElements(GL_TRIANGLES, num_indices_, GL_UNSIGNED_INT, nullptr);
  glDisable(GL_POLYGON_OFFSET_FILL);
  if (settings.wireframe) {
    glUniform1i(glGetUniformLocation(mesh_program_, "line_pass"), 1);
    glUniform3f(glGetUniformLocation(mesh_program_, "line_color"), 0.22f, 0.22f, 0.25f);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glDrawElements(GL_TRIANGLES, num_indices_, GL_UNSIGNED_INT, nullptr);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }

  if (settings.nodes && num_nodes_ > 0) {
    glUseProgram(sphere_program_);
    SetMatrices(sphere_program_, settings);
    glUniform1f(glGetUniformLocation(sphere_program_, "radius"),
                static_cast<float>(settings.node_radius));
    glUniform1i(glGetUniformLocation(sphere_program_, "flat_shading"), 0);
    glUniform1i(glGetUniformLocation(sphere_program_, "line_pass"), 0);
    glBindVertexArray(sphere_vao_);
    glDrawElementsInstanced(GL_TRIANGLES, sphere_indices_, GL_UNSIGNED_INT, nullptr, num_nodes_);
  }
  if (settings.edges && line_indices_ > 0) {
    // Seen through the surface: no depth test, half transparent.
    glUseProgram(line_program_);
    SetMatrices(line_program_, settings);
    glUniform4f(glGetUniformLocation(line_program_, "color"), kEdgeColor[0] / 255.0f,
                kEdgeColor[1] / 255.0f, kEdgeColor[2] / 255.0f, 0.55f);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(line_vao_);
    glDrawElements(GL_LINES, line_indices_, GL_UNSIGNED_INT, nullptr);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  glUseProgram(0);
}

void Renderer::Present(const Viewport& window) {
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  glBlitFramebuffer(0, 0, viewport_.width, viewport_.height, 0, 0, window.width, window.height,
                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

DepthMap Renderer::ReadDepth() const {
  DepthMap map;
  map.width = viewport_.width;
  map.height = viewport_.height;
  std::vector<float> bottom_up(static_cast<size_t>(map.width) * map.height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, map.width, map.height, GL_DEPTH_COMPONENT, GL_FLOAT, bottom_up.data());
  map.depth.resize(bottom_up.size());
  for (int y = 0; y < map.height; ++y) {
    std::copy_n(bottom_up.begin() + static_cast<size_t>(map.height - 1 - y) * map.width, map.width,
                map.depth.begin() + static_cast<size_t>(y) * map.width);
  }
  return map;
}

std::vector<std::uint8_t> Renderer::ReadColor() const {
  const size_t row = static_cast<size_t>(viewport_.width) * 3;
  std::vector<std::uint8_t> bottom_up(row * viewport_.height), top_down(row * viewport_.height);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, viewport_.width, viewport_.height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  for (int y = 0; y < viewport_.height; ++y) {
    std::copy_n(bottom_up.begin() + (viewport_.height - 1 - y) * row, row,
                top_down.begin() + y * row);
  }
  return top_down;
}

}  // namespace editor
}  // namespace msdeform
