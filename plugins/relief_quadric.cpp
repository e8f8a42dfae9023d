// `relief_quadric`: relief mapping with correct silhouettes on per-vertex quadrics.
// Oliveira and Policarpo, "An Efficient Representation for Surface Details", UFRGS RP-351, 2005,
// sections 3 to 3.5. The view ray runs in texture space against the height field deformed onto
// the fragment's interpolated quadric (equations 8 and 9, shaders_cpp/quadric.h): linear then
// binary search over [0, t_max]; `distance=approximate` measures the ray's depth below the quadric
// vertically (equation 7, the paper's default), `accurate` along U (equation 6, equation 7 where
// its discriminant is negative). Rays that come back to depth 0 without a hit are silhouette and
// are discarded, whether or not the material asks for the silhouette effect. Depth correction
// writes the hit's depth; shadows come from shadow maps (section 3.5: the deformed field has no
// texture-space entry point for a shadow ray), so there is no self_shadow effect.
// `search=relaxed_cone` replaces the linear + binary search with relaxed cone stepping on the
// deformed field, a bracket-safe fallback (`fallback_steps`) and halvings of the last bracket,
// all on the material's filtered depth (shaders_cpp/quadric.h, quadric_relaxed_cone_search); the
// relaxed cone map of slot 3 is baked from the depth map only when that search is chosen
// (reads_texture). Shares with the relief shell (plugins/relief_shell.h) the tangent frame, the
// per-quad depth LOD, the normal and colour maps and the lights.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/relief_quadric.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/cone_shell.h"
#include "plugins/relief_shell.h"
#include "shaders_cpp/quadric.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param {
  kSteps,
  kBinarySteps,
  kMinSteps,
  kDepthScaleParam,
  kDistanceParam,
  kSearchParam,
  kConeStepsParam,
  kFallbackStepsParam,
  kLodParam
};
const ParamSpec kParams[] = {
    {"steps", ParamType::kInt, 32.0f, 1.0f, 256.0f, nullptr,
     "linear search steps over [0, t_max] at grazing angles"},
    kBinaryStepsSpec,
    kMinStepsSpec,
    kDepthScaleSpec,
    {"distance", ParamType::kEnum, 0.0f, 0.0f, 1.0f, "approximate|accurate",
     "ray-quadric distance: approximate (equation 7) or accurate (equation 6)"},
    {"search", ParamType::kEnum, 0.0f, 0.0f, 1.0f, "linear|relaxed_cone",
     "linear + binary search (the paper), or relaxed cone stepping + binary search on the "
     "deformed field (relaxed cone map baked from depth if absent)"},
    {"cone_steps", ParamType::kInt, 15.0f, 1.0f, 256.0f, nullptr,
     "relaxed cone steps (search=relaxed_cone; GPU Gems 3 ch. 18 uses 15)"},
    kConeFallbackStepsSpec,  // search=relaxed_cone
    kSearchLodSpec,
};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec,
                                  kNormalSlotSpec,
                                  kDepthSlotSpec,
                                  {"cone_relaxed", false,
                                   "relaxed cone map for search=relaxed_cone (baked from depth "
                                   "if absent)"},
                                  kMaxMipSlotSpec};
constexpr int kMaxMipSlot = 4;

bool relaxed_search(const float* params) {
  return params[kSearchParam] >= 0.5f;
}
bool reads_texture(const float* params, int slot) {
  return (slot != kConeSlot || relaxed_search(params)) &&
         reads_max_mip_slot<kLodParam, kMaxMipSlot>(params, slot);
}

