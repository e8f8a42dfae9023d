// `relief`: relief mapping, linear then binary search, step count by view angle
// Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005.
// Binds the kernels of shaders_cpp/{ray,search,shadow}.h to the packet ABI following
// plugins/normal.cpp: per fragment, the tangent frame is re-orthonormalised, the view ray is
// followed into the depth map (constant LOD per quad), the hit is shaded with the normal map and
// base colour read at the hit uv, optionally self-shadowed and depth-corrected.
#include <cmath>

#include "plugins/builtin.h"
#include "plugins/shading.h"
#include "shaders_cpp/lighting.h"
#include "shaders_cpp/ray.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/shadow.h"

namespace relief {
namespace {

enum Slot { kBaseColorSlot = 0, kNormalSlot = 1, kDepthSlot = 2 };

const TextureSlotSpec kSlots[] = {
    {"base_color", false, "sRGB base colour, multiplied by the material's base colour"},
    {"normal", false, "tangent-space normal map (x along +u, y along +v, z out), linear RGB"},
    {"depth", true, "depth map: 0 at the reference surface, 1 deepest, linear"},
};

enum Param { kSteps, kBinarySteps, kMinSteps, kDepthScale, kShadowSteps };
const ParamSpec kParams[] = {
    {"steps", ParamType::kInt, 32.0f, 1.0f, 256.0f, nullptr, "linear search steps at grazing angles"},
    {"binary_steps", ParamType::kInt, 8.0f, 0.0f, 32.0f, nullptr, "binary search halvings after the linear search"},
    {"min_steps", ParamType::kInt, 8.0f, 1.0f, 256.0f, nullptr, "linear steps facing the surface (steps at grazing angles; mixed by |V.z|)"},
    {"depth_scale", ParamType::kFloat, 0.05f, 0.0f, 1.0f, nullptr, "relief height in uv units"},
    {"shadow_steps", ParamType::kInt, 32.0f, 1.0f, 256.0f, nullptr, "self-shadow ray steps over the full depth (self_shadow effect)"},
};
constexpr int kNumParams = sizeof(kParams) / sizeof(kParams[0]);

// Lanes of this group that are real, covered fragments.
template <class F> mask_t<F> covered_lanes(const FragIn<F>& in) {
  mask_t<F> m = false_mask<F>();
  for (int i = 0; i < lane_width<F>; ++i) {
    const int ln = in.lane0 + i;
    if ((ln >> 2) < in.packet->num_quads && in.packet->lane_covered(ln)) set_lane(m, i, true);
  }
  return m;
}

template <EffectMask kEffects> struct Kernel {
  static constexpr bool kShadow = (kEffects & kEffectSelfShadow) != 0;
  static constexpr bool kDepth = (kEffects & (kEffectDepthWrite | kEffectShadowPass)) != 0;
  static constexpr bool kShadowPass = (kEffects & kEffectShadowPass) != 0;

  template <class F> static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    V3<F> geo_n = in.normal;
    if (!in.front_facing) geo_n = -geo_n;
    const TangentFrame<F> tf = make_tangent_frame(geo_n, in.tangent, in.tangent_sign);
    const V3<F> w = world_view_dir(in.position, ctx.frame->eye, ctx.frame->orthographic,
                                   ctx.frame->view_dir, -tf.n);
    const V3<F> V = tf.to_tangent(w);
    const F depth_scale(m.params[kDepthScale]);
    const V2<F> ds = texture_step(V, depth_scale);
    const mask_t<F> active = covered_lanes(in);
    const Texture* dtex = m.textures[kDepthSlot];
    TextureDepth depth;
    depth.texture = dtex;
    depth.sampler = &m.samplers[kDepthSlot];
    SearchHit<F> hit{in.uv, F(0.0f), F(0.0f), F(0.0f)};
    if (dtex) {
      // constant LOD per quad, outside the loops
      for (int i = 0; i < lane_width<F>; ++i)
        depth.lod[i] = compute_lod(*dtex, {lane(in.duv_dx.x, i), lane(in.duv_dx.y, i)},
                                   {lane(in.duv_dy.x, i), lane(in.duv_dy.y, i)});
      const F n = relief_step_count(V.z, m.params[kMinSteps], m.params[kSteps]);
      hit = relief_search(depth, in.uv, ds, n, static_cast<int>(m.params[kBinarySteps]), active);
    }
    o.hit_uv = hit.uv;
    o.hit_depth = hit.depth;
    o.steps = hit.steps;
    o.fetches = hit.fetches;
    if constexpr (kDepth) {
      // world units per uv along T and B (scene/mesh_prep.cpp tile scale)
      const F world_height = depth_scale * (in.tile_scale.x + in.tile_scale.y) * F(0.5f);
      const V3<F> p = hit_world_position(in.position, w, V.z, hit.depth, world_height);
      o.depth = vmin(reversed_z_depth(ctx.frame->view_proj, p, in.frag_z), in.frag_z);
    }
    if constexpr (kShadowPass) {
      return o;
    } else {
      V3<F> n = tf.n;
      if (const Texture* t = m.textures[kNormalSlot]) {
        const V4<F> c = texture_grad(*t, m.samplers[kNormalSlot], hit.uv, in.duv_dx, in.duv_dy);
        n = normalize(tf.to_world(V3<F>(c.x * F(2.0f) - F(1.0f), c.y * F(2.0f) - F(1.0f),
                                        c.z * F(2.0f) - F(1.0f))));
        o.fetches += F(1.0f);
      }
      V3<F> albedo(glm::vec3(m.base_color));
      if (const Texture* t = m.textures[kBaseColorSlot]) {
        const V4<F> c = texture_grad(*t, m.samplers[kBaseColorSlot], hit.uv, in.duv_dx, in.duv_dy);
        albedo = albedo * c.xyz();
        o.fetches += F(1.0f);
      }
      const V3<F> v = -w;
      // lighting at the displaced point
      const V3<F> pos = hit_world_position(
          in.position, w, V.z, hit.depth,
          depth_scale * (in.tile_scale.x + in.tile_scale.y) * F(0.5f));
      auto visibility = [&](int, V3<F> l, mask_t<F> lit) -> F {
        if constexpr (kShadow) {
          if (!dtex) return F(1.0f);
          const V3<F> lt = tf.to_tangent(l);
          const V2<F> dl = light_step(lt, depth_scale);
          const int sn = static_cast<int>(m.params[kShadowSteps]);
          const ShadowResult<F> sr =
              self_shadow(depth, hit.uv, hit.depth, dl, lt.z, sn, 0.01f, active & lit);
          o.shadow_steps += sr.steps;
          o.fetches += sr.fetches;
          return sr.visibility;
        } else {
          return F(1.0f);
        }
      };
      o.color = blinn_phong(*ctx.frame, m, pos, n, v, albedo, visibility);
      o.alpha = F(m.base_color.a);
      o.shading_normal = n;
      return o;
    }
  }
};

template <EffectMask kE> constexpr ShadeFn fn() { return &shade_packet<Kernel<kE>>; }

ShadeFn select_relief(EffectMask e) {
  const bool s = e & kEffectSelfShadow;
  if (e & kEffectShadowPass) return fn<kEffectShadowPass>();
  if (e & kEffectDepthWrite)
    return s ? fn<kEffectSelfShadow | kEffectDepthWrite>() : fn<kEffectDepthWrite>();
  return s ? fn<kEffectSelfShadow>() : fn<0>();
}
DepthOutput depth_relief(EffectMask e) {
  return (e & (kEffectDepthWrite | kEffectShadowPass)) ? DepthOutput::kFarther : DepthOutput::kNone;
}

}  // namespace

// Declared here as well as in the builtin list so the definition has external linkage.
extern const PluginDescriptor kReliefPlugin;
const PluginDescriptor kReliefPlugin = {
    kPluginAbiVersion, "relief", "relief mapping: linear + binary search, self-shadow, depth correction (Policarpo et al. 2005)",
    kParams, kNumParams, kSlots, 3, kEffectSelfShadow | kEffectDepthWrite | kEffectShadowPass,
    &select_relief, &depth_relief, nullptr, nullptr,
};

}  // namespace relief
