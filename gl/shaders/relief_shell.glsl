// Twin of plugins/relief_shell.h: the shell every height-field technique shares (parallax,
// steep_parallax, pom, relief, exact): the per-fragment tangent frame, the view ray in texture
// space, the constant LOD per quad, depth correction of the hit, shading at the hit with the
// normal and base-colour maps, and the visibility hook: the technique's self-shadow ray, then
// (EFFECT_RECEIVE_SHADOW) the light's shadow map (shadow_map.glsl) looked up at the displaced hit
// point; with EFFECT_SHADOW_PASS the shader stops after the intersection and the corrected depth
// (the frame's eye is then the light). Policarpo, Oliveira and Comba,
// "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005 (figure 10 for the shadow
// ray, section 2 for the depth correction).
//
// A twin is its policy, as in C++. Before including this file it includes prelude.glsl and
// defines, from the prelude's kParam_<technique>_* and kSlot_<technique>_* names,
//   const int kDepthScale;  // schema index of "depth_scale"
//   const int kBaseColorSlot, kNormalSlot, kDepthSlot;  // texture slots base_color, normal, depth
// and, for a search with a `lod` parameter (the C++ policy's kLodParam and kMaxMipSlot),
//   #define RELIEF_LOD_PARAM <index>  and  #define RELIEF_MAX_MIP_SLOT <slot>
// and after it the two hooks declared below (search and shadow). The C++ kernel's template
// parameter kEffects is the EFFECT_* defines here: one program per combination.
#include "common.glsl"
#include "ray.glsl"
#include "search.glsl"
#include "shadow.glsl"
#include "shadow_map.glsl"

// First hit of the ray uv + t * (ds, 1) in depth units (V: tangent-space view direction).
SearchHit search(FragIn in_, TextureDepth depth, vec3 V, vec2 ds);
// Visibility in [0, 1] of the hit towards a light (tangent-space z = lz, texture step dl); adds
// its steps and fetches to o.
float shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, inout ShadeOut o);
#ifdef RELIEF_SELF_OCCLUSION
// Optional (a twin that defines RELIEF_SELF_OCCLUSION): the indirect light's factor at the hit
// while self-shadow is on.
float self_occlusion(SearchHit hit);
#endif

#ifndef EFFECT_HEIGHT_AO
#define EFFECT_HEIGHT_AO 0
#endif
#if EFFECT_HEIGHT_AO
// Height-field ambient occlusion: shaders_cpp/height_ao.h height_field_ao (kHeightAoSteps 4,
// kHeightAoBias 1/1024, tangents clamped at 1e4) times plugins/relief_shell.h's strength, the
// factor of the indirect term; its depth reads added to `fetches`.
uniform int height_ao_rays;
uniform float height_ao_radius;
uniform float height_ao_strength;
float height_ao_factor(TextureDepth depth, vec2 uv, float depth_scale, inout float fetches) {
  if (height_ao_rays <= 0 || !(height_ao_radius > 0.0)) return 1.0;
  float d0 = sample_depth(depth, uv);
  float sum = 0.0;
  for (int k = 0; k < height_ao_rays; ++k) {
    float a = 6.283185307179586 * float(k) / float(height_ao_rays);
    vec2 dir = vec2(cos(a), sin(a));
    float h = 0.0;
    for (int j = 1; j <= 4; ++j) {
      float t = height_ao_radius * float(j) / 4.0;
      float slope = min(depth_scale / t, 1e30);
      h = max(h, (d0 - sample_depth(depth, uv + dir * t) - 1.0 / 1024.0) * slope);
    }
    h = min(h, 1e4);
    sum += 1.0 - h / sqrt(1.0 + h * h);
  }
  fetches += float(1 + height_ao_rays * 4);
  return 1.0 - height_ao_strength * (1.0 - sum / float(height_ao_rays));
}
#endif

// What the C++ visibility lambda captures.
TangentFrame shell_tf;
TextureDepth shell_depth;
SearchHit shell_hit;
float shell_depth_scale;
ShadeOut shell_out;
vec3 shell_pos, shell_n;  // the displaced hit point and its shading normal (receivers)

// Self-shadow ray, then the light's shadow map where the ray left the point lit (vis > 0).
float visibility(int i, vec3 l) {
  float vis = 1.0;
#if EFFECT_SELF_SHADOW
  if (has_texture[kDepthSlot]) {
    vec3 lt = to_tangent(shell_tf, l);
    vis = shadow(shell_depth, shell_hit, light_step(lt, shell_depth_scale), lt.z, shell_out);
  }
#endif
#if EFFECT_RECEIVE_SHADOW
  if (vis > 0.0) vis = vis * shadow_map_visibility(i, shell_pos, shell_n, l, shell_out.fetches);
#endif
  return vis;
}

