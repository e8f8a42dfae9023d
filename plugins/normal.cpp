// `normal`: tangent-space normal mapping (Blinn 1978, "Simulation of wrinkled surfaces") with
// Blinn-Phong lighting: the surface keeps its polygonal position, only the normal follows the map.
#include "plugins/builtin.h"
#include "plugins/shading.h"
#include "shaders_cpp/lighting.h"
#include "shaders_cpp/shadow_map.h"

namespace relief {
namespace {

enum NormalSlot { kBaseColorSlot = 0, kNormalSlot = 1 };

const TextureSlotSpec kSlots[] = {
    {"base_color", false, "sRGB base colour, multiplied by the material's base colour"},
    {"normal", false, "tangent-space normal map (x along +u, y along +v, z out), linear RGB"},
};

const ParamSpec kParams[] = {
    {"normal_strength", ParamType::kFloat, 1.0f, 0.0f, 8.0f, nullptr,
     "scales the map's x and y before renormalising (0 = flat)"},
};

template <bool kReceive> struct NormalKernel {
  template <class F> static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    V3<F> geo_n = in.normal;
    if (!in.front_facing) geo_n = -geo_n;
    const TangentFrame<F> tf = make_tangent_frame(geo_n, in.tangent, in.tangent_sign);
    V3<F> n = tf.n;
    if (const Texture* t = m.textures[kNormalSlot]) {
      const V4<F> c = texture_grad(*t, m.samplers[kNormalSlot], in.uv, in.duv_dx, in.duv_dy);
      const F strength(m.params[0]);
      const V3<F> nt(
          (c.x * F(2.0f) - F(1.0f)) * strength, (c.y * F(2.0f) - F(1.0f)) * strength,
          c.z * F(2.0f) - F(1.0f));
      n = normalize(tf.to_world(nt));
      o.fetches += F(1.0f);
    }
    V3<F> albedo(glm::vec3(m.base_color));
    if (const Texture* t = m.textures[kBaseColorSlot]) {
      const V4<F> c = texture_grad(*t, m.samplers[kBaseColorSlot], in.uv, in.duv_dx, in.duv_dy);
      albedo = albedo * c.xyz();
      o.fetches += F(1.0f);
    }
    const V3<F> v = normalize(V3<F>(ctx.frame->eye) - in.position);
    // shadow maps compare against the polygon's plane (tf.n), which is where the point is
    if constexpr (kReceive)
      o.color = blinn_phong(*ctx.frame, m, in.position, n, v, albedo,
                            ShadowMapReceiver<F>{*ctx.frame, in.position, tf.n, o.fetches});
    else
      o.color = blinn_phong(*ctx.frame, m, in.position, n, v, albedo, NoShadow<F>());
    o.alpha = F(m.base_color.a);
    o.hit_uv = in.uv;
    o.shading_normal = n;
    return o;
  }
};

ShadeFn select_normal(EffectMask e) {
  return (e & kEffectReceiveShadow) ? &shade_packet_simd<NormalKernel<true>>
                                    : &shade_packet_simd<NormalKernel<false>>;
}
DepthOutput depth_normal(EffectMask) { return DepthOutput::kNone; }

}  // namespace

const PluginDescriptor kNormalPlugin = {
    kPluginAbiVersion, "normal", "tangent-space normal mapping, no parallax (Blinn 1978)",
    kParams, 1, kSlots, 2, kEffectReceiveShadow, &select_normal, &depth_normal, nullptr, nullptr,
};

}  // namespace relief
