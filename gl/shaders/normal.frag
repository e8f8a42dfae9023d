#version 450 core
// `normal`: GLSL twin of plugins/normal.cpp. Tangent-space normal mapping (Blinn 1978,
// "Simulation of wrinkled surfaces") with Blinn-Phong lighting: the surface keeps its polygonal
// position, only the normal follows the map.
#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kBaseColorSlot = kSlot_normal_base_color;
const int kNormalSlot = kSlot_normal_normal;
const int kNormalStrength = kParam_normal_normal_strength;

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
  vec3 geo_n = in_.normal;
  if (!in_.front_facing) geo_n = -geo_n;
  TangentFrame tf = make_tangent_frame(geo_n, in_.tangent, in_.tangent_sign);
  vec3 n = tf.n;
  if (has_texture[kNormalSlot]) {
    vec4 c = sample_slot(kNormalSlot, in_.uv, in_);
    float strength = material.params[kNormalStrength] * material.normal_scale;
    vec3 nt = normal_from_texel(c, strength);
    n = normalize_safe(to_world(tf, nt));
    o.fetches += 1.0;
  }
  vec3 albedo = material.base_color.rgb;
  float base_alpha = material.base_color.a;  // x texture alpha (plugins/surface.h)
  if (has_texture[kBaseColorSlot]) {
    vec4 c = sample_slot(kBaseColorSlot, in_.uv, in_);
    albedo = albedo * c.xyz;
    base_alpha *= c.w;
    o.fetches += 1.0;
  }
  vec3 v = frame.orthographic ? -frame.view_dir : normalize_safe(frame.eye - in_.position);
  albedo = albedo * in_.color.rgb;  // COLOR_0 (plugins/surface.h sample_albedo)
  base_alpha *= in_.color.a;
  recv_p = in_.position;
  recv_n = tf.n;
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
