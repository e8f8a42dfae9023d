// What the three cone-stepping plugins (cone, cone_quad, relaxed_cone) share on top of the relief
// shell (plugins/relief_shell.h): the cone-map slot, the cone source built from it at the depth
// map's per-quad LOD, and the self-shadow ray traced with the technique's own search. Dummer,
// "Cone Step Mapping", 2006; Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping",
// GPU Gems 3, ch. 18, 2007.
//
// Texture slot 3 is the cone map. Its name says which kind the plugin reads, and the planner
// derives a missing one from the depth map (render/derived_maps.h): "cone_conservative",
// "cone_quad" (four ratios +u, -u, +v, -v) or "cone_relaxed". The map has the depth map's size,
// so the depth map's LOD per quad is the cone map's too.

#if defined(RELIEF_PLUGINS_CONE_SHELL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_PLUGINS_CONE_SHELL_H_
#undef RELIEF_PLUGINS_CONE_SHELL_H_
#else
#define RELIEF_PLUGINS_CONE_SHELL_H_
#endif

#include "plugins/relief_shell.h"
#include "shaders_cpp/cone.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

inline constexpr int kConeSlot = 3;

inline constexpr TextureSlotSpec kConeConservativeSlotSpec = {
    "cone_conservative", true,
    "conservative cone map (Dummer): ratio in channel 0, min-mips; baked from depth if absent"};
inline constexpr TextureSlotSpec kConeQuadSlotSpec = {
    "cone_quad", true,
    "quad-directional cone map: ratios +u, -u, +v, -v in RGBA, min-mips; baked from depth if "
    "absent"};
inline constexpr TextureSlotSpec kConeRelaxedSlotSpec = {
    "cone_relaxed", true,
    "relaxed cone map (Policarpo & Oliveira): ratio in channel 0, min-mips; baked from depth if "
    "absent"};

inline constexpr ParamSpec kConeStepsSpec = {"steps",
                                             ParamType::kInt,
                                             15.0f,
                                             1.0f,
                                             256.0f,
                                             nullptr,
                                             "cone steps (GPU Gems 3 ch. 18 uses 15)"};
inline constexpr ParamSpec kConeShadowStepsSpec = {
    "shadow_steps",
    ParamType::kInt,
    15.0f,
    1.0f,
    256.0f,
    nullptr,
    "cone steps of the light ray (self_shadow effect)"};

// 8 halvings, as relief's: the chapter's 6 of a long relaxed bracket leave the inside end deeper
// than kConeShadowBias under `plane`'s brick tops, and the light ray starting there is shadowed
// (stray dark pixels; docs/cones.md).
inline constexpr ParamSpec kConeBinaryStepsSpec = {
    "binary_steps",
    ParamType::kInt,
    8.0f,
    0.0f,
    32.0f,
    nullptr,
    "halvings of [last outside, first inside sample] (chapter: 6, from H to K)"};
// 32 fallback steps: with cones valid for the bilinear surface most lanes finish in the march, and
// the lanes that do not are the ones the fallback's coarse samples sent through thin walls. On
// 4000 random rays (tests/builtin/cone_test.cpp fields) relaxed 15 + k + 6 at k = 8 / 32:
// mean error 0.644 / 0.347 texel on pattern, 0.140 / 0.077 on thin walls, for 38.5 / 40.4 and
// 38.9 / 41.2 fetches a ray.
inline constexpr ParamSpec kConeFallbackStepsSpec = {
    "fallback_steps",
    ParamType::kInt,
    32.0f,
    1.0f,
    64.0f,
    nullptr,
    "cone steps of at least half a texel (view ray) or a k-th of the rest (light ray) after "
    "`steps` left the ray outside the surface"};

// Depth units an occluder must rise above the shadow ray, exact's own (plugins/exact.cpp): the
// light ray starts at the surface above the hit (ConeFamilySearch::shadow), so the bias covers no
// search error. (0.01, relief's marched-shadow bias, lit points just under a crest: the thin-wall
// field's self-shadow was 2.7 % to 4.7 % off exact's, now 0.03 % to 0.04 %.)
inline constexpr float kConeShadowBias = 0.001f;

