#version 450 core
// `pom`: GLSL twin of plugins/pom.cpp. Parallax occlusion mapping, a linear search then the
// interpolation of the last two samples (Tatarchuk, "Dynamic Parallax Occlusion Mapping with
// Approximate Soft Shadows", I3D 2006), in the relief shell.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_pom_steps;
const int kMinSteps = kParam_pom_min_steps;
const int kDepthScale = kParam_pom_depth_scale;
const int kShadowStepsParam = kParam_pom_shadow_steps;
#define RELIEF_LOD_PARAM kParam_pom_lod
#define RELIEF_MAX_MIP_SLOT kSlot_pom_depth_max_mip
const int kBaseColorSlot = kSlot_pom_base_color;
const int kNormalSlot = kSlot_pom_normal;
const int kDepthSlot = kSlot_pom_depth;

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
  return pom_search(depth, in_.uv, ds, n);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01, o);
}
