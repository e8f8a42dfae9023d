// Cone stepping through a height field, written once over the lane type F (float or F8):
//   conservative cone stepping: Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield
//     Intersection Algorithm", 2006;
//   quad-directional cones and relaxed cone stepping + binary search: Policarpo and Oliveira,
//     "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3, ch. 18, 2007 (section 18.4.2,
//     equations 1-4, listing 18-3 and figure 18-10).
//
// Conventions: see shaders_cpp/ray.h and shaders_cpp/search.h. The ray is (uv + ds t, depth t),
// t in [0, 1]; a cone ratio (bake/cone_map.h) is uv distance per unit of depth. At a point
// outside the surface, h = D(uv + ds t) - t > 0 is the depth of the texel's surface below the
// ray, and the ray meets the cone of that texel (apex on the surface, opening upward) after
//   d = r h / (|ds| + r)                                            (chapter, equation 3)
// more units of depth. One step = one depth sample and one cone-map sample (two fetches: the cone
// map is its own texture here, where the chapter packs depth and ratio into one texel). A lane
// stops once it samples a point at or under the surface (h <= 0: the listing's saturate() makes
// d = 0 there, so the fixed-count loop would stay put), once it reaches t_max, or after n steps.
// All three techniques march and refine on one field, the material's (bilinear) depth that the
// exact reference intersects, and end bracket-safe (cone_finish): a lane the march left outside
// takes a bounded number of floored steps, so a hit is never reported above the surface (issue 22:
// the chapter marches the nearest-texel field its cones are baked for, and binary-searched the
// bilinear one from H to K, which "converged" in the air where neither end brackets a crossing).
//
// Cone sources: any object with `float operator()(int lane, float u, float v) const` returning
// the ratio that lane's ray may use at (u, v). TextureCone reads the first channel of a cone map;
// QuadTextureCone reads the four quad-directional ratios (+u, -u, +v, -v) and returns, for a ray
// whose uv direction has signs (su, sv), max(r[su], r[sv]): the ray stays in both closed
// half-planes, so either ratio is safe and the wider one is used.

#if defined(RELIEF_SHADERS_CPP_CONE_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_CONE_H_
#undef RELIEF_SHADERS_CPP_CONE_H_
#else
#define RELIEF_SHADERS_CPP_CONE_H_
#endif

#include <cmath>
#include <type_traits>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/texture.h"
#include "shaders_cpp/lanes.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// The nearest-texel depth field the relaxed cones are defined on: a TextureDepth whose sampler
// is `sampler` with nearest filtering (kept here, so the reader can be copied freely).
struct NearestTextureDepth {
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[kLanes] = {};
  mutable RLodPlan plan;  // as TextureDepth's
  float operator()(int lane, float u, float v) const {
    return sample_r_lod(*texture, sampler, glm::vec2(u, v), lod[lane]);
  }
  template <class F>
  F lanes(V2<F> uv) const {
    return r_lod_lanes(*texture, sampler, lod, uv, plan);
  }
};

// Sampler state for a cone map: nearest texel (a ratio belongs to one texel's apex; blending two
// ratios can widen a cone) of the mip level nearest the LOD (min-mips), the material's wraps.
inline SamplerState cone_sampler(const SamplerState& material) {
  SamplerState s = material;
  s.filter = Filter::kNearest;
  return s;
}

// One cone ratio per lane from channel 0 of a cone map at a constant LOD per lane.
struct TextureCone {
  const Texture* texture = nullptr;
  SamplerState sampler;  // cone_sampler(...)
  float lod[kLanes] = {};
  mutable RLodPlan plan;  // as TextureDepth's
  float operator()(int lane, float u, float v) const {
    return sample_lod(*texture, sampler, glm::vec2(u, v), lod[lane]).x;
  }
  // sample_r_lod is sample_lod's first channel for every format.
  template <class F>
  F lanes(V2<F> uv) const {
    return r_lod_lanes(*texture, sampler, lod, uv, plan);
  }
};

