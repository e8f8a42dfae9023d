#version 450 core
// The vertex stage of the relief paper's appendix shader (gl/appendix_relief.h): world-space
// position, normal, tangent (w: the bitangent's sign) and uv. Not a twin: the yardstick draws its
// own mesh, with none of the CPU's attribute planes.

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv;

uniform mat4 view_proj;
uniform vec4 uv_transform;  // xy: scale (the paper's `tile`), zw: offset

out vec3 v_position;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;

void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_tangent = a_tangent;
  v_uv = a_uv * uv_transform.xy + uv_transform.zw;
  gl_Position = view_proj * vec4(a_position, 1.0);
}
