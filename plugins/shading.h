// The glue between the packet ABI (rasterizer/fragment.h) and kernels written over a lane type.
//
// A plugin defines a Kernel with
//   template <class F> static ShadeOut<F> shade(const ShadeContext&, const FragIn<F>&);
// and exposes shade_packet<Kernel> as its ShadeFn. shade_packet walks the packet the SIMD
// target's kLanes lanes at a time (FN: two quads on AVX2 and baseline, four on AVX-512), or one
// lane at a time with float when FrameUniforms::scalar_lanes is set, loads the standard varyings
// (plugins/plugin.h, namespace varying), hands the kernel the per-quad uv derivatives (dFdx/dFdy,
// coarse), stores colour, depth, discards and AOVs, and adds the kernel's per-lane work counts for
// covered lanes only. Every target gives the same bits (base/simd.h).
//
// Per-target header (shaders_cpp/lanes.h says how); the select macro at the end is not.

#if defined(RELIEF_PLUGINS_SHADING_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_PLUGINS_SHADING_H_
#undef RELIEF_PLUGINS_SHADING_H_
#else
#define RELIEF_PLUGINS_SHADING_H_
#endif

#include "plugins/plugin.h"
#include "shaders_cpp/frame.h"
#include "shaders_cpp/sampling.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct FragIn {
  int lane0;  // first packet lane of this group
  const FragmentPacket* packet;
  V3<F> position;  // world
  V3<F> normal;    // world, interpolated (not unit)
  V3<F> tangent;   // world, interpolated
  F tangent_sign;
  V2<F> uv;
  V2<F> duv_dx, duv_dy;    // per quad
  V2<F> quadric;           // per-vertex quadric (a, b)
  V2<F> tile_scale;        // texture-tile size (sx, sy)
  V4<F> color;             // vertex colour rgba (COLOR_0), 1 when the mesh has none
  V2<F> uv1;               // TEXCOORD_1 (untransformed), 0 when the mesh has none
  V2<F> duv1_dx, duv1_dy;  // per quad
  bool has_extended;       // the packet carries colour and uv1 (varying::kCountExtended)
  F frag_z;                // polygon depth (reversed-Z)
  bool front_facing;
  // The last texture LOD the packet's reads computed (surface.h passes it to every read).
  mutable GradLodMemo<F> lod_memo;
};

template <class F>
struct ShadeOut {
  // User-provided, so that it is compiled for this namespace's target: GCC compiles an implicit
  // constructor without the target options of the region it is declared in.
  ShadeOut() {}
  V3<F> color{F(0.0f), F(0.0f), F(0.0f)};
  F alpha = F(1.0f);
  F depth = F(0.0f);  // read when the variant writes depth
  mask_t<F> discard = false_mask<F>();
  // AOVs
  V2<F> hit_uv{F(0.0f), F(0.0f)};
  F hit_depth = F(0.0f);  // depth-map units [0, 1]
  F steps = F(0.0f);      // search steps
  V3<F> shading_normal{F(0.0f), F(0.0f), F(1.0f)};
  // work
  F fetches = F(0.0f);
  F shadow_steps = F(0.0f);
};

