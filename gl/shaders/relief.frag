#version 450 core
// `relief`: GLSL twin of plugins/relief.cpp. Relief mapping, a linear then a binary search with
// the step count by view angle (Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on
// Arbitrary Polygonal Surfaces", I3D 2005), in the relief shell.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_relief_steps;
const int kBinarySteps = kParam_relief_binary_steps;
const int kMinSteps = kParam_relief_min_steps;
const int kDepthScale = kParam_relief_depth_scale;
const int kShadowStepsParam = kParam_relief_shadow_steps;
#define RELIEF_LOD_PARAM kParam_relief_lod
#define RELIEF_MAX_MIP_SLOT kSlot_relief_depth_max_mip
const int kBaseColorSlot = kSlot_relief_base_color;
const int kNormalSlot = kSlot_relief_normal;
const int kDepthSlot = kSlot_relief_depth;

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
  return relief_search(depth, in_.uv, ds, n, int(material.params[kBinarySteps]));
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01, o);
}
