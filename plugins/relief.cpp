// `relief`: relief mapping, linear then binary search, step count by view angle
// Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D
// 2005. The search of shaders_cpp/search.h inside the shared shell (plugins/relief_shell.h): the
// linear step count is mixed between min_steps and steps by the view angle (the paper's
// shading-model-3 note), then binary_steps halvings; the self-shadow ray is the marched one of
// figure 10.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/relief.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

using namespace relief_schema;

// relief_schema's parameters and the search's `lod` (relief_dual keeps the schema without it).
constexpr int kLodParam = static_cast<int>(std::size(relief_schema::kParams));
const ParamSpec kReliefParams[] = {
    kParams[kSteps],           kParams[kBinarySteps],      kParams[kMinSteps],
    kParams[kDepthScaleParam], kParams[kShadowStepsParam], kSearchLodSpec};
static_assert(std::size(kReliefParams) == kLodParam + 1);

struct ReliefSearch : MarchedShadow<kShadowStepsParam> {
  static constexpr int kDepthScale = kDepthScaleParam;
  static constexpr int kLodParam = HWY_NAMESPACE::kLodParam;
  static constexpr int kMaxMipSlot = kReliefMaxMipSlot;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>& V, const V2<F>& ds,
                             mask_t<F> active) {
    const float* p = ctx.material->params;
    const F n = relief_step_count(V.z, p[kMinSteps], p[kSteps]);
    return relief_search(depth, in.uv, ds, n, static_cast<int>(p[kBinarySteps]), active);
  }
};

}  // namespace

ShadeFn select_relief(EffectMask e) {
  return select_relief_variant<ReliefSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_relief)

RELIEF_BUILTIN_PLUGIN(kReliefPlugin);
const PluginDescriptor kReliefPlugin = {
    kPluginAbiVersion,
    "relief",
    "relief mapping: linear + binary search, self-shadow, depth correction (Policarpo et al. 2005)",
    kReliefParams,
    std::size(kReliefParams),
    kReliefSearchSlots,
    std::size(kReliefSearchSlots),
    kReliefShellEffects,
    &select_relief_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    &reads_max_mip_slot<kLodParam, kReliefMaxMipSlot>,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
