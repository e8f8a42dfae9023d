// `flat`: Lambert and Blinn-Phong over the interpolated normal and a base colour (texture or
// constant). The baseline every relief technique is compared against.
#include "plugins/builtin.h"
#include "plugins/shading.h"
#include "shaders_cpp/lighting.h"
#include "shaders_cpp/shadow_map.h"

namespace relief {
namespace {

enum FlatSlot { kBaseColorSlot = 0 };

const TextureSlotSpec kSlots[] = {
    {"base_color", false, "sRGB base colour, multiplied by the material's base colour"},
};

template <bool kReceive> struct FlatKernel {
  template <class F> static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    V3<F> n = normalize(in.normal);
    if (!in.front_facing) n = -n;
    V3<F> albedo(glm::vec3(m.base_color));
    if (const Texture* t = m.textures[kBaseColorSlot]) {
      const V4<F> c = texture_grad(*t, m.samplers[kBaseColorSlot], in.uv, in.duv_dx, in.duv_dy);
      albedo = albedo * c.xyz();
      o.fetches = F(1.0f);
    }
    const V3<F> v = normalize(V3<F>(ctx.frame->eye) - in.position);
    if constexpr (kReceive)
      o.color = blinn_phong(*ctx.frame, m, in.position, n, v, albedo,
                            ShadowMapReceiver<F>{*ctx.frame, in.position, n, o.fetches});
    else
      o.color = blinn_phong(*ctx.frame, m, in.position, n, v, albedo, NoShadow<F>());
    o.alpha = F(m.base_color.a);
    o.hit_uv = in.uv;
    o.shading_normal = n;
    return o;
  }
};

ShadeFn select_flat(EffectMask e) {
  return (e & kEffectReceiveShadow) ? &shade_packet_simd<FlatKernel<true>>
                                    : &shade_packet_simd<FlatKernel<false>>;
}
DepthOutput depth_flat(EffectMask) { return DepthOutput::kNone; }

}  // namespace

const PluginDescriptor kFlatPlugin = {
    kPluginAbiVersion, "flat", "Lambert and Blinn-Phong over the interpolated normal (no relief)",
    nullptr, 0, kSlots, 1, kEffectReceiveShadow, &select_flat, &depth_flat, nullptr, nullptr,
};

}  // namespace relief