namespace detail {

template <class F>
inline F load_var(const FragmentPacket& p, int k, int lane0) {
  return load_lanes(&p.varyings[k][lane0], F());
}

// Per-quad derivative of varying k, broadcast to the quad's lanes: lane kTo of the quad (1: the
// pixel to the right, dFdx; 2: the pixel below, dFdy) less its lane 0. Over lanes (lane0 a
// multiple of 4, so quads never straddle a group) it is two shuffles of the loaded lanes and one
// subtraction, the same float difference as lane by lane.
template <int kTo, class F>
inline F quad_delta(const FragmentPacket& p, int k, int lane0) {
  if constexpr (is_lanes_v<F>) {
    constexpr int n = lane_width<F>;
    const auto v = load_var<F>(p, k, lane0).v;
    vi_t<n> base{}, to{};
    for (int i = 0; i < n; ++i) {
      base[i] = i & ~3;
      to[i] = (i & ~3) + kTo;
    }
    return F(__builtin_shuffle(v, to) - __builtin_shuffle(v, base));
  } else {
    const int q = lane0 & ~3;
    return p.varyings[k][q + kTo] - p.varyings[k][q];
  }
}
template <class F>
inline F ddx(const FragmentPacket& p, int k, int lane0) {
  return quad_delta<1, F>(p, k, lane0);
}
template <class F>
inline F ddy(const FragmentPacket& p, int k, int lane0) {
  return quad_delta<2, F>(p, k, lane0);
}

template <class F>
inline FragIn<F> load_fragment(const FragmentPacket& p, int lane0) {
  using namespace varying;
  FragIn<F> f;
  f.lane0 = lane0;
  f.packet = &p;
  f.position = {load_var<F>(p, kPosition, lane0), load_var<F>(p, kPosition + 1, lane0),
                load_var<F>(p, kPosition + 2, lane0)};
  f.normal = {load_var<F>(p, kNormal, lane0), load_var<F>(p, kNormal + 1, lane0),
              load_var<F>(p, kNormal + 2, lane0)};
  f.tangent = {load_var<F>(p, kTangent, lane0), load_var<F>(p, kTangent + 1, lane0),
               load_var<F>(p, kTangent + 2, lane0)};
  f.tangent_sign = load_var<F>(p, kTangent + 3, lane0);
  f.uv = {load_var<F>(p, kUv, lane0), load_var<F>(p, kUv + 1, lane0)};
  f.duv_dx = {ddx<F>(p, kUv, lane0), ddx<F>(p, kUv + 1, lane0)};
  f.duv_dy = {ddy<F>(p, kUv, lane0), ddy<F>(p, kUv + 1, lane0)};
  if (p.num_varyings >= kCount) {
    f.quadric = {load_var<F>(p, kQuadric, lane0), load_var<F>(p, kQuadric + 1, lane0)};
    f.tile_scale = {load_var<F>(p, kTileScale, lane0), load_var<F>(p, kTileScale + 1, lane0)};
  } else {
    f.quadric = {F(0.0f), F(0.0f)};
    f.tile_scale = {F(1.0f), F(1.0f)};
  }
  f.has_extended = p.num_varyings >= kCountExtended;
  if (f.has_extended) {
    f.color = {load_var<F>(p, kColor, lane0), load_var<F>(p, kColor + 1, lane0),
               load_var<F>(p, kColor + 2, lane0), load_var<F>(p, kColor + 3, lane0)};
    f.uv1 = {load_var<F>(p, kUv1, lane0), load_var<F>(p, kUv1 + 1, lane0)};
    f.duv1_dx = {ddx<F>(p, kUv1, lane0), ddx<F>(p, kUv1 + 1, lane0)};
    f.duv1_dy = {ddy<F>(p, kUv1, lane0), ddy<F>(p, kUv1 + 1, lane0)};
  } else {
    f.color = {F(1.0f), F(1.0f), F(1.0f), F(1.0f)};
    f.uv1 = f.duv1_dx = f.duv1_dy = {F(0.0f), F(0.0f)};
  }
  f.frag_z = load_lanes(&p.frag_z[lane0], F());
  f.front_facing = p.front_facing;
  return f;
}

template <class F>
inline void store_out(const ShadeOut<F>& o, const FragmentPacket& p, int lane0,
                      FragmentOutput& out) {
  store_lanes(&out.color[0][lane0], o.color.x);
  store_lanes(&out.color[1][lane0], o.color.y);
  store_lanes(&out.color[2][lane0], o.color.z);
  store_lanes(&out.color[3][lane0], o.alpha);
  store_lanes(&out.depth[lane0], o.depth);
  store_lanes(&out.aov[kAovOffset[0]][lane0], o.hit_uv.x);
  store_lanes(&out.aov[kAovOffset[0] + 1][lane0], o.hit_uv.y);
  store_lanes(&out.aov[kAovOffset[1]][lane0], o.hit_depth);
  store_lanes(&out.aov[kAovOffset[2]][lane0], o.steps);
  store_lanes(&out.aov[kAovOffset[3]][lane0], o.shading_normal.x);
  store_lanes(&out.aov[kAovOffset[3] + 1][lane0], o.shading_normal.y);
  store_lanes(&out.aov[kAovOffset[3] + 2][lane0], o.shading_normal.z);
  // Discards are rare (MASK materials, silhouettes): the lanes are read one by one only then.
  // (Reading a lane of a vector in a loop goes through memory, and waits on the store.)
  if (!any(o.discard)) return;
  for (int i = 0; i < lane_width<F>; ++i) {
    const int ln = lane0 + i;
    if ((ln >> 2) >= p.num_quads) break;
    if (lane(o.discard, i)) out.discard[ln >> 2] |= uint8_t(1u << (ln & 3));
  }
}

// The lanes lane0 .. lane0 + width that the work counters count: covered lanes of the packet's
// quads (WorkCounters).
template <class F>
inline mask_t<F> counted_lanes(const FragmentPacket& p, int lane0) {
  if constexpr (std::is_same_v<F, float>) {
    return (lane0 >> 2) < p.num_quads && p.lane_covered(lane0);
  } else {
    using I = int_t<F>;
    constexpr int kW = lane_width<F>;
    static_assert(kW % kQuadLanes == 0 && kW <= 32);
    int32_t bits = 0;  // bit i: lane lane0 + i
    for (int q = 0; q < kW / kQuadLanes; ++q) {
      const int quad = (lane0 >> 2) + q;
      if (quad < p.num_quads) bits |= int32_t(p.coverage[quad] & 0xf) << (kQuadLanes * q);
    }
    I index;
    for (int i = 0; i < kW; ++i) set_lane(index, i, i);
    return ((I(bits) >> index) & 1) == 1;
  }
}

// A kernel's work (fetches, search and shadow steps: whole numbers held in float lanes) summed
// over the counted lanes of a packet, lane-parallel, and added to the counters once a packet.
template <class F>
struct WorkLanes {
  using I = int_t<F>;
  // User-provided, as ShadeOut's: compiled for this namespace's target.
  WorkLanes() : fetches(0), steps(0), shadow_steps(0) {}
  I fetches, steps, shadow_steps;
  void add(const ShadeOut<F>& o, const mask_t<F>& counted) {
    fetches = fetches + select(counted, trunc_to_int(o.fetches), I(0));
    steps = steps + select(counted, trunc_to_int(o.steps), I(0));
    shadow_steps = shadow_steps + select(counted, trunc_to_int(o.shadow_steps), I(0));
  }
  static uint64_t sum(const I& x) {
    int32_t a[lane_width<F>];
    std::memcpy(a, &x, sizeof a);
    uint64_t s = 0;
    for (int32_t v : a) s += static_cast<uint64_t>(v);
    return s;
  }
  void flush(WorkCounters& wc) const {
    wc.texture_fetches += sum(fetches);
    wc.search_steps += sum(steps);
    wc.shadow_steps += sum(shadow_steps);
  }
};

// The material's alphaMode applied to a kernel's output (docs/scene-format.md, "Alpha"): MASK
// discards the lanes whose alpha is below alpha_cutoff, and MASK and OPAQUE write alpha 1; BLEND
// keeps the alpha, clamped to [0, 1], for the rasterizer to composite with.
template <class F>
inline ShadeOut<F> resolve_alpha(const MaterialUniforms& m, ShadeOut<F> o) {
  if (m.alpha_mode == AlphaMode::kBlend) {
    o.alpha = clamp(o.alpha, F(0.0f), F(1.0f));
    return o;
  }
  if (m.alpha_mode == AlphaMode::kMask) o.discard = o.discard | (o.alpha < F(m.alpha_cutoff));
  o.alpha = F(1.0f);
  return o;
}

}  // namespace detail

