// `cone_quad`: quad-directional cone stepping
// Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
// (figure 18-1c: four cone ratios per texel, one per direction), on Dummer's cone stepping (2006).
// The march of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h) with the
// quad-directional cone map of slot 3 (+u, -u, +v, -v; baked from the depth map when absent): each
// ray uses the wider of the two ratios of its quadrant; then cone_finish as `cone` (fallback linear
// steps for lanes left above the surface, `binary_steps` halvings). Self-shadow: likewise.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/cone_quad.cpp"
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
                                  kConeQuadSlotSpec};
constexpr ConeParamIndex kIndex = {kSteps, kBinaryStepsParam, kDepthScaleParam, kShadowStepsParam,
                                   kFallbackStepsParam};
using ConeQuadSearch = ConeFamilySearch<QuadTextureCone, kIndex>;

}  // namespace

ShadeFn select_cone_quad(EffectMask e) {
  return select_relief_variant<ConeQuadSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_cone_quad)

RELIEF_BUILTIN_PLUGIN(kConeQuadPlugin);
const PluginDescriptor kConeQuadPlugin = cone_plugin(
    "cone_quad",
    "quad-directional cone stepping (four ratios per texel, GPU Gems 3 ch. 18): self-shadow, "
    "depth correction",
    kParams, kSlots, &select_cone_quad_dispatch);

}  // namespace relief
#endif  // HWY_ONCE
