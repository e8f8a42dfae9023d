// `parallax`: parallax mapping, one offset read at the fragment (Kaneko et al. 2001), optional
// offset limiting Kaneko et al., "Detailed shape representation with parallax mapping", ICAT 2001;
// Welsh, "Parallax mapping with offset limiting", 2004. One depth read and one offset inside the
// shared shell (plugins/relief_shell.h); the self-shadow ray is the marched one with a larger start
// offset, since the offset point is only approximate.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/parallax.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kDepthScaleParam, kOffsetLimiting, kShadowStepsParam };
const ParamSpec kParams[] = {
    kDepthScaleSpec,
    {"offset_limiting", ParamType::kBool, 1.0f, 0.0f, 1.0f, nullptr,
     "drop the 1 / V.z of the offset (Welsh 2004)"},
    kShadowStepsSpec,
};

struct ParallaxSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>& V, const V2<F>& ds,
                             mask_t<F> active) {
    const bool limit = ctx.material->params[kOffsetLimiting] != 0.0f;
    return parallax_offset(depth, in.uv, ds, V.z, limit, active);
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    const int steps = static_cast<int>(ctx.material->params[kShadowStepsParam]);
    return marched_shadow(depth, hit, dl, lz, steps, 0.05f, lit, o);
  }
};

}  // namespace

ShadeFn select_parallax(EffectMask e) {
  return select_relief_variant<ParallaxSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_parallax)

RELIEF_BUILTIN_PLUGIN(kParallaxPlugin);
const PluginDescriptor kParallaxPlugin = {
    kPluginAbiVersion,
    "parallax",
    "parallax mapping, one offset, optional offset limiting (Kaneko 2001; Welsh 2004)",
    kParams,
    std::size(kParams),
    kReliefSlots,
    std::size(kReliefSlots),
    kReliefShellEffects,
    &select_parallax_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    nullptr,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