// The cone source of slot 3 (TextureCone or QuadTextureCone) at the depth map's LODs; false when
// the material has no cone map (the search then reports the fragment's own uv at depth 0).
// The nearest-texel depth reader of the relaxed march shares the depth map's LODs.
inline NearestTextureDepth nearest_depth(const TextureDepth& depth) {
  NearestTextureDepth n;
  n.texture = depth.texture;
  n.sampler = cone_sampler(*depth.sampler);
  for (int i = 0; i < kLanes; ++i) n.lod[i] = depth.lod[i];
  return n;
}

template <class Cone>
inline bool make_cone_source(const ShadeContext& ctx, const TextureDepth& depth, Cone& cone) {
  const MaterialUniforms& m = *ctx.material;
  cone.texture = m.textures[kConeSlot];
  if (!cone.texture) return false;
  cone.sampler = cone_sampler(m.samplers[kConeSlot]);
  for (int i = 0; i < kLanes; ++i) cone.lod[i] = depth.lod[i];
  return true;
}

// Indices of the cone plugins' parameters in their schemas.
struct ConeParamIndex {
  int steps, binary_steps, depth_scale, shadow_steps, fallback_steps;
};

// The search of the three cone plugins in the relief shell: `Cone` (TextureCone or
// QuadTextureCone, aimed along each ray) from slot 3, cone_search on the material's depth for the
// view ray, cone_occluder_search for the light ray. They differ only in the cone map they read.
template <class Cone, const ConeParamIndex& kIndex>
struct ConeFamilySearch {
  static constexpr int kDepthScale = kIndex.depth_scale;
  template <class F>
  static void aim(Cone& cone, const V2<F>& dir) {
    if constexpr (requires { cone.aim(dir); }) cone.aim(dir);
  }
  // The view ray of one group for cone_search: the cone aimed along ds, the fallback floor half a
  // texel of the depth map along the ray.
  template <class F>
  static ConeRay<F, TextureDepth, Cone> view_ray(const TextureDepth& depth, Cone& cone,
                                                 const FragIn<F>& in, const V2<F>& ds,
                                                 mask_t<F> active) {
    aim(cone, ds);
    return {&depth,
            &cone,
            in.uv,
            ds,
            half_texel_along(depth.texture->width(), depth.texture->height(), ds),
            active};
  }
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>&, const V2<F>& ds,
                             mask_t<F> active) {
    Cone cone;
    if (!make_cone_source(ctx, depth, cone)) return unmoved_hit(in);
    const ConeRay<F, TextureDepth, Cone> r = view_ray(depth, cone, in, ds, active);
    const float* p = ctx.material->params;
    return cone_search(depth, cone, r.uv, r.ds, static_cast<int>(p[kIndex.steps]),
                       static_cast<int>(p[kIndex.fallback_steps]),
                       static_cast<int>(p[kIndex.binary_steps]), r.view_floor, r.active);
  }
  // search() of two groups of lanes, their rays stepped side by side (cone_search_pair).
  static constexpr bool kPairedSearch = true;
  template <class F>
  static void search_pair(const ShadeContext& ctx, const FragIn<F>& in_a, const FragIn<F>& in_b,
                          const TextureDepth& depth_a, const TextureDepth& depth_b,
                          const V2<F>& ds_a, const V2<F>& ds_b, mask_t<F> active_a,
                          mask_t<F> active_b, SearchHit<F>& hit_a, SearchHit<F>& hit_b) {
    Cone cone_a, cone_b;
    if (!make_cone_source(ctx, depth_a, cone_a) || !make_cone_source(ctx, depth_b, cone_b)) {
      hit_a = unmoved_hit(in_a);
      hit_b = unmoved_hit(in_b);
      return;
    }
    const float* p = ctx.material->params;
    cone_search_pair(view_ray(depth_a, cone_a, in_a, ds_a, active_a),
                     view_ray(depth_b, cone_b, in_b, ds_b, active_b),
                     static_cast<int>(p[kIndex.steps]), static_cast<int>(p[kIndex.fallback_steps]),
                     static_cast<int>(p[kIndex.binary_steps]), hit_a, hit_b);
  }
  // The light ray of a self-shadow query (light_ray, kConeShadowBias). It starts at the surface
  // above the hit (the hit lies at or under it by up to its last bracket over 2^binary_steps), so
  // the bias needs to cover no search error; that read is counted into `o`.
  template <class F>
  static LightRay<F> shadow_ray(const ShadowQuery<F>& q, ShadeOut<F>& o) {
    const F t = vmin(q.hit.depth, sample_depth(q.depth, q.hit.uv, q.lit));
    o.fetches += detail::count<F>(q.lit);
    return light_ray(q.hit.uv, t, q.dl, q.lz, kConeShadowBias, q.lit);
  }
  // The visibility of a light ray whose occluder search found h, its work counted into `o`.
  template <class F>
  static F shadow_result(const LightRay<F>& ray, const SearchHit<F>& h, ShadeOut<F>& o) {
    const ConeShadow<F> s = light_ray_result(ray, h);
    o.shadow_steps += s.steps;
    o.fetches += s.fetches;
    return s.visibility;
  }
  // Self-shadow: the light ray searched by the plugin's own occluder search
  // (cone_occluder_search, shadow_steps cone steps and fallback_steps), light_ray_shadow's test.
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    Cone cone;
    if (!make_cone_source(ctx, depth, cone)) return F(1.0f);
    const float* p = ctx.material->params;
    const LightRay<F> ray = shadow_ray<F>({depth, hit, dl, lz, lit}, o);
    if (none(ray.trace)) return ray.vis;
    aim(cone, ray.down);
    return shadow_result(
        ray,
        cone_occluder_search(depth, cone, ray.entry, ray.down,
                             static_cast<int>(p[kIndex.shadow_steps]),
                             static_cast<int>(p[kIndex.fallback_steps]), ray.trace, ray.t_max),
        o);
  }
  // shadow() of two groups, their light rays searched side by side
  // (cone_occluder_search_pair).
  static constexpr bool kPairedShadow = true;
  template <class F>
  static void shadow_pair(const ShadeContext& ctx, const ShadowQuery<F>& a, const ShadowQuery<F>& b,
                          ShadeOut<F>& oa, ShadeOut<F>& ob, F& vis_a, F& vis_b) {
    Cone cone_a, cone_b;
    if (!make_cone_source(ctx, a.depth, cone_a) || !make_cone_source(ctx, b.depth, cone_b)) {
      vis_a = vis_b = F(1.0f);
      return;
    }
    const float* p = ctx.material->params;
    const LightRay<F> ray_a = shadow_ray(a, oa), ray_b = shadow_ray(b, ob);
    aim(cone_a, ray_a.down);
    aim(cone_b, ray_b.down);
    SearchHit<F> hit_a, hit_b;
    cone_occluder_search_pair(a.depth, cone_a, ray_a, b.depth, cone_b, ray_b,
                              static_cast<int>(p[kIndex.shadow_steps]),
                              static_cast<int>(p[kIndex.fallback_steps]), hit_a, hit_b);
    vis_a = shadow_result(ray_a, hit_a, oa);
    vis_b = shadow_result(ray_b, hit_b, ob);
  }
};

// The descriptor of a cone plugin: its schema and slots, and `select` (the shell's variants of its
// search for every SIMD target, RELIEF_SELECT_FOR_EVERY_TARGET in plugins/shading.h).
template <size_t kNumParams, size_t kNumSlots>
constexpr PluginDescriptor cone_plugin(const char* name, const char* description,
                                       const ParamSpec (&params)[kNumParams],
                                       const TextureSlotSpec (&slots)[kNumSlots],
                                       ShadeFn (*select)(EffectMask)) {
  return {kPluginAbiVersion,
          name,
          description,
          params,
          static_cast<int>(kNumParams),
          slots,
          static_cast<int>(kNumSlots),
          kReliefShellEffects,
          select,
          &relief_depth_output,
          nullptr,
          nullptr,
          nullptr,
          nullptr};
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_PLUGINS_CONE_SHELL_H_
