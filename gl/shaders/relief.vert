#version 450 core
// The shared pass-through vertex stage of every GLSL twin. The CPU's prepare_draws
// (render/render.h) already computed clip positions and the standard varyings
// (plugins/plugin.h, namespace varying), so both backends interpolate the same numbers:
// attribute 0 is the clip position, attributes 1..6 the varyings as six vec4 (the 16 standard
// ones, then COLOR_0 and TEXCOORD_1, padded: gl_backend.cpp kGlVaryings; kCountGl of the
// generated prelude).
#include "prelude.glsl"

layout(location = 0) in vec4 a_clip;
layout(location = 1) in vec4 a_varyings[kCountGl / 4];

uniform vec2 viewport_size;

out vec4 vary[kCountGl / 4];

void main() {
  vec4 c = a_clip;
  if (c.w > 0.0 && c.z <= c.w && c.z >= 0.0 && viewport_size.x > 0.0) {
    dvec2 iw = dvec2(1.0LF / double(c.w));
    dvec2 s = (dvec2(c.x, -c.y) * iw * 0.5LF + 0.5LF) * dvec2(viewport_size);
    s = sign(s) * floor(abs(s) * 256.0LF + 0.5LF) / 256.0LF;  // std::lround: half away from 0
    dvec2 ndc = s / dvec2(viewport_size) * 2.0LF - 1.0LF;
    c.xy = vec2(ndc.x * double(c.w), -ndc.y * double(c.w));
  }
  gl_Position = c;
  for (int i = 0; i < kCountGl / 4; ++i) vary[i] = a_varyings[i];
}