// Quad-directional cones: per lane the +u or -u ratio (channel 0 or 1) and the +v or -v ratio
// (channel 2 or 3), set by aim() as the bit offsets of those halves in a texel.
struct QuadTextureCone {
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[kLanes] = {};
  IN shift_u, shift_v;    // 16 * (channel - 0) and 16 * (channel - 2) per lane
  mutable RLodPlan plan;  // quad_cone_lanes' (sampling_simd.h)
  // Picks each lane's pair of channels from the signs of its uv direction.
  template <class F>
  void aim(V2<F> ds) {
    for (int i = 0; i < lane_width<F>; ++i) {
      set_lane(shift_u, i, lane(ds.x, i) >= 0.0f ? 0 : 16);
      set_lane(shift_v, i, lane(ds.y, i) >= 0.0f ? 0 : 16);
    }
  }
  float operator()(int lane, float u, float v) const {
    return quad_cone_pick(sample_lod(*texture, sampler, glm::vec2(u, v), lod[lane]), shift_u[lane],
                          shift_v[lane]);
  }
  // The native lanes at once through quad_cone_lanes (bit-identical to operator() per lane).
  template <class F>
  F lanes(V2<F> uv) const {
    if constexpr (std::is_same_v<F, FN>)
      return quad_cone_lanes(*texture, sampler, lod, uv, shift_u, shift_v, plan);
    else
      return per_lane(uv.x, [&](int i) { return (*this)(i, lane(uv.x, i), lane(uv.y, i)); });
  }
};

// What a cone step reads at p: the depth and the cone ratio, for the marching lanes; counts one
// step and two fetches per marching lane.
template <class F>
struct ConeTexel {
  F depth, ratio;
};
template <class F, class Depth, class Cone>
inline ConeTexel<F> sample_cone_texel(const Depth& depth, const Cone& cone, const V2<F>& p,
                                      mask_t<F> marching, F& steps, F& fetches) {
  const ConeTexel<F> c{sample_depth(depth, p, marching), sample_depth(cone, p, marching)};
  steps += detail::count<F>(marching);
  fetches += detail::count<F>(marching) * F(2.0f);
  return c;
}

// What a cone march leaves per lane: where it stopped (t: the first sample at or under the
// surface, t_max, or the point the last step reached), the last sample outside (t_out, 0 when
// none) and whether the sample at t was inside. Counters: one step and two fetches per sample.
template <class F>
struct ConeMarch {
  F t, t_out;
  mask_t<F> inside;
  F steps, fetches;
};

// Cone stepping (n steps at most) from depth 0 on `depth`, capped at t_max <= 1 per lane, one
// step a call of step() while more(): cone_march_state runs it to the end, and
// cone_search_pair runs two packets' marches side by side (step_both).
// Conservative cones safe for the sampled surface never pass its first intersection; relaxed
// cones may step into the surface, and then stop at the first sample inside. (A floor under the
// step, one or a quarter texel along the ray, so that a march skimming a surface cannot stall,
// was measured worse on light rays: it leaves more of the ray to the coarse fallback.)
template <class F, class Depth, class Cone>
struct ConeMarcher {
  // User-provided, as ShadeOut's (plugins/shading.h): compiled for this namespace's target.
  ConeMarcher(const Depth& depth_, const Cone& cone_, V2<F> uv_, V2<F> ds_, int n_, F t_max_,
              mask_t<F> active)
      : depth(&depth_),
        cone(&cone_),
        uv(uv_),
        ds(ds_),
        t_max(t_max_),
        ray_ratio(vsqrt(ds_.x * ds_.x + ds_.y * ds_.y)),
        n(n_),
        m{F(0.0f), F(0.0f), false_mask<F>(), F(0.0f), F(0.0f)},
        marching(active & (m.t < t_max_)) {}
  bool more() const { return i < n && any(marching); }
  void step() {
    const ConeTexel<F> c =
        sample_cone_texel(*depth, *cone, uv + ds * m.t, marching, m.steps, m.fetches);
    const F r = c.ratio;
    const F h = c.depth - m.t;
    m.inside = m.inside | (marching & !(h > F(0.0f)));
    marching = marching & (h > F(0.0f));
    m.t_out = select(marching, m.t, m.t_out);
    // distance to the cone's surface along the ray (equation 3)
    const F den = ray_ratio + r;
    const mask_t<F> moves = marching & (den > F(0.0f));
    const F step = r * h / select(moves, den, F(1.0f));
    m.t = select(moves, vmin(m.t + step, t_max), m.t);
    marching = marching & (m.t < t_max);
    ++i;
  }

  const Depth* depth;
  const Cone* cone;
  V2<F> uv, ds;
  F t_max, ray_ratio;
  int n, i = 0;
  ConeMarch<F> m;
  mask_t<F> marching;
};

