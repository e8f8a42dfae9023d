// `exact`: the exact first hit on the bilinear height field: the accuracy reference
// Tevs, Ihrke and Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field
// Rendering", I3D 2008 (max-mip traversal; per-cell closed-form patch solve in
// shaders_cpp/exact_trace.cpp). The max-mip traversal of shaders_cpp/exact_trace.h inside the
// shared shell (plugins/relief_shell.h); the self-shadow answer is exact too. The max-mip is the
// plugin's per-material state.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/exact.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"
#include "shaders_cpp/exact_trace.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum Param { kDepthScaleParam };
const ParamSpec kParams[] = {kDepthScaleSpec};

struct ExactSearch {
  static constexpr int kDepthScale = kDepthScaleParam;
  static constexpr bool kSamplesDepthMap = false;  // the max-mip in ctx.state answers both rays
  template <class F>
  static SearchHit<F> search(const ShadeContext& ctx, const FragIn<F>& in, const TextureDepth&,
                             const V3<F>&, const V2<F>& ds, mask_t<F> active) {
    if (const HeightField* hf = static_cast<const HeightField*>(ctx.state))
      return exact_search(*hf, in.uv, ds, active);
    return {in.uv, F(0.0f), F(0.0f), F(0.0f)};
  }
  template <class F>
  static F shadow(const ShadeContext& ctx, const TextureDepth&, const SearchHit<F>& hit,
                  const V2<F>& dl, const F& lz, mask_t<F> lit, ShadeOut<F>& o) {
    const HeightField* hf = static_cast<const HeightField*>(ctx.state);
    if (!hf) return F(1.0f);
    F steps;
    const F vis = exact_shadow(*hf, hit.uv, hit.depth, dl, lz, 1e-3f, lit, &steps);
    o.shadow_steps += steps;
    return vis;
  }
};

// The max-mip of the material's depth texture (level 0, the sampler's wraps), built once.
void* create_exact(const MaterialUniforms& m) {
  const Texture* t = m.textures[kDepthSlot];
  if (!t || t->empty()) return nullptr;
  return new HeightField(HeightField::from_texture(*t, m.samplers[kDepthSlot]));
}
void destroy_exact(void* s) {
  delete static_cast<HeightField*>(s);
}

}  // namespace

ShadeFn select_exact(EffectMask e) {
  return select_relief_variant<ExactSearch>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_exact)

RELIEF_BUILTIN_PLUGIN(kExactPlugin);
const PluginDescriptor kExactPlugin = {
    kPluginAbiVersion,
    "exact",
    "exact first hit on the bilinear height field (max-mip traversal + patch solve): the reference",
    kParams,
    std::size(kParams),
    kReliefSlots,
    std::size(kReliefSlots),
    kReliefShellEffects,
    &select_exact_dispatch,
    &relief_depth_output,
    &create_exact,
    &destroy_exact,
    nullptr,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
