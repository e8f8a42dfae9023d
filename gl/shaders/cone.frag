#version 450 core
// `cone`: GLSL twin of plugins/cone.cpp. Conservative cone stepping (Dummer, "Cone Step Mapping:
// An Iterative Ray-Heightfield Intersection Algorithm", 2006) with the conservative cone map of
// slot 3 and cone.glsl's bracket-safe finish, in the relief shell; the self-shadow ray is searched
// the same way.

// Parameters, schema order.
const int kSteps = 0;
const int kDepthScale = 1;
const int kShadowStepsParam = 2;
const int kBinarySteps = 3;
const int kFallbackSteps = 4;

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