template <class F, class Depth, class Cone>
inline ConeMarch<F> cone_march_state(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds,
                                     int n, F t_max, mask_t<F> active) {
  ConeMarcher<F, Depth, Cone> marcher(depth, cone, uv, ds, n, t_max, active);
  while (marcher.more()) marcher.step();
  return marcher.m;
}

// Two steppers (ConeMarcher, ConeFallback) of two packets run to their ends side by side, a step
// of each in turn: a step is a chain of dependent latencies (its reads, then the division), and
// the other packet's step runs in its waits. Each packet computes what it computes alone.
template <class Stepper>
inline void step_both(Stepper& a, Stepper& b) {
  for (;;) {
    const bool more_a = a.more(), more_b = b.more();
    if (!more_a && !more_b) return;
    if (more_a) a.step();
    if (more_b) b.step();
  }
}

// The march alone, as a hit at the position it stopped (the chapter's K; for conservative cones
// the point reached, above the surface when the steps ran out).
template <class F, class Depth, class Cone>
inline SearchHit<F> cone_march(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds, int n,
                               F t_max, mask_t<F> active) {
  const ConeMarch<F> m = cone_march_state(depth, cone, uv, ds, n, t_max, active);
  return {uv + ds * m.t, m.t, m.steps, m.fetches};
}

// What cone_finish returns: the hit, and the lanes that found a sample inside (all active lanes
// of a view ray; the occluded lanes of a light ray).
template <class F>
struct ConeHit {
  SearchHit<F> hit;
  mask_t<F> found;
};

// Half a texel of a w x h map along a ray of uv step ds, in units of t (the view ray's fallback
// step; a ray along the normal gets a huge value, and the fallback's other bound decides).
template <class F>
inline F half_texel_along(int w, int h, V2<F> ds) {
  const F len = vsqrt(ds.x * ds.x + ds.y * ds.y) * F(static_cast<float>(w > h ? w : h));
  return F(0.5f) / vmax(len, F(1e-6f));
}

// The view ray's fallback ramp (cone_finish, quadric_relaxed_cone_search): fallback step j < ramp
// = fallback_ramp(k) takes at least min(floor, view_floor / 2^(ramp - j)) instead of floor,
// so a lane whose march stalled just before a crest (the cone ratio goes to 0 where the surface
// rises beside the ray) samples its way over the crest in doubling steps: a crest chord as long
// as its distance from the stall point is sampled inside. Without it the half-texel floor jumped
// such chords: on the thin-wall field 1 % to 50 % of the view rays landed on a wrong layer
// (docs/cones.md). Light rays keep their plain floor (the same ramp there bought nothing on the
// bench's fields at 15 % more fetches).
inline constexpr int kFallbackRamp = 16;
// A fallback of k steps ramps over its first min(kFallbackRamp, k / 2), so a short one (the
// schema allows 1) still takes half-texel steps over most of its length.
inline int fallback_ramp(int k) {
  return k / 2 < kFallbackRamp ? k / 2 : kFallbackRamp;
}
template <class F>
inline F ramped_floor(int j, int ramp, const F& floor, const F& view_floor) {
  return j < ramp ? vmin(floor, view_floor * F(std::ldexp(1.0f, j - ramp))) : floor;
}

// cone_finish's cone steps after the march, one a call of step() while more() (as ConeMarcher).
template <class F, class Depth, class Cone>
struct ConeFallback {
  // User-provided, as ConeMarcher's.
  ConeFallback(const Depth& depth_, const Cone& cone_, V2<F> uv_, V2<F> ds_, const ConeMarch<F>& mr,
               int k_, F t_max_, bool bottom_, F view_floor_, mask_t<F> active)
      : depth(&depth_),
        cone(&cone_),
        uv(uv_),
        ds(ds_),
        t_max(t_max_),
        view_floor(view_floor_),
        ray_ratio(vsqrt(ds_.x * ds_.x + ds_.y * ds_.y)),
        lo(mr.t_out),
        hi(mr.t),
        steps(mr.steps),
        fetches(mr.fetches),
        floor((t_max_ - mr.t) * F(1.0f / static_cast<float>(k_))),
        s(mr.t),
        found(active & mr.inside),
        searching(active & !mr.inside & (mr.t < t_max_)),
        k(k_),
        ramp(fallback_ramp(k_)),
        bottom(bottom_) {
    if (bottom) floor = vmin(floor, view_floor);
  }
  bool more() const { return j < k && any(searching); }
  void step() {
    const ConeTexel<F> c = sample_cone_texel(*depth, *cone, uv + ds * s, searching, steps, fetches);
    const F h = c.depth - s;
    const mask_t<F> in = searching & !(h > F(0.0f));
    found = found | in;
    hi = select(in, s, hi);
    searching = searching & !in;
    lo = select(searching, s, lo);
    const F den = ray_ratio + c.ratio;
    const F step = vmax(c.ratio * h / select(den > F(0.0f), den, F(1.0f)),
                        bottom ? ramped_floor(j, ramp, floor, view_floor) : floor);
    s = select(searching, vmin(s + step, t_max), s);
    searching = searching & (s < t_max);
    ++j;
  }

