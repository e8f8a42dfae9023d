// `cone`: conservative cone stepping
// Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection Algorithm", 2006 (as
// summarised in Policarpo and Oliveira, GPU Gems 3 ch. 18, section 18.3).
// The march of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h): `steps` cone
// steps with the conservative cone map of slot 3 (baked from the depth map when the material has
// none); the hit is where the march stopped. Self-shadow: the light ray, cone-stepped the same way.
#include "plugins/builtin.h"
#include "plugins/cone_shell.h"

namespace relief {
namespace {

enum Param { kSteps, kDepthScaleParam, kShadowStepsParam };
const ParamSpec kParams[] = {kConeStepsSpec, kDepthScaleSpec, kConeShadowStepsSpec};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec, kDepthSlotSpec,
                                  kConeConservativeSlotSpec};

struct ConeSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>&, const V2<F>& ds,
                             mask_t<F> active) {
    TextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return {in.uv, F(0.0f), F(0.0f), F(0.0f)};
    return cone_search(depth, cone, in.uv, ds, static_cast<int>(ctx.material->params[kSteps]),
                       active);
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    TextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return F(1.0f);
    const int n = static_cast<int>(ctx.material->params[kShadowStepsParam]);
    return cone_light_visibility(hit, dl, lz, lit, o,
                                 [&](V2<F> uv, V2<F> dir, F t_max, mask_t<F> a) {
                                   return cone_search(depth, cone, uv, dir, n, a, t_max);
                                 });
  }
};

}  // namespace

extern const PluginDescriptor kConePlugin;
const PluginDescriptor kConePlugin = cone_plugin<ConeSearch>(
    "cone",
    "conservative cone stepping (Dummer 2006): cone map derived from depth, self-shadow, depth "
    "correction",
    kParams, kSlots);

}  // namespace relief
