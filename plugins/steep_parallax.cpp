// `steep_parallax`: steep parallax mapping, n depth planes at a constant LOD, self-shadow loop
// McGuire and McGuire, "Steep Parallax Mapping", I3D 2005 poster.
// The n-plane march of shaders_cpp/search.h inside the shared shell (plugins/relief_shell.h); the
// self-shadow ray starts one plane above the hit, as the poster's "Self-Shadowing" loop does.
// `shadow=depth` replaces the ray with the poster's "Fur and Grass" trick: self-shadowing
// approximated as darkening that grows with the hit's depth (shaders_cpp/shadow.h
// depth_darkening), for each light and for the indirect light, with no depth reads.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/steep_parallax.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kSteps, kDepthScaleParam, kShadowStepsParam, kLodParam, kShadowMode, kShadowStrength };
enum class ShadowMode { kRay = 0, kDepth = 1 };
const ParamSpec kParams[] = {
    {"steps", ParamType::kInt, 32.0f, 1.0f, 256.0f, nullptr, "depth planes"},
    kDepthScaleSpec,
    kShadowStepsSpec,
    kSearchLodSpec,
    {"shadow", ParamType::kEnum, 0.0f, 0.0f, 1.0f, "ray|depth",
     "self-shadow: ray (march toward each light) or depth (darkening that grows with depth, the "
     "poster's fur and grass trick; no depth reads)"},
    {"shadow_strength", ParamType::kFloat, 0.5f, 0.0f, 1.0f, nullptr,
     "shadow=depth: darkening at the deepest point (1 - strength x depth)"},
};

bool depth_shadow(const float* p) {
  return static_cast<ShadowMode>(static_cast<int>(p[kShadowMode])) == ShadowMode::kDepth;
}

struct SteepSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  static constexpr int kLodParam = Param::kLodParam;
  static constexpr int kMaxMipSlot = kReliefMaxMipSlot;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>& V, const V2<F>& ds,
                             mask_t<F> active) {
    return steep_parallax_search(depth, in.uv, ds, F(ctx.material->params[kSteps]), active);
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    const float* p = ctx.material->params;
    // below the tangent plane (lz <= 0) the light is blocked, as the ray's
    if (depth_shadow(p))
      return select(lz > F(0.0f), depth_darkening(hit.depth, p[kShadowStrength]), F(0.0f));
    const int steps = static_cast<int>(p[kShadowStepsParam]);
    return marched_shadow(depth, hit, dl, lz, steps, 0.01f + 1.0f / p[kSteps], lit, o);
  }
  template <class F>
  static F self_occlusion(const ShadeContext& ctx, const SearchHit<F>& hit) {
    const float* p = ctx.material->params;
    return depth_shadow(p) ? depth_darkening(hit.depth, p[kShadowStrength]) : F(1.0f);
  }
};

}  // namespace

ShadeFn select_steep(EffectMask e) {
  return select_relief_variant<SteepSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_steep)

RELIEF_BUILTIN_PLUGIN(kSteepParallaxPlugin);
const PluginDescriptor kSteepParallaxPlugin = {
    kPluginAbiVersion,
    "steep_parallax",
    "steep parallax: n depth planes, constant LOD, self-shadow (McGuire & McGuire 2005)",
    kParams,
    std::size(kParams),
    kReliefSearchSlots,
    std::size(kReliefSearchSlots),
    kReliefShellEffects,
    &select_steep_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    &reads_max_mip_slot<kLodParam, kReliefMaxMipSlot>,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