// The ShadeFn of a kernel: the packet walked kLanes lanes (kLanes / 4 quads) at a time with FN,
// or one lane at a time with float when FrameUniforms::scalar_lanes is set (the reference path);
// same bits either way. It is compiled for the SIMD target of the enclosing namespace, kernel
// and all; RELIEF_SELECT_FOR_EVERY_TARGET hands out the right target's copy per draw.
namespace detail {
// Whether a kernel shades two groups of lanes at once (static constexpr bool kPaired and
// shade_pair<F>(ctx, in_a, in_b, out_a, out_b), the same outputs as shade<F> of each).
template <class Kernel>
constexpr bool paired_kernel() {
  if constexpr (requires { Kernel::kPaired; })
    return Kernel::kPaired;
  else
    return false;
}
// The lane loop. `flatten` inlines the kernel, its search and its lighting into it (the samplers
// stay out of line, in sampling_simd.cpp): a matter of speed only, since caller and callees are
// all this target's code; without it GCC left small lane functions out of line, 13% more
// instructions a fragment (docs/performance.md, "Per-target compilation").
template <class Kernel>
RELIEF_LANE_FLATTEN void shade_lanes(const ShadeContext& ctx, const FragmentPacket& in,
                                     FragmentOutput& out, WorkCounters& wc) {
  static_assert(kPacketLanes % kLanes == 0);
  const int lanes = in.num_quads * kQuadLanes;
  WorkLanes<FN> work;
  // a group's output: the material's alpha mode, the store, the work counts
  const auto emit = [&](const ShadeOut<FN>& shaded, int lane0) {
    const ShadeOut<FN> o = resolve_alpha(*ctx.material, shaded);
    store_out(o, in, lane0, out);
    work.add(o, counted_lanes<FN>(in, lane0));
  };
  int l = 0;
  if constexpr (paired_kernel<Kernel>()) {
    // two groups at a time (Kernel::shade_pair), the last one alone when their count is odd
    for (; l + kLanes < lanes; l += 2 * kLanes) {
      const FragIn<FN> fa = load_fragment<FN>(in, l), fb = load_fragment<FN>(in, l + kLanes);
      ShadeOut<FN> oa, ob;
      Kernel::template shade_pair<FN>(ctx, fa, fb, oa, ob);
      emit(oa, l);
      emit(ob, l + kLanes);
    }
  }
  for (; l < lanes; l += kLanes) emit(Kernel::template shade<FN>(ctx, load_fragment<FN>(in, l)), l);
  work.flush(wc);
}
}  // namespace detail

