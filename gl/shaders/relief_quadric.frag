#version 450 core
// `relief_quadric`: GLSL twin of plugins/relief_quadric.cpp. Relief mapping with correct
// silhouettes on per-vertex quadrics (Oliveira and Policarpo, "An Efficient Representation for
// Surface Details", UFRGS RP-351, 2005, sections 3 to 3.5): the texture-space ray against the
// quadric-deformed height field (quadric.glsl), linear then binary search over [0, t_max]; rays
// that leave the relief without a hit are discarded (silhouette), whatever the material's
// effects. Depth correction writes the hit's depth; no self-shadow (section 3.5), shadow maps
// looked up at the hit. Shares the relief shell's frame, per-quad LOD, normal and colour maps.
// search=relaxed_cone: relaxed cone stepping on the deformed field, bracket-safe (quadric.glsl).
// Misses discard: no early fragment tests (common.glsl).
#define RELIEF_MAY_DISCARD 1
#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
#define RELIEF_MAX_MIP_SLOT kSlot_relief_quadric_depth_max_mip
const int kSteps = kParam_relief_quadric_steps;
const int kBinarySteps = kParam_relief_quadric_binary_steps;
const int kMinSteps = kParam_relief_quadric_min_steps;
const int kDepthScale = kParam_relief_quadric_depth_scale;
const int kDistance = kParam_relief_quadric_distance;
const int kSearch = kParam_relief_quadric_search;
const int kConeSteps = kParam_relief_quadric_cone_steps;
const int kFallbackSteps = kParam_relief_quadric_fallback_steps;
const int kLod = kParam_relief_quadric_lod;
const int kBaseColorSlot = kSlot_relief_quadric_base_color;
const int kNormalSlot = kSlot_relief_quadric_normal;
const int kDepthSlot = kSlot_relief_quadric_depth;
const int kConeSlot = kSlot_relief_quadric_cone_relaxed;

#include "common.glsl"
#include "ray.glsl"
#include "search.glsl"
#include "cone.glsl"
#include "quadric.glsl"
#include "shadow_map.glsl"

// The C++ ShadowMapReceiver (EFFECT_RECEIVE_SHADOW): the map at the hit, against the plane with
// the shading normal; NoShadow otherwise.
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
  int kind = material.params[kDistance] >= 0.5 ? kQuadricAccurate : kQuadricApproximate;
  vec3 geo_n = in_.normal;
  if (!in_.front_facing) geo_n = -geo_n;
  TangentFrame tf = make_tangent_frame(geo_n, in_.tangent, in_.tangent_sign);
  vec3 w = world_view_dir(in_.position, frame.eye, frame.orthographic, frame.view_dir, -tf.n);
  vec3 V = to_tangent(tf, w);
  float depth_scale = material.params[kDepthScale];
  // seen from the back the surface curves the other way
  vec2 q = in_.front_facing ? in_.quadric : -in_.quadric;
  // relief depth in world units: depth_scale uv units (as in the relief shell)
  float sz = depth_scale * (in_.tile_scale.x + in_.tile_scale.y) * 0.5;
  float t = 0.0, world_per_t = 0.0;
  vec2 hit_uv = in_.uv;
  if (has_texture[kDepthSlot]) {
    // constant LOD per quad, outside the loops
    TextureDepth depth = material_depth(in_, int(material.params[kLod]));
    QuadricRay ray = make_quadric_ray(kind, V, q, in_.tile_scale, sz);
    int m = int(material.params[kBinarySteps]);
    QuadricHit h;
    if (material.params[kSearch] >= 0.5 && has_texture[kConeSlot]) {
      ConeSource cone = make_cone_source(depth, false);
      h = quadric_relaxed_cone_search(kind, depth, cone, in_.uv, ray,
                                      int(material.params[kConeSteps]),
                                      int(material.params[kFallbackSteps]), m);
    } else {
      float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
      h = quadric_search(kind, depth, in_.uv, ray, n, m);
    }
    hit_uv = h.hit.uv;
    t = h.t;
    world_per_t = ray.world_per_t;
    o.hit_depth = h.hit.depth;
    o.steps = h.hit.steps;
    o.fetches = h.hit.fetches;
    o.discarded = h.miss;
  }
  o.hit_uv = hit_uv;
  precise float dist = t * world_per_t;
  vec3 pos = in_.position + w * dist;
#if EFFECT_DEPTH_WRITE || EFFECT_SHADOW_PASS
  o.depth = min(reversed_z_depth(frame.view_proj, pos, in_.frag_z), in_.frag_z);
#endif
#if EFFECT_SHADOW_PASS
  // MASK casters cut their shadow by the base colour's alpha at the hit
  if (material.alpha_mode == kAlphaMask)
    o.alpha = base_alpha_at(kBaseColorSlot, hit_uv, in_, o.fetches);
  return o;
#else
  vec3 n = tf.n;
  if (has_texture[kNormalSlot]) {
    vec4 c = sample_slot(kNormalSlot, hit_uv, in_);
    n = normalize_safe(to_world(tf, normal_from_texel(c, material.normal_scale)));
    o.fetches += 1.0;
  }
  vec3 albedo = material.base_color.rgb;
  float base_alpha = material.base_color.a;  // x texture alpha (plugins/surface.h)
  if (has_texture[kBaseColorSlot]) {
    vec4 c = sample_slot(kBaseColorSlot, hit_uv, in_);
    albedo = albedo * c.xyz;
    base_alpha *= c.w;
    o.fetches += 1.0;
  }
  albedo = albedo * in_.color.rgb;  // COLOR_0 (plugins/surface.h sample_albedo)
  base_alpha *= in_.color.a;
  recv_p = pos;
  recv_n = n;
  vec2 mr = sample_metallic_roughness(hit_uv, in_, o.fetches);  // plugins/surface.h sample_surface
  // plugins/surface.h finish_surface: the occlusion texture, before lighting
  float occlusion = surface_occlusion(hit_uv, in_, o.fetches);
  recv_fetches = o.fetches;
  o.color = material.unlit ? albedo : shade_direct(pos, n, -w, albedo, mr, occlusion);
  o.fetches = recv_fetches;
  o.color = finish_surface(o.color, hit_uv, albedo, in_, o.fetches);
  o.alpha = base_alpha;
  o.shading_normal = n;
  return o;
#endif
}

void main() { store_out(shade(load_fragment())); }
