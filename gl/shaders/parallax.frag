#version 450 core
// `parallax`: GLSL twin of plugins/parallax.cpp. Parallax mapping, one offset read at the fragment
// (Kaneko et al., "Detailed shape representation with parallax mapping", ICAT 2001), optional
// offset limiting (Welsh, "Parallax mapping with offset limiting", 2004), in the relief shell.

// Parameters, schema order.
const int kDepthScale = 0;
const int kOffsetLimiting = 1;
const int kShadowStepsParam = 2;

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  bool limit = material.params[kOffsetLimiting] != 0.0;
  return parallax_offset(depth, in_.uv, ds, V.z, limit);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.05, o);
}