  const Depth* depth;
  const Cone* cone;
  V2<F> uv, ds;
  F t_max, view_floor, ray_ratio;
  F lo, hi, steps, fetches, floor, s;
  mask_t<F> found, searching;
  int k, ramp, j = 0;
  bool bottom;
};

// What cone_finish does once its cone steps are done, in three parts that cone_search_pair runs
// for two packets: cone_close (a view ray's even samples; the lanes at t_max), the halvings of
// every found lane's bracket (bisect or Bisector with a ConeInside test), cone_hit.
template <class F, class Depth, class Cone>
inline void cone_close(ConeFallback<F, Depth, Cone>& fb, mask_t<F> active) {
  const Depth& depth = *fb.depth;
  const V2<F> uv = fb.uv, ds = fb.ds;
  const F t_max = fb.t_max;
  F &lo = fb.lo, &hi = fb.hi, &steps = fb.steps, &fetches = fb.fetches;
  mask_t<F>&found = fb.found, &searching = fb.searching;
  const int k = fb.k;
  if (fb.bottom) {
    // view rays the short steps did not finish: k even samples over the rest, [s, t_max)
    const F s0 = fb.s, rest = t_max - fb.s;
    for (int j = 0; j < k && any(searching); ++j) {
      const F u = s0 + rest * F(static_cast<float>(j) / static_cast<float>(k));
      const F d = sample_depth(depth, uv + ds * u, searching);
      steps += detail::count<F>(searching);
      fetches += detail::count<F>(searching);
      const mask_t<F> in = searching & (d <= u);
      found = found | in;
      hi = select(in, u, hi);
      searching = searching & !in;
      lo = select(searching, u, lo);
    }
  }
  const mask_t<F> at_end = active & !found;  // reached t_max, or out of fallback steps
  hi = select(at_end, t_max, hi);
  if (fb.bottom) found = found | at_end;
}
// The halvings' test: the sample at depth mid is inside.
template <class F, class Depth>
struct ConeInside {
  const Depth* depth;
  V2<F> uv, ds;
  mask_t<F> operator()(const F& mid, mask_t<F> refine) const {
    return sample_depth(*depth, uv + ds * mid, refine) <= mid;
  }
};
template <class F, class Depth, class Cone>
inline ConeHit<F> cone_hit(const ConeFallback<F, Depth, Cone>& fb, mask_t<F> active) {
  const F t = select(active, fb.hi, F(0.0f));
  return {{fb.uv + fb.ds * t, t, fb.steps, fb.fetches}, fb.found};
}

// The bracket-safe end of a cone march on the field it marched (`depth`, the surface the hit is
// reported on). Lanes whose march sampled a point inside keep [t_out, t] as their bracket. Lanes
// it left outside (out of steps, a stalled conservative march, or at t_max) fall back to k more
// cone steps from where it stopped, each at least `floor` = (t_max - t) / k, on a view ray
// (`bottom`) at most `view_floor` (half a texel along the ray: samples that close cannot step
// over a one-texel wall the way an even split of a grazing ray's rest does) and its first
// fallback_ramp(k) ramped up from 1/2^16 of that (ramped_floor); the cone's own step is taken when
// longer. A view ray those steps leave short of t_max takes k even samples over the rest (one
// fetch each). t_max ends the fallback: inside on a view ray (depth 1 is under every surface;
// unsampled), the end of a light ray (no occluder: not found). The first inside sample closes
// the bracket with the last outside one. Then m halvings (one step, one fetch each) of every
// found lane's bracket, returning its inside end: every hit is a sample of `depth` at or under
// the surface whose outside partner lies (t_in - t_out) / 2^m before it, so no hit is reported in
// the air. Lanes not found return t_max. k >= 1. Counters: the march's, plus one step and two
// fetches per fallback cone step, one and one per even sample.
template <class F, class Depth, class Cone>
inline ConeHit<F> cone_finish(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds,
                              const ConeMarch<F>& mr, int k, int m, F t_max, bool bottom,
                              F view_floor, mask_t<F> active) {
  ConeFallback<F, Depth, Cone> fb(depth, cone, uv, ds, mr, k, t_max, bottom, view_floor, active);
  while (fb.more()) fb.step();
  cone_close(fb, active);
  const ConeInside<F, Depth> inside{&depth, uv, ds};
  bisect(fb.lo, fb.hi, fb.found & (fb.hi > fb.lo), m, 1.0f, fb.steps, fb.fetches, inside);
  return cone_hit(fb, active);
}

