// `shells`: the shell method, the comparison technique for steep-parallax fur (McGuire and
// McGuire 2005, "Related work"). Lengyel, Praun, Finkelstein and Hoppe, "Real-time fur over
// arbitrary surfaces", I3D 2001: N offset copies of the surface along the normal, each alpha-tested
// against the same height field and drawn in order. The copies are geometry, made by the prepare
// stage from the `layers` hook (render/prepare.cpp): shell i of N lies at height fraction h = i/N,
// (1 - h) relief heights below the polygon (the level of the tallest tips, depth 0), outermost
// first, and carries (i, N) in varying::kQuadric (shells never read quadric coefficients). A
// texel is opaque on shell i when its height 1 - depth reaches h; shell 0, the base, is opaque
// everywhere. The planner alpha-tests the material (MASK), so the depth test keeps the outermost
// opaque shell of every pixel. Shading uses the fragment's own uv and world position: the shell
// is the surface it shows. Self-shadow is Lengyel et al.'s approximation, which the steep parallax
// paper borrows: light falls off with depth by 1 - shadow_strength * (1 - h) (shaders_cpp/shadow.h
// depth_darkening, as steep parallax's shadow=depth), and a light below the tangent plane is
// blocked.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "plugins/shells.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "plugins/builtin_plugins.h"
#include "plugins/relief_shell.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

// The schema, in the order of Param.
const ParamSpec kParams[] = {
    {"layers", ParamType::kInt, 32.0f, 1.0f, 256.0f, nullptr,
     "offset copies of the surface (shells), each rasterised and shaded where covered"},
    kDepthScaleSpec,
    {"shadow_strength", ParamType::kFloat, 0.5f, 0.0f, 1.0f, nullptr,
     "self-shadow: light and indirect light times 1 - strength * depth below the tips"},
};
enum Param { kLayers, kDepthScaleParam, kShadowStrength };

// The shell this fragment lies on: index i and count N (rounded: interpolation of the constant
// per-copy values may be off by an ulp), and its height fraction h = i / N. Clamped to
// 0 <= i < N, 1 <= N <= 256, NaN to the bounds, so that a draw without the layer tags (a caller
// of prepare_instances(scene) alone) still shades finite values: N = 1, the base.
template <class F>
struct Shell {
  F index, count, height;
};
template <class F>
Shell<F> fragment_shell(const FragIn<F>& in) {
  F n = vfloor(in.quadric.y + F(0.5f));
  n = select(n >= F(1.0f), n, F(1.0f));
  n = select(n <= F(256.0f), n, F(256.0f));
  F i = vfloor(in.quadric.x + F(0.5f));
  i = select(i >= F(0.0f), i, F(0.0f));
  i = select(i <= n - F(1.0f), i, n - F(1.0f));
  return {i, n, i / n};
}

// 1 where the texel is opaque on the shell: its height 1 - depth reaches i / N, compared as
// N - N * depth >= i, so that h = i / N is never rounded (shell 0 is opaque at every depth <= 1).
template <class F>
F shell_coverage(const MaterialUniforms& m, const FragIn<F>& in, const Shell<F>& s,
                 ShadeOut<F>& o) {
  const TextureDepth depth = material_depth(m, in);
  if (!depth.texture) return F(1.0f);
  const F d = sample_depth(depth, in.uv, covered_lanes(in));
  o.fetches += F(1.0f);
  return select(s.count - s.count * d >= s.index, F(1.0f), F(0.0f));
}

// kEffects: kEffectShadowPass alone, or kEffectSelfShadow and kEffectReceiveShadow in any mix.
template <EffectMask kEffects>
struct ShellsKernel {
  template <class F>
  static ShadeOut<F> shade(const ShadeContext& ctx, const FragIn<F>& in) {
    const MaterialUniforms& m = *ctx.material;
    ShadeOut<F> o;
    const Shell<F> s = fragment_shell(in);
    const F coverage = shell_coverage(m, in, s, o);
    o.hit_uv = in.uv;
    o.hit_depth = F(1.0f) - s.height;
    if constexpr ((kEffects & kEffectShadowPass) != 0) {
      // the planner makes every layered material MASK: uncovered texels cast no shadow
      o.alpha = coverage * sample_alpha(m, kBaseColorSlot, in.uv, in, o.fetches);
      return o;
    } else {
      const ShellView<F> view = shell_view(ctx, in);
      const V3<F> n = sample_normal_map(m, kNormalSlot, view.tf, in.uv, in, F(1.0f), o.fetches);
      SurfaceColor<F> sc = sample_surface(m, kBaseColorSlot, in.uv, in, o.fetches, &o.alpha);
      o.alpha = o.alpha * coverage;
      constexpr bool kSelfShadow = (kEffects & kEffectSelfShadow) != 0;
      F light(1.0f);
      if constexpr (kSelfShadow) {
        light = depth_darkening(F(1.0f) - s.height, m.params[kShadowStrength]);
        sc.occlusion = sc.occlusion * light;
      }
      // a light below the tangent plane is blocked, as steep parallax's shadow=depth has it
      o.color = shade_point<(kEffects & kEffectReceiveShadow) != 0>(
          ctx, in, in.uv, in.position, n, view.w, sc, covered_lanes(in), o,
          [&](int, const V3<F>& l, mask_t<F>) {
            if constexpr (kSelfShadow) return select(dot(view.tf.n, l) > F(0.0f), light, F(0.0f));
            return light;
          });
      o.shading_normal = n;
      return o;
    }
  }
};

template <EffectMask kR>
ShadeFn select_lit_shells(EffectMask e) {
  return (e & kEffectSelfShadow) ? &shade_packet<ShellsKernel<kEffectSelfShadow | kR>>
                                 : &shade_packet<ShellsKernel<kR>>;
}

}  // namespace

ShadeFn select_shells(EffectMask e) {
  if (e & kEffectShadowPass) return &shade_packet<ShellsKernel<kEffectShadowPass>>;
  return (e & kEffectReceiveShadow) ? select_lit_shells<kEffectReceiveShadow>(e)
                                    : select_lit_shells<0>(e);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

// Every variant writes the polygon's depth: the shells are the geometry.
static DepthOutput shells_depth_output(EffectMask) {
  return DepthOutput::kNone;
}
static int shells_layers(const float* params) {
  return static_cast<int>(params[kLayers]);
}

RELIEF_SELECT_FOR_EVERY_TARGET(select_shells)

RELIEF_BUILTIN_PLUGIN(kShellsPlugin);
const PluginDescriptor kShellsPlugin = {
    kPluginAbiVersion,
    "shells",
    "shell method: N alpha-tested offset copies of the surface (Lengyel et al. 2001)",
    kParams,
    std::size(kParams),
    kReliefSlots,
    std::size(kReliefSlots),
    kEffectSelfShadow | kEffectShadowPass | kEffectReceiveShadow,
    &select_shells_dispatch,
    &shells_depth_output,
    nullptr,
    nullptr,
    nullptr,
    &shells_layers,
};

}  // namespace relief
#endif  // HWY_ONCE
