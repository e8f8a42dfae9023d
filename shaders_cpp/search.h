// Height-field ray searches written once over the lane type F (float or F8):
//   linear + binary search: Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary
//     Polygonal Surfaces", I3D 2005 (section 3, figures 7-9; appendix ray_intersect_rm);
//   steep parallax: McGuire and McGuire, "Steep Parallax Mapping", I3D 2005 poster (n planes);
//   secant refinement: Tatarchuk, "Dynamic Parallax Occlusion Mapping with Approximate Soft
//     Shadows", I3D 2006 (interpolation of the last two samples);
//   parallax: Kaneko et al. 2001; offset limiting: Welsh 2004.
//
// Conventions: see shaders_cpp/ray.h. A ray starts at uv (depth 0) and reaches depth t at
// uv + ds * t. A sample at depth t is "inside" (under the surface) when the sampled depth
// D(uv + ds * t) <= t. Every search returns the hit (uv, depth) and, per lane, the steps it took
// and the texture fetches it made (one call of the depth source = one fetch). Lanes outside
// `active` do nothing, are not counted and return their start uv at depth 0. Loops stop as soon
// as no lane is still searching.
//
// A depth source is any object with `float operator()(int lane, float u, float v) const`; lane is
// the lane index within F (0 for float), so a source can hold one LOD per quad. TextureDepth reads
// a depth texture through sample_r_lod at a constant LOD. A source may also offer
// `F lanes(V2<F> uv) const`, every lane at once with the same values; sample_depth prefers it.

#if defined(RELIEF_SHADERS_CPP_SEARCH_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_SEARCH_H_
#undef RELIEF_SHADERS_CPP_SEARCH_H_
#else
#define RELIEF_SHADERS_CPP_SEARCH_H_
#endif

#include <type_traits>

#include <glm/vec2.hpp>

#include "rasterizer/texture.h"
#include "shaders_cpp/lanes.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// The first channel of `t` at uv with the lanes' LODs lod[0..lanes): the lane-parallel sampler,
// for the native lanes FN through `plan` (sampling_simd.h: levels chosen once for the LODs, the
// read out of line), bit-identical to sample_r_lod per lane.
template <class F>
inline F r_lod_lanes(const Texture& t, const SamplerState& s, const float* lod, V2<F> uv,
                     RLodPlan& plan) {
  if constexpr (std::is_same_v<F, FN>) {
    return texture_r_lod_planned(t, s, lod, uv, plan);
  } else {
    (void)plan;
    return texture_r_lod(t, s, uv, load_lanes(lod, F()));
  }
}

// Depth from the first channel of a texture at a fixed LOD per lane (computed once per quad).
// `plan` is the lane reads' cache: prepared on the first read, again when the texture, sampler
// or LODs have changed since (a copy may be retargeted), so it never serves stale levels.
struct TextureDepth {
  const Texture* texture = nullptr;
  const SamplerState* sampler = nullptr;
  float lod[kLanes] = {};
  mutable RLodPlan plan;
  float operator()(int lane, float u, float v) const {
    return sample_r_lod(*texture, *sampler, glm::vec2(u, v), lod[lane]);
  }
  // All lanes through the lane-parallel sampler (bit-identical to operator() per lane).
  template <class F>
  F lanes(V2<F> uv) const {
    return r_lod_lanes(*texture, *sampler, lod, uv, plan);
  }
};

template <class F>
struct SearchHit {
  V2<F> uv;   // hit texture coordinates (not wrapped)
  F depth;    // ray depth at the hit, [0, 1]
  F steps;    // search iterations, per lane
  F fetches;  // depth samples, per lane
};

// The bracket a linear search leaves for a refinement: the last sample outside (depth t_out,
// g_out = D - t > 0, or t_out = 0 with g_out = 0 when nothing was sampled outside) and the first
// inside (t_in, g_in = D - t <= 0).
template <class F>
struct Bracket {
  F t_out, g_out, t_in, g_in;
};

// One depth sample per active lane; inactive lanes read 0 without a fetch.
template <class F, class Depth>
inline F sample_depth(const Depth& depth, V2<F> uv, mask_t<F> active) {
  // Inactive lanes are sampled too (the sampler takes any uv) and then read as 0.
  if constexpr (requires { depth.lanes(uv); }) return select(active, depth.lanes(uv), F(0.0f));
  return per_lane(F(0.0f), [&](int i) {
    return lane(active, i) ? depth(i, lane(uv.x, i), lane(uv.y, i)) : 0.0f;
  });
}

// A march's depth sample at uv for the lanes m, over 8 lanes read two steps at a time: on a
// `fresh` step it reads uv and the next step's uv_next together and keeps the second in `ahead`
// (the two reads do not depend on each other, so the second one's texel loads are in flight
// while the first is decoded and tested: a read is a chain of dependent latencies, not a
// throughput limit); on the next step it returns the kept sample for that step's lanes, all of
// which were marching at the fresh step, so the values are the ones a read would give. A single
// lane reads every step.
template <class F, class Depth>
[[gnu::always_inline]] inline F paired_sample(const Depth& depth, bool fresh, const V2<F>& uv,
                                              const V2<F>& uv_next, mask_t<F> m, F& ahead) {
  if constexpr (lane_width < F >> 1) {
    if (!fresh) return select(m, ahead, F(0.0f));
    const F d = sample_depth(depth, uv, m);
    ahead = sample_depth(depth, uv_next, m);
    return d;
  } else {
    (void)fresh;
    (void)uv_next;
    (void)ahead;
    return sample_depth(depth, uv, m);
  }
}

