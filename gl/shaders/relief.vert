#version 450 core
// The shared vertex stage of every GLSL twin. The CPU's prepare stage (render/render.h) made the
// standard varyings (plugins/plugin.h, namespace varying) in world space: attributes 1..6 hold
// them as six vec4 (the 16 standard ones, then COLOR_0 and TEXCOORD_1, padded: gl_backend.cpp
// kGlVaryings; kCountGl of the generated prelude). Attribute 0 is the position, in one of the two
// modes of BackendConfig::gl_interpolation:
//  - GPU interpolation: the world position, kept on the GPU across frames; clip_from_input is the
//    pass's view-projection and GL interpolates the varyings.
//  - The CPU's planes: the CPU's clip position (clip_from_input is the identity), snapped as the
//    CPU rasterizer snaps a vertex, so that GL covers the pixels whose planes the fragment stage
//    evaluates (common.glsl interpolate_like_cpu).
#include "prelude.glsl"

layout(location = 0) in vec4 a_position;
layout(location = 1) in vec4 a_varyings[kCountGl / 4];

uniform vec2 viewport_size;
uniform mat4 clip_from_input;
uniform bool snap_like_cpu;

out vec4 vary[kCountGl / 4];

void main() {
  vec4 c = snap_like_cpu ? a_position : clip_from_input * a_position;
  if (snap_like_cpu && c.w > 0.0 && c.z <= c.w && c.z >= 0.0 && viewport_size.x > 0.0) {
    dvec2 iw = dvec2(1.0LF / double(c.w));
    dvec2 s = (dvec2(c.x, -c.y) * iw * 0.5LF + 0.5LF) * dvec2(viewport_size);
    s = sign(s) * floor(abs(s) * 256.0LF + 0.5LF) / 256.0LF;  // std::lround: half away from 0
    dvec2 ndc = s / dvec2(viewport_size) * 2.0LF - 1.0LF;
    c.xy = vec2(ndc.x * double(c.w), -ndc.y * double(c.w));
  }
  gl_Position = c;
  for (int i = 0; i < kCountGl / 4; ++i) vary[i] = a_varyings[i];
}
