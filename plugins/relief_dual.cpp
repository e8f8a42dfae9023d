// `relief_dual`: dual-depth relief textures. Policarpo, Oliveira and Comba, "Real-Time Relief
// Mapping on Arbitrary Polygonal Surfaces", I3D 2005, section 3.1: a front and a back depth layer
// over the polygon (depth 0 at the polygon, 1 deepest); a ray point at depth t is inside the
// object when front <= t <= back. Linear then binary search over both layers
// (shaders_cpp/dual_depth.h); rays that pass through without entering the object are discarded,
// so one quad draws a whole object (an impostor) with its own outline. Depth correction writes
// the hit's depth; the self-shadow ray is blocked where it runs inside the object; the normal is
// the front layer's (slot `normal`) or, where the hit lies nearer the back layer and a
// `normal_back` map is bound, the back layer's. Without `depth_back` the back layer reads 1 and
// the technique is `relief` with misses discarded. Both depth maps share one size (the back
// layer is sampled at the front layer's LOD).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/relief_dual.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"
#include "shaders_cpp/dual_depth.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

using namespace relief_schema;  // relief's schema

enum DualSlot { kBackDepthSlot = 3, kBackNormalSlot = 4 };
const TextureSlotSpec kDualSlots[] = {
    kBaseColorSlotSpec,
    kNormalSlotSpec,
    {"depth", true,
     "front depth layer: where the object starts (0 at the polygon, 1 deepest); "
     "1 where the object is absent"},
    {"depth_back", false,
     "back depth layer: where the object ends; 0 where it is absent "
     "(absent map: 1 everywhere)"},
    {"normal_back", false, "tangent-space normal map of the back layer (outward normals)"},
};

// The back layer when no map is bound: the object reaches depth 1 everywhere.
struct FullDepth {
  static constexpr float kFetches = 0.0f;  // a constant: no texture read
  float operator()(int, float, float) const { return 1.0f; }
};

