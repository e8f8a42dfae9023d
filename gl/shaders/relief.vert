#version 450 core
// The shared pass-through vertex stage of every GLSL twin. The CPU's prepare_draws
// (render/render.h) already computed clip positions and the standard varyings
// (plugins/plugin.h, namespace varying), so both backends interpolate the same numbers:
// attribute 0 is the clip position, attributes 1..4 the 16 varyings as four vec4.

layout(location = 0) in vec4 a_clip;
layout(location = 1) in vec4 a_varyings[4];

out vec4 vary[4];

void main() {
  gl_Position = a_clip;
  for (int i = 0; i < 4; ++i) vary[i] = a_varyings[i];
}
