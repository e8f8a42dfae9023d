#version 450 core
// `shells`: GLSL twin of plugins/shells.cpp. The shell method (Lengyel, Praun, Finkelstein and
// Hoppe, "Real-time fur over arbitrary surfaces", I3D 2001): the prepare stage draws N offset
// copies of the surface (render/prepare.cpp), each carrying its shell index i and N in the
// quadric varying; a texel is opaque on shell i when its height 1 - depth reaches i/N (the
// material is MASK, so the discard of common.glsl cuts the rest). Shading at the fragment's own
// uv and position; self-shadow by 1 - shadow_strength * (1 - i/N).

#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kShadowStrength = kParam_shells_shadow_strength;
const int kBaseColorSlot = kSlot_shells_base_color;
const int kNormalSlot = kSlot_shells_normal;
const int kDepthSlot = kSlot_shells_depth;

#include "common.glsl"
#include "ray.glsl"
#include "search.glsl"
#include "shadow.glsl"
#include "shadow_map.glsl"

// What the C++ visibility lambda captures: the shell's light factor, then (receivers) the
// light's shadow map at the fragment.
float shell_light;
vec3 shell_pos, shell_n, shell_geo_n;
float shell_fetches;
float visibility(int i, vec3 l) {
  float vis = shell_light;
#if EFFECT_SELF_SHADOW
  if (dot(shell_geo_n, l) <= 0.0) vis = 0.0;  // below the tangent plane: blocked
#endif
#if EFFECT_RECEIVE_SHADOW
  if (vis > 0.0) vis = vis * shadow_map_visibility(i, shell_pos, shell_n, l, shell_fetches);
#endif
  return vis;
}

ShadeOut shade(FragIn in_) {
  ShadeOut o = shade_out_default();
  // the shell (plugins/shells.cpp fragment_shell) and its coverage, N - N * depth >= i
  float count = floor(in_.quadric.y + 0.5);
  count = count >= 1.0 ? count : 1.0;  // not clamp(): NaN goes to the bound as in the C++
  count = count <= 256.0 ? count : 256.0;
  float index = floor(in_.quadric.x + 0.5);
  index = index >= 0.0 ? index : 0.0;
  index = index <= count - 1.0 ? index : count - 1.0;
  float height = index / count;
  float coverage = 1.0;
  if (has_texture[kDepthSlot]) {
    float d = sample_depth(material_depth(in_, 0), in_.uv);
    o.fetches += 1.0;
    precise float above = count - count * d;  // no fused multiply-add: the C++ rounds twice
    coverage = above >= index ? 1.0 : 0.0;
  }
  o.hit_uv = in_.uv;
  o.hit_depth = 1.0 - height;
#if EFFECT_SHADOW_PASS
  o.alpha = coverage * base_alpha_at(kBaseColorSlot, in_.uv, in_, o.fetches);
  return o;
#else
  vec3 geo_n = in_.normal;
  if (!in_.front_facing) geo_n = -geo_n;
  TangentFrame tf = make_tangent_frame(geo_n, in_.tangent, in_.tangent_sign);
  vec3 w = world_view_dir(in_.position, frame.eye, frame.orthographic, frame.view_dir, -tf.n);
  vec3 n = tf.n;
  if (has_texture[kNormalSlot]) {
    vec4 c = sample_slot(kNormalSlot, in_.uv, in_);
    n = normalize_safe(to_world(tf, normal_from_texel(c, material.normal_scale)));
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
  shell_light = 1.0;
#if EFFECT_SELF_SHADOW
  shell_light = depth_darkening(1.0 - height, material.params[kShadowStrength]);
#endif
  vec2 mr = sample_metallic_roughness(in_.uv, in_, o.fetches);
  // C++: SurfaceColor::occlusion times the shell's factor, then the occlusion texture
  float occlusion = shell_light * surface_occlusion(in_.uv, in_, o.fetches);
  shell_pos = in_.position;
  shell_geo_n = tf.n;
  shell_n = n;
  shell_fetches = o.fetches;
  albedo = albedo * in_.color.rgb;  // COLOR_0 (plugins/surface.h sample_albedo)
  base_alpha *= in_.color.a;
  vec3 color = material.unlit ? albedo : shade_direct(in_.position, n, -w, albedo, mr, occlusion);
  o.fetches = shell_fetches;
  o.color = finish_surface(color, in_.uv, albedo, in_, o.fetches);
  o.alpha = base_alpha * coverage;
  o.shading_normal = n;
  return o;
#endif
}

void main() { store_out(shade(load_fragment())); }