namespace detail {
template <class F>
inline F count(mask_t<F> m) {
  return select(m, F(1.0f), F(0.0f));
}
}  // namespace detail

// Linear search with n steps per lane (n >= 1, a whole number; may differ per lane): samples depth
// t_i = i / n for i = 0, 1, ..., n and stops at the first sample inside; t = 1 counts as inside
// (D <= 1) whatever it reads. At most n + 1 steps and fetches. Returns the first inside sample as
// the hit; `bracket` (optional) receives the last outside and first inside samples.
template <class F, class Depth>
inline SearchHit<F> linear_search(const Depth& depth, V2<F> uv, V2<F> ds, F n, mask_t<F> active,
                                  Bracket<F>* bracket = nullptr) {
  F inv_n = F(1.0f) / n;
  F t_out(0.0f), g_out(0.0f), t_in(0.0f), g_in(0.0f);
  F steps(0.0f), fetches(0.0f);
  mask_t<F> searching = active;
  F ahead(0.0f);  // steps i and i + 1 read together (paired_sample)
  for (int i = 0; any(searching); ++i) {
    F fi = F(static_cast<float>(i));
    mask_t<F> last = fi >= n;
    F t = select(last, F(1.0f), fi * inv_n);
    const F fi1 = F(static_cast<float>(i + 1));
    const F t1 = select(fi1 >= n, F(1.0f), fi1 * inv_n);
    mask_t<F> fetch = searching;
    F d = paired_sample(depth, (i & 1) == 0, uv + ds * t, uv + ds * t1, fetch, ahead);
    F g = select(last, vmin(d - t, F(0.0f)), d - t);
    mask_t<F> inside = searching & (last | (g <= F(0.0f)));
    mask_t<F> outside = searching & !inside;
    steps += detail::count<F>(searching);
    fetches += detail::count<F>(fetch);
    t_out = select(outside, t, t_out);
    g_out = select(outside, g, g_out);
    t_in = select(inside, t, t_in);
    g_in = select(inside, g, g_in);
    searching = outside;
  }
  if (bracket) *bracket = {t_out, g_out, t_in, g_in};
  return {uv + ds * t_in, t_in, steps, fetches};
}

// m halvings of the brackets [lo, hi] of the lanes in `refine` (those with hi > lo): `inside(mid,
// lanes)` tells which midpoints are inside; hi keeps the inside end, lo the outside one. Each
// halving adds one step and `fetches_per_step` fetches per refined lane. The loop every bracketed
// search shares (binary_search here, shaders_cpp/dual_depth.h, shaders_cpp/quadric.h).
//
// Over 8 lanes two halvings are taken per round from three independent tests: the midpoint and
// both midpoints the second halving can have (of [lo, mid] and of [mid, hi]), each the value the
// sequential halving computes, then the second is picked by the first's outcome. Same brackets
// bit for bit; a third more tests, but they run side by side instead of one after the other
// (a test is a chain of dependent latencies). Counters count the sequential halvings.
//
// bisect_round is one round from halving i (it returns the next round's i); bisect runs the
// rounds, Bisector runs them one a call of step() while more(), so that two packets' halvings
// can run side by side (shaders_cpp/cone.h, step_both).
template <class F, class Inside>
inline int bisect_round(F& lo, F& hi, mask_t<F> refine, int i, int m, const F& per_lane,
                        const F& per_step, F& steps, F& fetches, const Inside& inside) {
  constexpr bool kTwoPerRound = lane_width < F >> 1;
  const F mid = (lo + hi) * F(0.5f);
  if (kTwoPerRound && i + 1 < m) {
    const F mid_lo = (lo + mid) * F(0.5f), mid_hi = (mid + hi) * F(0.5f);
    const mask_t<F> in = inside(mid, refine);
    const mask_t<F> in_lo = inside(mid_lo, refine), in_hi = inside(mid_hi, refine);
    hi = select(refine & in, mid, hi);
    lo = select(refine & !in, mid, lo);
    const F mid2 = select(in, mid_lo, mid_hi);
    const mask_t<F> in2 = (in & in_lo) | ((!in) & in_hi);
    hi = select(refine & in2, mid2, hi);
    lo = select(refine & !in2, mid2, lo);
    steps += per_lane + per_lane;
    fetches += per_step + per_step;
    return i + 2;
  }
  const mask_t<F> in = inside(mid, refine);
  hi = select(refine & in, mid, hi);
  lo = select(refine & !in, mid, lo);
  steps += per_lane;
  fetches += per_step;
  return i + 1;
}