template <class Kernel>
void shade_packet(const ShadeContext& ctx, const FragmentPacket& in, FragmentOutput& out,
                  WorkCounters& wc) {
  if (!ctx.frame->scalar_lanes) return detail::shade_lanes<Kernel>(ctx, in, out, wc);
  const int lanes = in.num_quads * kQuadLanes;
  detail::WorkLanes<float> work;
  for (int l = 0; l < lanes; ++l) {
    if (!in.coverage[l >> 2]) continue;
    const FragIn<float> f = detail::load_fragment<float>(in, l);
    const ShadeOut<float> o =
        detail::resolve_alpha(*ctx.material, Kernel::template shade<float>(ctx, f));
    detail::store_out(o, in, l, out);
    work.add(o, detail::counted_lanes<float>(in, l));
  }
  work.flush(wc);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_PLUGINS_SHADING_H_

#ifndef RELIEF_PLUGINS_SHADING_H_ONCE
#define RELIEF_PLUGINS_SHADING_H_ONCE
// A plugin's PluginDescriptor::select for every SIMD target. In a plugin compiled with
// hwy/foreach_target.h, define per target (inside relief::HWY_NAMESPACE)
//   ShadeFn NAME(EffectMask effects) { ... return &shade_packet<...>; }
// and, once (#if HWY_ONCE, in namespace relief), RELIEF_SELECT_FOR_EVERY_TARGET(NAME): it
// defines NAME_dispatch, the descriptor's `select`, which returns the packet shader of the SIMD
// level in use (base/simd.h) when the draw is planned. No vector crosses it.
#define RELIEF_SELECT_FOR_EVERY_TARGET(NAME)    \
  HWY_EXPORT(NAME);                             \
  ShadeFn NAME##_dispatch(EffectMask effects) { \
    return HWY_DYNAMIC_DISPATCH(NAME)(effects); \
  }
#endif  // RELIEF_PLUGINS_SHADING_H_ONCE