template <EffectMask kEffects>
struct QuadricKernel {
  static constexpr bool kDepth = (kEffects & (kEffectDepthWrite | kEffectShadowPass)) != 0;
  static constexpr bool kShadowPass = (kEffects & kEffectShadowPass) != 0;
  static constexpr bool kReceive = (kEffects & kEffectReceiveShadow) != 0;

  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    if (ctx.material->params[kDistanceParam] >= 0.5f)
      return shade_with<QuadricDistance::kAccurate>(ctx, in);
    return shade_with<QuadricDistance::kApproximate>(ctx, in);
  }

  template <QuadricDistance kD, class F>
  static ShadeOut<F> shade_with(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    const ShellView<F> view = shell_view(ctx, in);
    const TangentFrame<F>& tf = view.tf;
    const V3<F>&w = view.w, &V = view.V;
    const F depth_scale(m.params[kDepthScaleParam]);
    const mask_t<F> active = covered_lanes(in);
    const TextureDepth depth = material_depth(m, in, kLodParam, kMaxMipSlot);
    // seen from the back the surface curves the other way
    const V2<F> q = in.front_facing ? in.quadric : V2<F>(-in.quadric.x, -in.quadric.y);
    const F sz = relief_world_height(depth_scale, in);
    F t(0.0f), world_per_t(0.0f);
    V2<F> hit_uv = in.uv;
    if (depth.texture) {
      const QuadricRay<F> ray = make_quadric_ray<kD>(V, q, in.tile_scale, sz);
      const float* p = m.params;
      const int m_steps = static_cast<int>(p[kBinarySteps]);
      TextureCone cone;
      QuadricHit<F> h;
      if (relaxed_search(p) && make_cone_source(ctx, depth, cone)) {
        const V2<F> duv(ray.dir.x, ray.dir.y);
        const F view_floor = half_texel_along(depth.texture->width(), depth.texture->height(), duv);
        h = quadric_relaxed_cone_search<kD>(
            depth, cone, in.uv, ray, static_cast<int>(p[kConeStepsParam]),
            static_cast<int>(p[kFallbackStepsParam]), m_steps, view_floor, active);
      } else {
        const F n = relief_step_count(V.z, p[kMinSteps], p[kSteps]);
        h = quadric_search<kD>(depth, in.uv, ray, n, m_steps, active);
      }
      hit_uv = h.hit.uv;
      t = h.t;
      world_per_t = ray.world_per_t;
      o.hit_depth = h.hit.depth;
      o.steps = h.hit.steps;
      o.fetches = h.hit.fetches;
      o.discard = h.miss;
    }
    o.hit_uv = hit_uv;
    const V3<F> pos = in.position + w * (t * world_per_t);
    if constexpr (kDepth) o.depth = corrected_depth(ctx, in, pos);
    if constexpr (kShadowPass) {
      // MASK casters cut their shadow where the base colour at the hit is below the cutoff
      if (m.alpha_mode == AlphaMode::kMask)
        o.alpha = sample_alpha(m, kBaseColorSlot, hit_uv, in, o.fetches);
      return o;
    } else {
      const V3<F> nrm = sample_normal_map(m, kNormalSlot, tf, hit_uv, in, F(1.0f), o.fetches);
      SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, hit_uv, in, o.fetches, &o.alpha);
      o.color = finish_surface(ctx, in, hit_uv, sc, o.fetches, [&] {
        return shade_lights<kReceive>(ctx, pos, nrm, nrm, -w, sc, o.fetches);
      });
      o.shading_normal = nrm;
      return o;
    }
  }
};

ShadeFn select_quadric(EffectMask e) {
  constexpr EffectMask kD = kEffectDepthWrite, kR = kEffectReceiveShadow;
  if (e & kEffectShadowPass) return &shade_packet<QuadricKernel<kEffectShadowPass>>;
  if (e & kD)
    return (e & kR) ? &shade_packet<QuadricKernel<kD | kR>> : &shade_packet<QuadricKernel<kD>>;
  return (e & kR) ? &shade_packet<QuadricKernel<kR>> : &shade_packet<QuadricKernel<0>>;
}

}  // namespace

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_quadric)

RELIEF_BUILTIN_PLUGIN(kReliefQuadricPlugin);
const PluginDescriptor kReliefQuadricPlugin = {
    kPluginAbiVersion,
    "relief_quadric",
    "relief mapping on per-vertex quadrics: curved silhouettes by discard, accurate or "
    "approximate distance, depth correction (Oliveira & Policarpo 2005)",
    kParams,
    std::size(kParams),
    kSlots,
    std::size(kSlots),
    kEffectDepthWrite | kEffectShadowPass | kEffectReceiveShadow | kEffectSilhouette,
    &select_quadric_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    &reads_texture,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
