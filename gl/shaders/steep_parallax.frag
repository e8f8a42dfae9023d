#version 450 core
// `steep_parallax`: GLSL twin of plugins/steep_parallax.cpp. Steep parallax mapping, n depth
// planes at a constant LOD and a self-shadow loop (McGuire and McGuire, "Steep Parallax Mapping",
// I3D 2005 poster), in the relief shell.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_steep_parallax_steps;
const int kDepthScale = kParam_steep_parallax_depth_scale;
const int kShadowStepsParam = kParam_steep_parallax_shadow_steps;
const int kShadowMode = kParam_steep_parallax_shadow;  // 0 ray, 1 depth
const int kShadowStrength = kParam_steep_parallax_shadow_strength;
#define RELIEF_SELF_OCCLUSION 1
#define RELIEF_LOD_PARAM kParam_steep_parallax_lod
#define RELIEF_MAX_MIP_SLOT kSlot_steep_parallax_depth_max_mip
const int kBaseColorSlot = kSlot_steep_parallax_base_color;
const int kNormalSlot = kSlot_steep_parallax_normal;
const int kDepthSlot = kSlot_steep_parallax_depth;

#include "relief_shell.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  return steep_parallax_search(depth, in_.uv, ds, material.params[kSteps]);
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  // shadow=depth: darkening with depth (shaders_cpp/shadow.h depth_darkening), blocked below the
  // tangent plane as the ray is
  if (int(material.params[kShadowMode]) == 1)
    return lz > 0.0 ? depth_darkening(hit.depth, material.params[kShadowStrength]) : 0.0;
  int steps = int(material.params[kShadowStepsParam]);
  return marched_shadow(depth, hit, dl, lz, steps, 0.01 + 1.0 / material.params[kSteps], o);
}

// The indirect light's factor at the hit while self-shadow is on (C++: SteepSearch::self_occlusion).
float self_occlusion(SearchHit hit) {
  return int(material.params[kShadowMode]) == 1
             ? depth_darkening(hit.depth, material.params[kShadowStrength])
             : 1.0;
}
