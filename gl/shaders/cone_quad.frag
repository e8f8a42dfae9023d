#version 450 core
// `cone_quad`: GLSL twin of plugins/cone_quad.cpp. Quad-directional cone stepping (Policarpo and
// Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007, figure 18-1c;
// on Dummer's cone stepping, 2006): each ray uses the wider ratio of its quadrant, in the relief
// shell; the self-shadow ray likewise.

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_cone_quad_steps;
const int kDepthScale = kParam_cone_quad_depth_scale;
const int kShadowStepsParam = kParam_cone_quad_shadow_steps;
const int kBinarySteps = kParam_cone_quad_binary_steps;
const int kFallbackSteps = kParam_cone_quad_fallback_steps;
const int kBaseColorSlot = kSlot_cone_quad_base_color;
const int kNormalSlot = kSlot_cone_quad_normal;
const int kDepthSlot = kSlot_cone_quad_depth;
const int kConeSlot = kSlot_cone_quad_cone_quad;

#include "relief_shell.glsl"
#include "cone.glsl"

SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds) {
  if (!has_texture[kConeSlot]) return SearchHit(in_.uv, 0.0, 0.0, 0.0);
  ConeSource cone = make_cone_source(depth, true);
  if (cone.quad) cone = aim(cone, ds);
  return cone_search(depth, cone, in_.uv, ds, int(material.params[kSteps]),
                     int(material.params[kFallbackSteps]), int(material.params[kBinarySteps]));
}

float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o) {
  if (!has_texture[kConeSlot]) return 1.0;
  ConeSource cone = make_cone_source(depth, true);
  return cone_light_visibility(depth, cone, hit, dl, lz, int(material.params[kShadowStepsParam]),
                               int(material.params[kFallbackSteps]), o);
}
