#version 450 core
// `relief`: GLSL twin of plugins/relief.cpp. Relief mapping, a linear then a binary search with
// the step count by view angle (Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on
// Arbitrary Polygonal Surfaces", I3D 2005), in the relief shell.

// Parameters, schema order.
const int kSteps = 0;
const int kBinarySteps = 1;
const int kMinSteps = 2;
const int kDepthScale = 3;
const int kShadowStepsParam = 4;
#define RELIEF_LOD_PARAM 5  // `lod` (plugins/relief_shell.h SearchLod)
#define RELIEF_MAX_MIP_SLOT 3  // kReliefMaxMipSlot

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
  return relief_search(depth, in_.uv, ds, n, int(material.params[kBinarySteps]));
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01, o);
}
