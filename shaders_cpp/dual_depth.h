// Dual-depth relief textures: Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on
// Arbitrary Polygonal Surfaces", I3D 2005, section 3.1. Two depth layers over one reference
// plane: `front` (the depth where the object starts, seen from the plane) and `back` (where it
// ends). A point at depth t is inside the object when front <= t <= back; texels the object does
// not cover read front = 1, back = 0 (never inside). Written once over the lane type F (float or
// F8), with the conventions of shaders_cpp/search.h (a ray at depth t is at uv + ds * t).

#if defined(RELIEF_SHADERS_CPP_DUAL_DEPTH_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_DUAL_DEPTH_H_
#undef RELIEF_SHADERS_CPP_DUAL_DEPTH_H_
#else
#define RELIEF_SHADERS_CPP_DUAL_DEPTH_H_
#endif

#include "shaders_cpp/search.h"
#include "shaders_cpp/shadow.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// Texture fetches one read of a depth source costs: 1, or the source's own kFetches (0 for a
// constant layer such as relief_dual's back layer when no map is bound).
template <class D>
constexpr float read_cost() {
  if constexpr (requires { D::kFetches; })
    return D::kFetches;
  else
    return 1.0f;
}

// Inside the object between the two layers.
template <class F>
inline mask_t<F> dual_inside(F front, F back, F t) {
  return (front <= t) & (t <= back);
}

// Linear search with n steps per lane (t_i = i / n, i = 0..n) for the first sample inside, then m
// binary halvings between the last outside and the first inside sample. Unlike the single-layer
// search, depth 1 is not inside by itself: a ray that finds no inside sample misses the object
// (returned in `miss`, its hit left at uv, depth 0). One step reads both layers (read_cost each),
// two steps at a time over 8 lanes as linear_search does (paired_sample: the same values).
template <class F, class Front, class Back>
inline SearchHit<F> dual_depth_search(const Front& front, const Back& back, V2<F> uv, V2<F> ds, F n,
                                      int m, mask_t<F> active, mask_t<F>& miss) {
  constexpr float kPerStep = read_cost<Front>() + read_cost<Back>();
  const F inv_n = F(1.0f) / n;
  F t_out(0.0f), t_in(0.0f), steps(0.0f), fetches(0.0f);
  F front_ahead(0.0f), back_ahead(0.0f);  // step i + 1's samples, read with step i's
  mask_t<F> searching = active, found = false_mask<F>();
  for (int i = 0; any(searching); ++i) {
    const F fi = F(static_cast<float>(i));
    const mask_t<F> last = fi >= n;
    const F t = select(last, F(1.0f), fi * inv_n);
    const F fi1 = F(static_cast<float>(i + 1));
    const F t1 = select(fi1 >= n, F(1.0f), fi1 * inv_n);
    const V2<F> p = uv + ds * t, p1 = uv + ds * t1;
    const bool fresh = (i & 1) == 0;
    const F f = paired_sample(front, fresh, p, p1, searching, front_ahead);
    const F b = paired_sample(back, fresh, p, p1, searching, back_ahead);
    const mask_t<F> in = searching & dual_inside(f, b, t);
    steps += detail::count<F>(searching);
    fetches += detail::count<F>(searching) * F(kPerStep);
    t_in = select(in, t, t_in);
    t_out = select(searching & !in, t, t_out);
    found = found | in;
    searching = searching & !in & !last;
  }
  F lo = t_out, hi = t_in;
  bisect(lo, hi, found & (hi > lo), m, kPerStep, steps, fetches,
         [&](const F& mid, mask_t<F> refine) {
           const V2<F> p = uv + ds * mid;
           return dual_inside(sample_depth(front, p, refine), sample_depth(back, p, refine), mid);
         });
  miss = active & !found;
  const F t_hit = select(found, hi, F(0.0f));
  return {uv + ds * t_hit, t_hit, steps, fetches};
}

// Hard self-shadow of the hit (uv, t) toward a light with tangent-space step dl and L.z = lz: the
// ray (uv + dl * s, t - s), s = 1/n, 2/n, ... < t, is blocked where it is inside the object by
// more than `bias` (front < t - s - bias and t - s + bias < back). Visibility 1 lit, 0 blocked
// (or lz <= 0); inactive lanes 1. Both layers read per step (read_cost each).
template <class F, class Front, class Back>
inline ShadowResult<F> dual_depth_shadow(const Front& front, const Back& back, V2<F> uv, F t,
                                         V2<F> dl, F lz, int n, float bias, mask_t<F> active) {
  constexpr float kPerStep = read_cost<Front>() + read_cost<Back>();
  F steps(0.0f), fetches(0.0f);
  const F inv_n = F(1.0f) / F(static_cast<float>(n));
  const mask_t<F> lit_side = lz > F(0.0f);
  F vis = select(active & !lit_side, F(0.0f), F(1.0f));
  mask_t<F> marching = active & lit_side;
  for (int i = 1; any(marching); ++i) {
    const F s = F(static_cast<float>(i)) * inv_n;
    marching = marching & (s < t);
    if (none(marching)) break;
    const V2<F> p = uv + dl * s;
    const F depth = t - s;
    const mask_t<F> blocked = marching & (sample_depth(front, p, marching) < depth - F(bias)) &
                              (sample_depth(back, p, marching) > depth + F(bias));
    steps += detail::count<F>(marching);
    fetches += detail::count<F>(marching) * F(kPerStep);
    vis = select(blocked, F(0.0f), vis);
    marching = marching & !blocked;
  }
  return {vis, steps, fetches};
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_DUAL_DEPTH_H_
