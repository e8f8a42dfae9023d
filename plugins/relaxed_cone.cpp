// `relaxed_cone`: relaxed cone stepping then binary search
// Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
// (section 18.4.2, listing 18-3, figure 18-10).
// The search of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h): `steps`
// relaxed cone steps with the relaxed cone map of slot 3 (baked from the depth map when absent),
// then `binary_steps` halvings of the segment from H (half-way) to K (where the march stopped).
// Self-shadow: the light ray, relaxed-cone marched the same way.
#include "plugins/builtin.h"
#include "plugins/cone_shell.h"

namespace relief {
namespace {

enum Param { kSteps, kBinarySteps, kDepthScaleParam, kShadowStepsParam };
const ParamSpec kParams[] = {
    kConeStepsSpec,
    {"binary_steps", ParamType::kInt, 6.0f, 0.0f, 32.0f, nullptr,
     "binary search halvings from H to K (chapter: 6)"},
    kDepthScaleSpec,
    kConeShadowStepsSpec,
};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec, kDepthSlotSpec,
                                  kConeRelaxedSlotSpec};

struct RelaxedConeSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>&, const V2<F>& ds,
                             mask_t<F> active) {
    TextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return {in.uv, F(0.0f), F(0.0f), F(0.0f)};
    const float* p = ctx.material->params;
    return relaxed_cone_search(nearest_depth(depth), depth, cone, in.uv, ds,
                               static_cast<int>(p[kSteps]), static_cast<int>(p[kBinarySteps]),
                               active);
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    TextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return F(1.0f);
    // the march on the material's depth decides (stopped before the point: shadowed)
    const int n = static_cast<int>(ctx.material->params[kShadowStepsParam]);
    return cone_light_visibility(hit, dl, lz, lit, o,
                                 [&](V2<F> uv, V2<F> dir, F t_max, mask_t<F> a) {
                                   return cone_march(depth, cone, uv, dir, n, t_max, a);
                                 });
  }
};

}  // namespace

extern const PluginDescriptor kRelaxedConePlugin;
const PluginDescriptor kRelaxedConePlugin = cone_plugin<RelaxedConeSearch>(
    "relaxed_cone",
    "relaxed cone stepping + binary search H..K (Policarpo & Oliveira 2007): self-shadow, depth "
    "correction",
    kParams, kSlots);

}  // namespace relief
