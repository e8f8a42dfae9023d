// `pom`: parallax occlusion mapping, linear search then interpolation of the last two samples
// Tatarchuk, "Dynamic Parallax Occlusion Mapping with Approximate Soft Shadows", I3D 2006.
// The search of shaders_cpp/search.h inside the shared shell (plugins/relief_shell.h), with the
// step count mixed by view angle as for relief; the self-shadow ray is the marched one.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/pom.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kSteps, kMinSteps, kDepthScaleParam, kShadowStepsParam, kLodParam };
const ParamSpec kParams[] = {
    kLinearStepsSpec, kMinStepsSpec, kDepthScaleSpec, kShadowStepsSpec, kSearchLodSpec,
};

struct PomSearch : MarchedShadow<kShadowStepsParam> {
  static constexpr int kDepthScale = kDepthScaleParam;
  static constexpr int kLodParam = Param::kLodParam;
  static constexpr int kMaxMipSlot = kReliefMaxMipSlot;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>& V, const V2<F>& ds,
                             mask_t<F> active) {
    const float* p = ctx.material->params;
    return pom_search(depth, in.uv, ds, relief_step_count(V.z, p[kMinSteps], p[kSteps]), active);
  }
};

}  // namespace

ShadeFn select_pom(EffectMask e) {
  return select_relief_variant<PomSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_pom)

RELIEF_BUILTIN_PLUGIN(kPomPlugin);
const PluginDescriptor kPomPlugin = {
    kPluginAbiVersion,
    "pom",
    "parallax occlusion mapping: linear search + secant of the last two samples (Tatarchuk 2006)",
    kParams,
    std::size(kParams),
    kReliefSearchSlots,
    std::size(kReliefSearchSlots),
    kReliefShellEffects,
    &select_pom_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    &reads_max_mip_slot<kLodParam, kReliefMaxMipSlot>,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