// Cone stepping (n steps, any cone kind) on `depth` then cone_finish (k fallback steps of at most
// view_floor, half_texel_along the ray; m halvings) of the view ray: the search of all three cone
// techniques. Conservative and quad cones bring most lanes down to the surface from above (the
// halvings then refine the last gap), relaxed ones into it; the chapter's bracket from H (half-way
// to K) to K is replaced by [last outside sample, K], which is a bracket on every lane.
template <class F, class Depth, class Cone>
inline SearchHit<F> cone_search(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds, int n,
                                int k, int m, F view_floor, mask_t<F> active) {
  const ConeMarch<F> mr = cone_march_state(depth, cone, uv, ds, n, F(1.0f), active);
  return cone_finish(depth, cone, uv, ds, mr, k, m, F(1.0f), true, view_floor, active).hit;
}

// One cone source and view ray per packet, for cone_search_pair.
template <class F, class Depth, class Cone>
struct ConeRay {
  const Depth* depth;
  const Cone* cone;
  V2<F> uv, ds;
  F view_floor;
  mask_t<F> active;
};

// cone_search of two packets, their marches and then their fallback steps run side by side
// (step_both): the same hits and counters as two calls of cone_search, in less time where the
// steps wait on their reads (docs/performance.md, "two packets in flight").
template <class F, class Depth, class Cone>
inline void cone_search_pair(const ConeRay<F, Depth, Cone>& a, const ConeRay<F, Depth, Cone>& b,
                             int n, int k, int m, SearchHit<F>& hit_a, SearchHit<F>& hit_b) {
  ConeMarcher<F, Depth, Cone> march_a(*a.depth, *a.cone, a.uv, a.ds, n, F(1.0f), a.active);
  ConeMarcher<F, Depth, Cone> march_b(*b.depth, *b.cone, b.uv, b.ds, n, F(1.0f), b.active);
  step_both(march_a, march_b);
  ConeFallback<F, Depth, Cone> fall_a(*a.depth, *a.cone, a.uv, a.ds, march_a.m, k, F(1.0f), true,
                                      a.view_floor, a.active);
  ConeFallback<F, Depth, Cone> fall_b(*b.depth, *b.cone, b.uv, b.ds, march_b.m, k, F(1.0f), true,
                                      b.view_floor, b.active);
  step_both(fall_a, fall_b);
  cone_close(fall_a, a.active);
  cone_close(fall_b, b.active);
  const ConeInside<F, Depth> inside_a{a.depth, a.uv, a.ds}, inside_b{b.depth, b.uv, b.ds};
  using Halving = Bisector<F, ConeInside<F, Depth>>;
  Halving half_a(fall_a.lo, fall_a.hi, fall_a.found & (fall_a.hi > fall_a.lo), m, 1.0f,
                 fall_a.steps, fall_a.fetches, inside_a);
  Halving half_b(fall_b.lo, fall_b.hi, fall_b.found & (fall_b.hi > fall_b.lo), m, 1.0f,
                 fall_b.steps, fall_b.fetches, inside_b);
  step_both(half_a, half_b);
  hit_a = cone_hit(fall_a, a.active).hit;
  hit_b = cone_hit(fall_b, b.active).hit;
}

// A light ray's occluder search (see light_ray_shadow): the march and the fallback (steps of at
// least a k-th of what is left), no halvings; the hit's depth is below t_max exactly on the lanes
// where a sample was inside.
template <class F, class Depth, class Cone>
inline SearchHit<F> occluder_hit(const ConeFallback<F, Depth, Cone>& fb, mask_t<F> active) {
  const ConeHit<F> h = cone_hit(fb, active);
  SearchHit<F> hit = h.hit;
  hit.depth = select(h.found, hit.depth, fb.t_max);
  return hit;
}
template <class F, class Depth, class Cone>
inline SearchHit<F> cone_occluder_search(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds,
                                         int n, int k, mask_t<F> active, F t_max) {
  const ConeMarch<F> mr = cone_march_state(depth, cone, uv, ds, n, t_max, active);
  ConeFallback<F, Depth, Cone> fb(depth, cone, uv, ds, mr, k, t_max, false, F(0.0f), active);
  while (fb.more()) fb.step();
  cone_close(fb, active);
  return occluder_hit(fb, active);
}

