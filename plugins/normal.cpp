// `normal`: tangent-space normal mapping (Blinn 1978, "Simulation of wrinkled surfaces") with
// Blinn-Phong lighting: the surface keeps its polygonal position, only the normal follows the map.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/normal.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/surface.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

enum NormalSlot { kBaseColorSlot = 0, kNormalSlot = 1 };

const TextureSlotSpec kSlots[] = {kBaseColorSlotSpec, kNormalSlotSpec};

const ParamSpec kParams[] = {
    {"normal_strength", ParamType::kFloat, 1.0f, 0.0f, 8.0f, nullptr,
     "scales the map's x and y before renormalising (0 = flat)"},
};

template <bool kReceive>
struct NormalKernel {
  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    const TangentFrame<F> tf = fragment_frame(in);
    const V3<F> n = sample_normal_map(m, kNormalSlot, tf, in.uv, in, F(m.params[0]), o.fetches);
    SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, in.uv, in, o.fetches, &o.alpha);
    const V3<F> v = to_eye(*ctx.frame, in.position);
    // shadow maps compare against the polygon's plane (tf.n), which is where the point is
    o.color = finish_surface(ctx, in, in.uv, sc, o.fetches, [&] {
      return shade_lights<kReceive>(ctx, in.position, n, tf.n, v, sc, o.fetches);
    });
    o.hit_uv = in.uv;
    o.shading_normal = n;
    return o;
  }
};

ShadeFn select_normal(EffectMask e) {
  return (e & kEffectReceiveShadow) ? &shade_packet<NormalKernel<true>>
                                    : &shade_packet<NormalKernel<false>>;
}
DepthOutput depth_normal(EffectMask) {
  return DepthOutput::kNone;
}

}  // namespace

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_normal)

RELIEF_BUILTIN_PLUGIN(kNormalPlugin);
const PluginDescriptor kNormalPlugin = {
    kPluginAbiVersion,
    "normal",
    "tangent-space normal mapping, no parallax (Blinn 1978)",
    kParams,
    1,
    kSlots,
    2,
    kEffectReceiveShadow,
    &select_normal_dispatch,
    &depth_normal,
    nullptr,
    nullptr,
    nullptr,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
