// `cone`: conservative cone stepping
// Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm", 2006 (as
// summarised in Policarpo and Oliveira, GPU Gems 3 ch. 18, section 18.3).
// The search of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h): `steps` cone
// steps with the conservative cone map of slot 3 (bilinear-safe, baked from the depth map when the
// material has none), then cone_finish: lanes still above the surface take `fallback_steps`
// linear steps, and `binary_steps` halvings refine the last bracket, so the hit lies on the
// surface (Dummer's march alone stops above it when the steps run out). Self-shadow: the light
// ray, searched the same way without the halvings.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/cone.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/cone_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kSteps, kDepthScaleParam, kShadowStepsParam, kBinaryStepsParam, kFallbackStepsParam };
const ParamSpec kParams[] = {kConeStepsSpec, kDepthScaleSpec, kConeShadowStepsSpec,
                             kConeBinaryStepsSpec, kConeFallbackStepsSpec};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec, kDepthSlotSpec,
                                  kConeConservativeSlotSpec};
constexpr ConeParamIndex kIndex = {kSteps, kBinaryStepsParam, kDepthScaleParam, kShadowStepsParam,
                                   kFallbackStepsParam};
using ConeSearch = ConeFamilySearch<TextureCone, kIndex>;

}  // namespace

ShadeFn select_cone(EffectMask e) {
  return select_relief_variant<ConeSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_cone)

RELIEF_BUILTIN_PLUGIN(kConePlugin);
const PluginDescriptor kConePlugin = cone_plugin(
    "cone",
    "conservative cone stepping (Dummer 2006): cone map derived from depth, self-shadow, depth "
    "correction",
    kParams, kSlots, &select_cone_dispatch);

}  // namespace relief
#endif  // HWY_ONCE
