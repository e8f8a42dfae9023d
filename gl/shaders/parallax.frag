#version 450 core
// `parallax`: GLSL twin of plugins/parallax.cpp. Parallax mapping, one offset read at the fragment
// (Kaneko et al., "Detailed shape representation with parallax mapping", ICAT 2001), optional
// offset limiting (Welsh, "Parallax mapping with offset limiting", 2004), in the relief shell.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kDepthScale = kParam_parallax_depth_scale;
const int kOffsetLimiting = kParam_parallax_offset_limiting;
const int kShadowStepsParam = kParam_parallax_shadow_steps;
const int kBaseColorSlot = kSlot_parallax_base_color;
const int kNormalSlot = kSlot_parallax_normal;
const int kDepthSlot = kSlot_parallax_depth;

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  bool limit = material.params[kOffsetLimiting] != 0.0;
  return parallax_offset(depth, in_.uv, ds, V.z, limit);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.05, o);
}
