// `relaxed_cone`: relaxed cone stepping then binary search
// Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
// (section 18.4.2, listing 18-3, figure 18-10).
// The search of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h): `steps`
// relaxed cone steps with the relaxed cone map of slot 3 (baked from the depth map when absent)
// on the material's depth, then `binary_steps` halvings of [last outside sample, K] (the chapter
// halves from H, half-way to K: not a bracket on every lane); a lane the march left outside first
// takes `fallback_steps` linear steps (cone_finish). Self-shadow: the light ray, searched the same
// way without the halvings.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/relaxed_cone.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/cone_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kSteps, kBinarySteps, kDepthScaleParam, kShadowStepsParam, kFallbackStepsParam };
const ParamSpec kParams[] = {kConeStepsSpec, kConeBinaryStepsSpec, kDepthScaleSpec,
                             kConeShadowStepsSpec, kConeFallbackStepsSpec};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec, kDepthSlotSpec,
                                  kConeRelaxedSlotSpec};
constexpr ConeParamIndex kIndex = {kSteps, kBinarySteps, kDepthScaleParam, kShadowStepsParam,
                                   kFallbackStepsParam};
using RelaxedConeSearch = ConeFamilySearch<TextureCone, kIndex>;

}  // namespace

ShadeFn select_relaxed_cone(EffectMask e) {
  return select_relief_variant<RelaxedConeSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_relaxed_cone)

RELIEF_BUILTIN_PLUGIN(kRelaxedConePlugin);
const PluginDescriptor kRelaxedConePlugin =
    cone_plugin("relaxed_cone",
                "relaxed cone stepping + binary search (Policarpo & Oliveira 2007), bracket-safe: "
                "self-shadow, depth correction",
                kParams, kSlots, &select_relaxed_cone_dispatch);

}  // namespace relief
#endif  // HWY_ONCE
