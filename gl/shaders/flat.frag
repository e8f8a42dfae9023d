#version 450 core
// `flat`: GLSL twin of plugins/flat.cpp. Lambert and Blinn-Phong over the interpolated normal
// and a base colour (texture or constant). The baseline every relief technique is compared
// against.
#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kBaseColorSlot = kSlot_flat_base_color;

#include "common.glsl"

#include "shadow_map.glsl"

// The C++ ShadowMapReceiver (EFFECT_RECEIVE_SHADOW): light i's map at the polygon point, compared
// against the plane with normal recv_n; NoShadow otherwise.
vec3 recv_p, recv_n;
float recv_fetches;
float visibility(int i, vec3 l) {
#if EFFECT_RECEIVE_SHADOW
  return shadow_map_visibility(i, recv_p, recv_n, l, recv_fetches);
#else
  return 1.0;
#endif
}

ShadeOut shade(FragIn in_) {
  ShadeOut o = shade_out_default();
  vec3 n = normalize_safe(in_.normal);
  if (!in_.front_facing) n = -n;
  vec3 albedo = material.base_color.rgb;
  float base_alpha = material.base_color.a;  // x texture alpha (plugins/surface.h)
  if (has_texture[kBaseColorSlot]) {
    vec4 c = sample_slot(kBaseColorSlot, in_.uv, in_);
    albedo = albedo * c.xyz;
    base_alpha *= c.w;
    o.fetches = 1.0;
  }
  vec3 v = frame.orthographic ? -frame.view_dir : normalize_safe(frame.eye - in_.position);
  albedo = albedo * in_.color.rgb;  // COLOR_0 (plugins/surface.h sample_albedo)
  base_alpha *= in_.color.a;
  recv_p = in_.position;
  recv_n = n;
  vec2 mr = sample_metallic_roughness(in_.uv, in_, o.fetches);  // plugins/surface.h sample_surface
  // plugins/surface.h finish_surface: the occlusion texture, before lighting
  float occlusion = surface_occlusion(in_.uv, in_, o.fetches);
  recv_fetches = o.fetches;
  o.color = material.unlit ? albedo : shade_direct(in_.position, n, v, albedo, mr, occlusion);
  o.fetches = recv_fetches;
  o.color = finish_surface(o.color, in_.uv, albedo, in_, o.fetches);
  o.alpha = base_alpha;
  o.hit_uv = in_.uv;
  o.shading_normal = n;
  return o;
}

void main() { store_out(shade(load_fragment())); }
