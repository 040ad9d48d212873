// GLSL 3.30 core sources of the editor's three programs. Lighting is a
// headlight (the light sits at the eye), two-sided, so every visible face is
// lit and the colours the tests look for stay recognisable:
//   colour = albedo * (0.35 + 0.65 |n . v|) + 0.08 |n . v|^24.

#ifndef MSDEFORM_APPS_EDITOR_SHADERS_H_
#define MSDEFORM_APPS_EDITOR_SHADERS_H_

namespace msdeform {
namespace editor {
namespace shaders {

// The mesh: per-vertex position, normal and colour; flat shading takes the
// triangle's normal from screen-space derivatives of the eye position.
inline constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 color;
uniform mat4 view;
uniform mat4 projection;
out vec3 eye_position;
out vec3 eye_normal;
out vec3 albedo;
void main() {
  vec4 eye = view * vec4(position, 1.0);
  eye_position = eye.xyz;
  eye_normal = mat3(view) * normal;
  albedo = color;
  gl_Position = projection * eye;
}
)";

inline constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 eye_position;
in vec3 eye_normal;
in vec3 albedo;
uniform int flat_shading;
uniform int line_pass;
uniform vec3 line_color;
out vec4 fragment;
void main() {
  if (line_pass == 1) {
    fragment = vec4(line_color, 1.0);
    return;
  }
  vec3 n = flat_shading == 1 ? cross(dFdx(eye_position), dFdy(eye_position)) : eye_normal;
  float length_n = length(n);
  n = length_n > 0.0 ? n / length_n : vec3(0.0, 0.0, 1.0);
  float facing = abs(dot(n, normalize(-eye_position)));
  vec3 shaded = albedo * (0.35 + 0.65 * facing) + vec3(0.08 * pow(facing, 24.0));
  fragment = vec4(min(shaded, vec3(1.0)), 1.0);
}
)";

// Node spheres: a unit sphere instanced at each node with its colour.
inline constexpr const char* kSphereVertex = R"(#version 330 core
layout(location = 0) in vec3 unit;
layout(location = 1) in vec3 center;
layout(location = 2) in vec3 color;
uniform mat4 view;
uniform mat4 projection;
uniform float radius;
out vec3 eye_position;
out vec3 eye_normal;
out vec3 albedo;
void main() {
  vec4 eye = view * vec4(center + radius * unit, 1.0);
  eye_position = eye.xyz;
  eye_normal = mat3(view) * unit;
  albedo = color;
  gl_Position = projection * eye;
}
)";

// Graph edges: one colour, blended so the surface they pass under shows.
inline constexpr const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view;
uniform mat4 projection;
void main() {
  gl_Position = projection * view * vec4(position, 1.0);
}
)";

inline constexpr const char* kLineFragment = R"(#version 330 core
uniform vec4 color;
out vec4 fragment;
void main() {
  fragment = color;
}
)";

}  // namespace shaders
}  // namespace editor
}  // namespace msdeform

#endif  // MSDEFORM_APPS_EDITOR_SHADERS_H_