ShadeOut shade(FragIn in_) {
  ShadeOut o = shade_out_default();
  vec3 geo_n = in_.normal;
  if (!in_.front_facing) geo_n = -geo_n;
  TangentFrame tf = make_tangent_frame(geo_n, in_.tangent, in_.tangent_sign);
  vec3 w = world_view_dir(in_.position, frame.eye, frame.orthographic, frame.view_dir, -tf.n);
  vec3 V = to_tangent(tf, w);
  float depth_scale = material.params[kDepthScale];
  vec2 ds = texture_step(V, depth_scale);
  TextureDepth depth = TextureDepth(0.0, false);
  SearchHit hit = SearchHit(in_.uv, 0.0, 0.0, 0.0);
  if (has_texture[kDepthSlot]) {
    // constant LOD per quad, outside the loops
#ifdef RELIEF_LOD_PARAM
    depth = material_depth(in_, int(material.params[RELIEF_LOD_PARAM]));
#else
    depth = material_depth(in_, 0);
#endif
    hit = search(in_, depth, V, ds);
  }
  o.hit_uv = hit.uv;
  o.hit_depth = hit.depth;
  o.steps = hit.steps;
  o.fetches = hit.fetches;
  // world units per uv along T and B (scene/mesh_prep.cpp tile scale)
  float world_height = depth_scale * (in_.tile_scale.x + in_.tile_scale.y) * 0.5;
  vec3 pos = hit_world_position(in_.position, w, V.z, hit.depth, world_height);
#if EFFECT_DEPTH_WRITE || EFFECT_SHADOW_PASS
  o.depth = min(reversed_z_depth(frame.view_proj, pos, in_.frag_z), in_.frag_z);
#endif
#if EFFECT_SHADOW_PASS
  // MASK casters cut their shadow by the base colour's alpha at the hit
  if (material.alpha_mode == kAlphaMask)
    o.alpha = base_alpha_at(kBaseColorSlot, hit.uv, in_, o.fetches);
  return o;
#else
  vec3 n = tf.n;
  if (has_texture[kNormalSlot]) {
    vec4 c = sample_slot(kNormalSlot, hit.uv, in_);
    n = normalize_safe(to_world(tf, normal_from_texel(c, material.normal_scale)));
    o.fetches += 1.0;
  }
  vec3 albedo = material.base_color.rgb;
  float base_alpha = material.base_color.a;  // x texture alpha (plugins/surface.h)
  if (has_texture[kBaseColorSlot]) {
    vec4 c = sample_slot(kBaseColorSlot, hit.uv, in_);
    albedo = albedo * c.xyz;
    base_alpha *= c.w;
    o.fetches += 1.0;
  }
  // the indirect term's factor (C++: SurfaceColor::occlusion before finish_surface)
  float height_occlusion = 1.0;
#if EFFECT_HEIGHT_AO
  if (has_texture[kDepthSlot])
    height_occlusion = height_ao_factor(depth, hit.uv, depth_scale, o.fetches);
#endif
  // lighting at the displaced point
  shell_tf = tf;
  shell_depth = depth;
  shell_hit = hit;
  shell_depth_scale = depth_scale;
  vec2 mr = sample_metallic_roughness(hit.uv, in_, o.fetches);  // plugins/surface.h sample_surface
  // plugins/surface.h finish_surface: the occlusion texture, before lighting
  float occlusion = height_occlusion * surface_occlusion(hit.uv, in_, o.fetches);
#if EFFECT_SELF_SHADOW && defined(RELIEF_SELF_OCCLUSION)
  occlusion *= self_occlusion(hit);
#endif
  shell_out = o;
  shell_pos = pos;
  shell_n = n;
  albedo = albedo * in_.color.rgb;  // COLOR_0 (plugins/surface.h sample_albedo)
  base_alpha *= in_.color.a;
  vec3 color = material.unlit ? albedo : shade_direct(pos, n, -w, albedo, mr, occlusion);
  o = shell_out;
  o.color = finish_surface(color, hit.uv, albedo, in_, o.fetches);
  o.alpha = base_alpha;
  o.shading_normal = n;
  return o;
#endif
}

// The marched self-shadow ray of shadow.glsl with a start offset `bias` in depth units.
float marched_shadow(TextureDepth depth, SearchHit hit, vec2 dl, float lz, int steps, float bias,
                     inout ShadeOut o) {
  ShadowResult sr = self_shadow(depth, hit.uv, hit.depth, dl, lz, steps, bias);
  o.shadow_steps += sr.steps;
  o.fetches += sr.fetches;
  return sr.visibility;
}

void main() { store_out(shade(load_fragment())); }
