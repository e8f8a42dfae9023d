#version 450 core
// `relaxed_cone`: GLSL twin of plugins/relaxed_cone.cpp. Relaxed cone stepping then a binary
// search of [last outside sample, K] (Policarpo and Oliveira, "Relaxed Cone Stepping for Relief
// Mapping", GPU Gems 3 ch. 18, 2007, section 18.4.2, listing 18-3, figure 18-10; the chapter
// starts at H), bracket-safe (cone.glsl cone_finish), in the relief shell; the self-shadow ray is
// relaxed-cone searched on the material's depth.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_relaxed_cone_steps;
const int kBinarySteps = kParam_relaxed_cone_binary_steps;
const int kDepthScale = kParam_relaxed_cone_depth_scale;
const int kShadowStepsParam = kParam_relaxed_cone_shadow_steps;
const int kFallbackSteps = kParam_relaxed_cone_fallback_steps;
const int kBaseColorSlot = kSlot_relaxed_cone_base_color;
const int kNormalSlot = kSlot_relaxed_cone_normal;
const int kDepthSlot = kSlot_relaxed_cone_depth;
const int kConeSlot = kSlot_relaxed_cone_cone_relaxed;

#include "relief_shell.glsl"
#include "cone.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  if (!has_texture[kConeSlot]) return SearchHit(in_.uv, 0.0, 0.0, 0.0);
  ConeSource cone = make_cone_source(depth, false);
  if (cone.quad) cone = aim(cone, ds);
  return cone_search(depth, cone, in_.uv, ds, int(material.params[kSteps]),
                     int(material.params[kFallbackSteps]), int(material.params[kBinarySteps]));
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  if (!has_texture[kConeSlot]) return 1.0;
  ConeSource cone = make_cone_source(depth, false);
  return cone_light_visibility(depth, cone, hit, dl, lz, int(material.params[kShadowStepsParam]),
                               int(material.params[kFallbackSteps]), o);
}
