// `cone_quad`: quad-directional cone stepping
// Policarpo and Oliveira, "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3 ch. 18, 2007
// (figure 18-1c: four cone ratios per texel, one per direction), on Dummer's cone stepping (2006).
// The march of shaders_cpp/cone.h inside the shared shell (plugins/relief_shell.h) with the
// quad-directional cone map of slot 3 (+u, -u, +v, -v; baked from the depth map when absent): each
// ray uses the wider of the two ratios of its quadrant. Self-shadow: the light ray, likewise.
#include "plugins/builtin.h"
#include "plugins/cone_shell.h"

namespace relief {
namespace {

enum Param { kSteps, kDepthScaleParam, kShadowStepsParam };
const ParamSpec kParams[] = {kConeStepsSpec, kDepthScaleSpec, kConeShadowStepsSpec};
const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec, kDepthSlotSpec,
                                  kConeQuadSlotSpec};

struct ConeQuadSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in,
                             const TextureDepth& depth, const V3<F>&, const V2<F>& ds,
                             mask_t<F> active) {
    QuadTextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return {in.uv, F(0.0f), F(0.0f), F(0.0f)};
    cone.aim(ds);
    return cone_search(depth, cone, in.uv, ds, static_cast<int>(ctx.material->params[kSteps]),
                       active);
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth& depth, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    QuadTextureCone cone;
    if (!make_cone_source(ctx, depth, cone)) return F(1.0f);
    const int n = static_cast<int>(ctx.material->params[kShadowStepsParam]);
    return cone_light_visibility(hit, dl, lz, lit, o,
                                 [&](V2<F> uv, V2<F> dir, F t_max, mask_t<F> a) {
                                   cone.aim(dir);
                                   return cone_search(depth, cone, uv, dir, n, a, t_max);
                                 });
  }
};

}  // namespace

extern const PluginDescriptor kConeQuadPlugin;
const PluginDescriptor kConeQuadPlugin = cone_plugin<ConeQuadSearch>(
    "cone_quad",
    "quad-directional cone stepping (four ratios per texel, GPU Gems 3 ch. 18): self-shadow, "
    "depth correction",
    kParams, kSlots);

}  // namespace relief
