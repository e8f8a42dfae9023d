// `cone_quad`: quad-directional cone stepping
// Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
// (figure 18-1c: four cone ratios per texel, one per direction), on Dummer's cone stepping (2006).
// The march of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h) with the
// quad-directional cone map of slot 3 (+u, -u, +v, -v; baked from the depth map when absent): each
// ray uses the wider of the two ratios of its quadrant; then cone_finish as `cone` (fallback linear
// steps for lanes left above the surface, `binary_steps` halvings). Self-shadow: likewise.
#include "plugins/builtin.h"
#include "plugins/cone_shell.h"

namespace relief {
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

extern const PluginDescriptor kConeQuadPlugin;
const PluginDescriptor kConeQuadPlugin = cone_plugin<ConeQuadSearch>(
    "cone_quad",
    "quad-directional cone stepping (four ratios per texel, GPU Gems 3 ch. 18): self-shadow, "
    "depth correction",
    kParams, kSlots);

}  // namespace relief
