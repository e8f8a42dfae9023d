#version 450 core
// `cone`: GLSL twin of plugins/cone.cpp. Conservative cone stepping (Dummer, "Cone Step Mapping:
// An Iterative Ray-Heightfield Intersection Algorithm", 2006) with the conservative cone map of
// slot 3 and cone.glsl's bracket-safe finish, in the relief shell; the self-shadow ray is searched
// the same way.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_cone_steps;
const int kDepthScale = kParam_cone_depth_scale;
const int kShadowStepsParam = kParam_cone_shadow_steps;
const int kBinarySteps = kParam_cone_binary_steps;
const int kFallbackSteps = kParam_cone_fallback_steps;
const int kBaseColorSlot = kSlot_cone_base_color;
const int kNormalSlot = kSlot_cone_normal;
const int kDepthSlot = kSlot_cone_depth;
const int kConeSlot = kSlot_cone_cone_conservative;

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
