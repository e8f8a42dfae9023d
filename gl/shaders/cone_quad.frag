#version 450 core
// `cone_quad`: GLSL twin of plugins/cone_quad.cpp. Quad-directional cone stepping (Policarpo and
// Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007, figure 18-1c;
// on Dummer's cone stepping, 2006): each ray uses the wider ratio of its quadrant, in the relief
// shell; the self-shadow ray likewise.

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