template <EffectMask kEffects>
struct DualKernel {
  static constexpr bool kShadow = (kEffects & kEffectSelfShadow) != 0;
  static constexpr bool kDepth = (kEffects & (kEffectDepthWrite | kEffectShadowPass)) != 0;
  static constexpr bool kShadowPass = (kEffects & kEffectShadowPass) != 0;
  static constexpr bool kReceive = (kEffects & kEffectReceiveShadow) != 0;

  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    const TextureDepth front = material_depth(m, in);
    if (const Texture* back_tex = m.textures[kBackDepthSlot]) {
      TextureDepth back = front;
      back.texture = back_tex;
      back.sampler = &m.samplers[kBackDepthSlot];
      return shade_with(ctx, in, front, back);
    }
    return shade_with(ctx, in, front, FullDepth{});
  }

  template <class F, class Back>
  static ShadeOut<F> shade_with(const ShadeContext& ctx, const FragIn<F>& in,
                                const TextureDepth& front, const Back& back) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    const ShellView<F> view = shell_view(ctx, in);
    const TangentFrame<F>& tf = view.tf;
    const V3<F>&w = view.w, &V = view.V;
    const F depth_scale(m.params[kDepthScaleParam]);
    const V2<F> ds = texture_step(V, depth_scale);
    const mask_t<F> active = covered_lanes(in);
    SearchHit<F> hit{in.uv, F(0.0f), F(0.0f), F(0.0f)};
    if (front.texture) {
      const float* p = m.params;
      const F n = relief_step_count(V.z, p[kMinSteps], p[kSteps]);
      mask_t<F> miss = false_mask<F>();
      hit = dual_depth_search(front, back, in.uv, ds, n, static_cast<int>(p[kBinarySteps]), active,
                              miss);
      o.discard = miss;
    }
    const V3<F> pos = record_hit(in, view, depth_scale, hit, o);
    if constexpr (kDepth) o.depth = corrected_depth(ctx, in, pos);
    if constexpr (kShadowPass) {
      // MASK casters cut their shadow where the base colour at the hit is below the cutoff
      if (m.alpha_mode == AlphaMode::kMask)
        o.alpha = sample_alpha(m, kBaseColorSlot, hit.uv, in, o.fetches);
      return o;
    } else {
      V3<F> n = sample_normal_map(m, kNormalSlot, tf, hit.uv, in, F(1.0f), o.fetches);
      if (m.textures[kBackNormalSlot] && front.texture) {
        // the hit's nearer layer: back where t is closer to the back depth than to the front
        F fetches(0.0f);
        const F f = sample_depth(front, hit.uv, active), b = sample_depth(back, hit.uv, active);
        const mask_t<F> on_back = active & (vabs(b - hit.depth) < vabs(hit.depth - f));
        if (any(on_back)) {
          const V3<F> nb = sample_normal_map(m, kBackNormalSlot, tf, hit.uv, in, F(1.0f), fetches);
          n = select(on_back, nb, n);
        }
        o.fetches +=
            F(read_cost<TextureDepth>() + read_cost<Back>()) + select(on_back, F(1.0f), F(0.0f));
      }
      SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, hit.uv, in, o.fetches, &o.alpha);
      auto visibility = [&](int i, V3<F> l, mask_t<F> lit) -> F {
        F vis(1.0f);
        if constexpr (kShadow) {
          if (front.texture) {
            const V3<F> lt = tf.to_tangent(l);
            const ShadowResult<F> sr = dual_depth_shadow(
                front, back, hit.uv, hit.depth, light_step(lt, depth_scale), lt.z,
                static_cast<int>(m.params[kShadowStepsParam]), 0.01f, active & lit);
            vis = sr.visibility;
            o.shadow_steps += sr.steps;
            o.fetches += sr.fetches;
          }
        }
        if constexpr (kReceive) {
          if (const ShadowMapView* sm = ctx.frame->lights[i].shadow)
            vis = vis *
                  shadow_map_visibility(*sm, pos, n, l, active & lit & (vis > F(0.0f)), o.fetches);
        }
        return vis;
      };
      o.color = finish_surface(ctx, in, hit.uv, sc, o.fetches, [&] {
        return shade_direct(*ctx.frame, m, pos, n, -w, sc, visibility);
      });
      o.shading_normal = n;
      return o;
    }
  }
};

template <EffectMask kR>
ShadeFn select_lit_dual(EffectMask e) {
  constexpr EffectMask kS = kEffectSelfShadow, kD = kEffectDepthWrite;
  if (e & kD)
    return (e & kS) ? &shade_packet<DualKernel<kS | kD | kR>> : &shade_packet<DualKernel<kD | kR>>;
  return (e & kS) ? &shade_packet<DualKernel<kS | kR>> : &shade_packet<DualKernel<kR>>;
}

ShadeFn select_dual(EffectMask e) {
  if (e & kEffectShadowPass) return &shade_packet<DualKernel<kEffectShadowPass>>;
  return (e & kEffectReceiveShadow) ? select_lit_dual<kEffectReceiveShadow>(e)
                                    : select_lit_dual<0>(e);
}

}  // namespace

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

RELIEF_SELECT_FOR_EVERY_TARGET(select_dual)

RELIEF_BUILTIN_PLUGIN(kReliefDualPlugin);
const PluginDescriptor kReliefDualPlugin = {
    kPluginAbiVersion,
    "relief_dual",
    "dual-depth relief textures: front and back layers, linear + binary search, misses "
    "discarded, self-shadow, depth correction (Policarpo et al. 2005, section 3.1)",
    kParams,
    std::size(kParams),
    kDualSlots,
    std::size(kDualSlots),
    (kReliefShellEffects & ~kEffectHeightAo) | kEffectSilhouette,  // no height-field AO
    &select_dual_dispatch,
    &relief_depth_output,
    nullptr,
    nullptr,
    nullptr,
    nullptr,  // layers
};

}  // namespace relief
#endif  // HWY_ONCE
