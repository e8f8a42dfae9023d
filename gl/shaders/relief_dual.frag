#version 450 core
// `relief_dual`: GLSL twin of plugins/relief_dual.cpp and shaders_cpp/dual_depth.h. Dual-depth
// relief textures (Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary
// Polygonal Surfaces", I3D 2005, section 3.1): a front and a back depth layer, a ray point at
// depth t inside the object when front <= t <= back; linear then binary search over both layers,
// misses discarded (the impostor's outline), depth correction, a self-shadow ray blocked inside
// the object, the back layer's normal map where the hit lies nearer the back layer. Without
// `depth_back` the back layer reads 1. The back layer is sampled at the front layer's LOD.
// Misses discard: no early fragment tests (common.glsl).
#define RELIEF_MAY_DISCARD 1
#include "prelude.glsl"

// Parameters and texture slots by name (the generated prelude, docs/plugins.md).
const int kSteps = kParam_relief_dual_steps;
const int kBinarySteps = kParam_relief_dual_binary_steps;
const int kMinSteps = kParam_relief_dual_min_steps;
const int kDepthScale = kParam_relief_dual_depth_scale;
const int kShadowStepsParam = kParam_relief_dual_shadow_steps;
const int kBaseColorSlot = kSlot_relief_dual_base_color;
const int kNormalSlot = kSlot_relief_dual_normal;
const int kBackDepthSlot = kSlot_relief_dual_depth_back;
const int kBackNormalSlot = kSlot_relief_dual_normal_back;
const int kDepthSlot = kSlot_relief_dual_depth;

#include "common.glsl"
#include "ray.glsl"
#include "search.glsl"
#include "shadow_map.glsl"

// The back layer at the front layer's LOD; 1 (FullDepth) when no map is bound.
float sample_back(TextureDepth depth, vec2 uv) {
  return has_texture[kBackDepthSlot] ? textureLod(textures[kBackDepthSlot], uv, depth.lod).r : 1.0;
}

bool dual_inside(float front, float back, float t) { return front <= t && t <= back; }

// Fetches a read of both layers costs: the back layer is a constant when no map is bound.
float layer_fetches() { return has_texture[kBackDepthSlot] ? 2.0 : 1.0; }

// dual_depth_search: n linear steps (t_i = i / n), depth 1 not inside by itself, m halvings;
// layer_fetches() per step.
SearchHit dual_depth_search(TextureDepth depth, vec2 uv, vec2 ds, float n, int m, out bool miss) {
  float inv_n = 1.0 / n;
  float t_out = 0.0, t_in = 0.0, steps = 0.0, fetches = 0.0;
  bool found = false;
  for (int i = 0; i <= kMaxLinearSteps; ++i) {
    float fi = float(i);
    bool last = fi >= n || i == kMaxLinearSteps;
    float t = last ? 1.0 : fi * inv_n;
    vec2 p = uv + ds * t;
    bool inside = dual_inside(sample_depth(depth, p), sample_back(depth, p), t);
    steps += 1.0;
    fetches += layer_fetches();
    if (inside) {
      t_in = t;
      found = true;
      break;
    }
    t_out = t;
    if (last) break;
  }
  float lo = t_out, hi = t_in;
  bool refine = found && hi > lo;
  for (int i = 0; i < m && refine; ++i) {
    float mid = (lo + hi) * 0.5;
    vec2 p = uv + ds * mid;
    bool inside = dual_inside(sample_depth(depth, p), sample_back(depth, p), mid);
    if (inside)
      hi = mid;
    else
      lo = mid;
    steps += 1.0;
    fetches += layer_fetches();
  }
  miss = !found;
  float t_hit = found ? hi : 0.0;
  return SearchHit(uv + ds * t_hit, t_hit, steps, fetches);
}

// dual_depth_shadow: the ray (uv + dl s, t - s), s = 1/n, 2/n, ... < t, blocked where inside the
// object by more than bias; layer_fetches() per step.
float dual_depth_shadow(TextureDepth depth, vec2 uv, float t, vec2 dl, float lz, int n, float bias,
                        inout ShadeOut o) {
  float inv_n = 1.0 / float(n);
  if (!(lz > 0.0)) return 0.0;
  float vis = 1.0;
  for (int i = 1; i <= kMaxLinearSteps; ++i) {
    float s = float(i) * inv_n;
    if (!(s < t)) break;
    vec2 p = uv + dl * s;
    float d = t - s;
    bool blocked = sample_depth(depth, p) < d - bias && sample_back(depth, p) > d + bias;
    o.shadow_steps += 1.0;
    o.fetches += layer_fetches();
    if (blocked) {
      vis = 0.0;
      break;
    }
  }
  return vis;
}

// What the C++ visibility lambda captures.
TangentFrame shell_tf;
TextureDepth shell_depth;
SearchHit shell_hit;
float shell_depth_scale;
ShadeOut shell_out;
vec3 shell_pos, shell_n;

float visibility(int i, vec3 l) {
  float vis = 1.0;
#if EFFECT_SELF_SHADOW
  if (has_texture[kDepthSlot]) {
    vec3 lt = to_tangent(shell_tf, l);
    vis = dual_depth_shadow(shell_depth, shell_hit.uv, shell_hit.depth,
                            light_step(lt, shell_depth_scale), lt.z,
                            int(material.params[kShadowStepsParam]), 0.01, shell_out);
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
    depth.lod = compute_lod(vec2(textureSize(textures[kDepthSlot], 0)), in_.duv_dx, in_.duv_dy);
    float n = relief_step_count(V.z, material.params[kMinSteps], material.params[kSteps]);
    bool miss;
    hit = dual_depth_search(depth, in_.uv, ds, n, int(material.params[kBinarySteps]), miss);
    o.discarded = miss;
  }
  o.hit_uv = hit.uv;
  o.hit_depth = hit.depth;
  o.steps = hit.steps;
  o.fetches = hit.fetches;
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
  if (has_texture[kBackNormalSlot] && has_texture[kDepthSlot]) {
    // the hit's nearer layer: back where t is closer to the back depth than to the front
    float f = sample_depth(depth, hit.uv), b = sample_back(depth, hit.uv);
    bool on_back = abs(b - hit.depth) < abs(hit.depth - f);
    if (on_back) {
      vec4 c = sample_slot(kBackNormalSlot, hit.uv, in_);
      n = normalize_safe(to_world(tf, normal_from_texel(c, material.normal_scale)));
    }
    o.fetches += layer_fetches() + (on_back ? 1.0 : 0.0);
  }
  vec3 albedo = material.base_color.rgb;
  float base_alpha = material.base_color.a;  // x texture alpha (plugins/surface.h)
  if (has_texture[kBaseColorSlot]) {
    vec4 c = sample_slot(kBaseColorSlot, hit.uv, in_);
    albedo = albedo * c.xyz;
    base_alpha *= c.w;
    o.fetches += 1.0;
  }
  shell_tf = tf;
  shell_depth = depth;
  shell_hit = hit;
  shell_depth_scale = depth_scale;
  vec2 mr = sample_metallic_roughness(hit.uv, in_, o.fetches);  // plugins/surface.h sample_surface
  // plugins/surface.h finish_surface: the occlusion texture, before lighting
  float occlusion = surface_occlusion(hit.uv, in_, o.fetches);
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

void main() { store_out(shade(load_fragment())); }