template <class F, class Inside>
inline void bisect(F& lo, F& hi, mask_t<F> refine, int m, float fetches_per_step, F& steps,
                   F& fetches, const Inside& inside) {
  const F per_lane = detail::count<F>(refine);  // `refine` is fixed: so are the counts a step adds
  const F per_step = per_lane * F(fetches_per_step);
  for (int i = 0; i < m && any(refine);)
    i = bisect_round(lo, hi, refine, i, m, per_lane, per_step, steps, fetches, inside);
}

template <class F, class Inside>
struct Bisector {
  // User-provided, as ShadeOut's (plugins/shading.h): compiled for this namespace's target.
  Bisector(F& lo_, F& hi_, mask_t<F> refine_, int m_, float fetches_per_step, F& steps_,
           F& fetches_, const Inside& inside_)
      : lo(lo_),
        hi(hi_),
        steps(steps_),
        fetches(fetches_),
        inside(inside_),
        refine(refine_),
        per_lane(detail::count<F>(refine_)),
        per_step(per_lane * F(fetches_per_step)),
        m(m_) {}
  bool more() const { return i < m && any(refine); }
  void step() {
    i = bisect_round(lo, hi, refine, i, m, per_lane, per_step, steps, fetches, inside);
  }

  F &lo, &hi, &steps, &fetches;
  const Inside& inside;
  mask_t<F> refine;
  F per_lane, per_step;
  int m, i = 0;
};

// Binary search (m halvings) between the last outside and first inside depths of `b`: keeps the
// half whose ends straddle the surface and returns the inside end. Adds to `hit`'s counters.
template <class F, class Depth>
inline SearchHit<F> binary_search(const Depth& depth, V2<F> uv, V2<F> ds, const Bracket<F>& b,
                                  int m, mask_t<F> active, SearchHit<F> hit) {
  F lo = b.t_out, hi = b.t_in;
  bisect(lo, hi, active & (hi > lo), m, 1.0f, hit.steps, hit.fetches,
         [&](const F& mid, mask_t<F> refine) {
           return sample_depth(depth, uv + ds * mid, refine) <= mid;
         });
  hit.depth = select(active, hi, hit.depth);
  hit.uv = select(active, uv + ds * hi, hit.uv);
  return hit;
}

// Secant refinement (POM): the root of the line through the bracket's two samples,
// t = t_out + (t_in - t_out) * g_out / (g_out - g_in). No fetch; clamped to the bracket.
template <class F>
inline SearchHit<F> secant_refine(V2<F> uv, V2<F> ds, const Bracket<F>& b, mask_t<F> active,
                                  SearchHit<F> hit) {
  F den = b.g_out - b.g_in;
  mask_t<F> ok = active & (den > F(0.0f));
  F w = b.g_out / select(ok, den, F(1.0f));
  F t = clamp(b.t_out + (b.t_in - b.t_out) * w, b.t_out, b.t_in);
  t = select(ok, t, hit.depth);
  hit.depth = select(active, t, hit.depth);
  hit.uv = select(active, uv + ds * t, hit.uv);
  return hit;
}

// Relief mapping: linear search (n steps) then binary search (m steps).
template <class F, class Depth>
inline SearchHit<F> relief_search(const Depth& depth, V2<F> uv, V2<F> ds, F n, int m,
                                  mask_t<F> active) {
  Bracket<F> b;
  SearchHit<F> hit = linear_search(depth, uv, ds, n, active, &b);
  return binary_search(depth, uv, ds, b, m, active, hit);
}

// Parallax occlusion mapping: linear search (n steps) then secant refinement.
template <class F, class Depth>
inline SearchHit<F> pom_search(const Depth& depth, V2<F> uv, V2<F> ds, F n, mask_t<F> active) {
  Bracket<F> b;
  SearchHit<F> hit = linear_search(depth, uv, ds, n, active, &b);
  return secant_refine(uv, ds, b, active, hit);
}

// Steep parallax: n depth planes t_i = i / n; the hit is the first plane sample inside, with no
// refinement (the linear search itself).
template <class F, class Depth>
inline SearchHit<F> steep_parallax_search(const Depth& depth, V2<F> uv, V2<F> ds, F n,
                                          mask_t<F> active) {
  return linear_search(depth, uv, ds, n, active);
}

// Parallax mapping: one depth sample d = D(uv), hit at uv + ds * d (the ray reaching depth d).
// With offset limiting (Welsh) the offset drops the 1 / -V.z factor: uv + ds * (-V.z) * d, which
// bounds it by depth_scale * d at grazing angles. One step, one fetch.
template <class F, class Depth>
inline SearchHit<F> parallax_offset(const Depth& depth, V2<F> uv, V2<F> ds, F vz,
                                    bool offset_limiting, mask_t<F> active) {
  F d = sample_depth(depth, uv, active);
  d = saturate(d);
  V2<F> step = offset_limiting ? ds * saturate(-vz) : ds;
  SearchHit<F> hit;
  hit.uv = select(active, uv + step * d, uv);
  hit.depth = select(active, d, F(0.0f));
  hit.steps = detail::count<F>(active);
  hit.fetches = hit.steps;
  return hit;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_SEARCH_H_
