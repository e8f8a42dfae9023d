#version 450 core
// `pom`: GLSL twin of plugins/pom.cpp. Parallax occlusion mapping, a linear search then the
// interpolation of the last two samples (Tatarchuk, "Dynamic Parallax Occlusion Mapping with
// Approximate Soft Shadows", I3D 2006), in the relief shell.

// Parameters, schema order.
const int kSteps = 0;
const int kMinSteps = 1;
const int kDepthScale = 2;
const int kShadowStepsParam = 3;
#define RELIEF_LOD_PARAM 4  // `lod` (plugins/relief_shell.h SearchLod)
#define RELIEF_MAX_MIP_SLOT 3  // kReliefMaxMipSlot

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
  return pom_search(depth, in_.uv, ds, n);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01, o);
}