template <class F>
struct ConeShadow {
  F visibility;  // 1 lit, 0 shadowed
  F steps;       // iterations of the light ray's search, per lane
  F fetches;     // texture samples, per lane
};

// The light ray of light_ray_shadow before its search: it enters the depth range at `entry`,
// runs along `down` to depth t_max on the `trace` lanes; `vis` is the visibility of the lanes
// that trace nothing.
template <class F>
struct LightRay {
  V2<F> entry, down;
  F t_max;
  mask_t<F> trace;
  F vis;
};
template <class F>
inline LightRay<F> light_ray(V2<F> uv, F t, V2<F> dl, F lz, float bias, mask_t<F> active) {
  const mask_t<F> lit_side = lz > F(0.0f);
  const F t_max = t - F(bias);
  const mask_t<F> trace = active & lit_side & (t_max > F(0.0f));
  return {uv + dl * t_max,
          {F(0.0f) - dl.x, F(0.0f) - dl.y},
          t_max,
          trace,
          select(active & !lit_side, F(0.0f), F(1.0f))};
}
// The shadow of a light ray whose occluder search found h.
template <class F>
inline ConeShadow<F> light_ray_result(const LightRay<F>& r, const SearchHit<F>& h) {
  return {select(r.trace & (h.depth < r.t_max), F(0.0f), r.vis), h.steps, h.fetches};
}

// Hard self-shadow with the view ray's own search (Policarpo et al. 2005, figure 10: does the
// light ray reach the shaded point before any other surface point?), with the exact reference's
// bias semantics (shadowed where the surface is above the shadow ray by more than `bias`): the
// light ray lowered by `bias` enters the depth range at E = uv + dl t_max, t_max = t - bias, and
// runs down along -dl to depth t_max; `search(E, -dl, t_max, active)` is the technique's
// occluder search capped at t_max (cone_occluder_search). The point is shadowed where the search
// reports a depth before t_max: it sampled a point under the surface (a march that runs out of
// steps on the way is not a shadow: cone_occluder_search then samples the rest of the ray).
// Lanes with L.z <= 0 get visibility 0 and take no step; inactive lanes get 1.
template <class F, class Search>
inline ConeShadow<F> light_ray_shadow(V2<F> uv, F t, V2<F> dl, F lz, float bias, mask_t<F> active,
                                      Search&& search) {
  const LightRay<F> r = light_ray(uv, t, dl, lz, bias, active);
  if (none(r.trace)) return {r.vis, F(0.0f), F(0.0f)};
  return light_ray_result(r, search(r.entry, r.down, r.t_max, r.trace));
}

// The occluder searches of two packets' light rays (cone_occluder_search of each, cones aimed),
// their marches and fallback steps run side by side (step_both): the same hits as one at a time.
template <class F, class Depth, class Cone>
inline void cone_occluder_search_pair(const Depth& depth_a, const Cone& cone_a,
                                      const LightRay<F>& a, const Depth& depth_b,
                                      const Cone& cone_b, const LightRay<F>& b, int n, int k,
                                      SearchHit<F>& hit_a, SearchHit<F>& hit_b) {
  using Marcher = ConeMarcher<F, Depth, Cone>;
  Marcher march_a(depth_a, cone_a, a.entry, a.down, n, a.t_max, a.trace);
  Marcher march_b(depth_b, cone_b, b.entry, b.down, n, b.t_max, b.trace);
  step_both(march_a, march_b);
  using Fallback = ConeFallback<F, Depth, Cone>;
  Fallback fall_a(depth_a, cone_a, a.entry, a.down, march_a.m, k, a.t_max, false, F(0.0f), a.trace);
  Fallback fall_b(depth_b, cone_b, b.entry, b.down, march_b.m, k, b.t_max, false, F(0.0f), b.trace);
  step_both(fall_a, fall_b);
  cone_close(fall_a, a.trace);
  cone_close(fall_b, b.trace);
  hit_a = occluder_hit(fall_a, a.trace);
  hit_b = occluder_hit(fall_b, b.trace);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_CONE_H_
