#version 450 core
// `steep_parallax`: GLSL twin of plugins/steep_parallax.cpp. Steep parallax mapping, n depth
// planes at a constant LOD and a self-shadow loop (McGuire and McGuire, "Steep Parallax Mapping",
// I3D 2005 poster), in the relief shell.

// Parameters, schema order.
const int kSteps = 0;
const int kDepthScale = 1;
const int kShadowStepsParam = 2;
#define RELIEF_LOD_PARAM 3  // `lod` (plugins/relief_shell.h SearchLod)
#define RELIEF_MAX_MIP_SLOT 3  // kReliefMaxMipSlot

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  return steep_parallax_search(depth, in_.uv, ds, material.params[kSteps]);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01 + 1.0 / material.params[kSteps], o);
}
