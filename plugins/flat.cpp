// `flat`: Lambert and Blinn-Phong over the interpolated normal and a base colour (texture or
// constant). The baseline every relief technique is compared against.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/flat.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/surface.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum FlatSlot { kBaseColorSlot = 0 };

const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec};

template <bool kReceive>
struct FlatKernel {
  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    V3<F> n = normalize(in.normal);
    if (!in.front_facing) n = -n;
    SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, in.uv, in, o.fetches, &o.alpha);
    const V3<F> v = to_eye(*ctx.frame, in.position);
    o.color = finish_surface(ctx, in, in.uv, sc, o.fetches, [&] {
      return shade_lights<kReceive>(ctx, in.position, n, n, v, sc, o.fetches);
    });
    o.hit_uv = in.uv;
    o.shading_normal = n;
    return o;
  }
};

ShadeFn select_flat(EffectMask e) {
  return (e & kEffectReceiveShadow) ? &shade_packet<FlatKernel<true>>
                                    : &shade_packet<FlatKernel<false>>;
}
DepthOutput depth_flat(EffectMask) {
  return DepthOutput::kNone;
}

}  // namespace

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_flat)

RELIEF_BUILTIN_PLUGIN(kFlatPlugin);
const PluginDescriptor kFlatPlugin = {
    kPluginAbiVersion,
    "flat",
    "Lambert and Blinn-Phong over the interpolated normal (no relief)",
    nullptr,
    0,
    kSlots,
    1,
    kEffectReceiveShadow,
    &select_flat_dispatch,
    &depth_flat,
    nullptr,
    nullptr,
    nullptr,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
