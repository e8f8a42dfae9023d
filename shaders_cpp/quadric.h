// Relief mapping with correct silhouettes: the view ray against a height field deformed onto the
// per-vertex quadric z = a x^2 + b y^2, in texture space. Oliveira and Policarpo, "An Efficient
// Representation for Surface Details", UFRGS RP-351, 2005 (the quadric-silhouettes paper):
// section 3.1 (equation 6, the ray-quadric distance along U), 3.2 (equation 7, the vertical
// distance), 3.3 (the search range [0, t_max]; rays that come back to depth 0 are silhouette),
// 3.4 (equations 8 and 9: the quadric and the ray in texture space).
//
// Conventions. Tangent space as in shaders_cpp/ray.h (V unit, V.z < 0 into the surface). Texture
// space: x along T in uv units, y along B in uv units, z = depth in depth-map units (positive into
// the surface), so object = (x sx, y sy, z sz) with sx, sy the tile scale (world units per uv) and
// sz the relief's full depth in world units. The quadric is in the same depth convention (z along
// -N, a, b > 0 on a convex surface; scene/mesh_prep.h) and becomes z = alpha x^2 + beta y^2 with
// alpha = a sx^2 / sz, beta = b sy^2 / sz (equation 8). The ray is P(t) = dir t, dir = Vt / |Vt|,
// Vt = (V.x / sx, V.y / sy, -V.z / sz) (equation 9), -V.z clamped to at least kMinRayCos so every
// quantity stays finite. A ray point is `inside` the relief when its distance D(t) below the
// quadric is at least the depth map's value there.

#if defined(RELIEF_SHADERS_CPP_QUADRIC_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_QUADRIC_H_
#undef RELIEF_SHADERS_CPP_QUADRIC_H_
#else
#define RELIEF_SHADERS_CPP_QUADRIC_H_
#endif

#include "shaders_cpp/cone.h"
#include "shaders_cpp/ray.h"
#include "shaders_cpp/search.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

enum class QuadricDistance { kApproximate, kAccurate };

template <class F>
struct QuadricRay {
  V3<F> dir;         // unit, texture space, dir.z > 0
  V3<F> up;          // U (tangent space: unit, perpendicular to the ray, in the plane of the
                     // ray and the normal, U.z <= 0) in texture units per depth unit
  F alpha, beta;     // equation 8
  F t_max;           // section 3.3
  mask_t<F> bottom;  // t_max is where the ray reaches depth 1 (else where it returns to 0)
  F world_per_t;     // world distance along the view ray per unit of t
};

namespace detail {
// The smallest root in (0, inf) of q2 t^2 + q1 t + q0 = 0, or `none` (numerically stable form).
template <class F>
inline F smallest_positive_root(F q2, F q1, F q0, F none) {
  const F disc = q1 * q1 - F(4.0f) * q2 * q0;
  const mask_t<F> real = disc >= F(0.0f);
  const F sq = vsqrt(vmax(disc, F(0.0f)));
  // q = -(q1 + sign(q1) sqrt(disc)) / 2; roots q / q2 and q0 / q
  const F q = (q1 + select(q1 < F(0.0f), -sq, sq)) * F(-0.5f);
  const mask_t<F> qok = vabs(q) > F(1e-30f), q2ok = vabs(q2) > F(1e-30f);
  const F r1 = select(qok & q2ok, q / select(q2ok, q2, F(1.0f)), none);
  const F r2 = select(qok, q0 / select(qok, q, F(1.0f)), none);
  F best = none;
  best = select(real & (r1 > F(0.0f)) & (r1 < best), r1, best);
  best = select(real & (r2 > F(0.0f)) & (r2 < best), r2, best);
  return best;
}
}  // namespace detail

// The ray-quadric distance at t by equation 7: D = P.z - (alpha P.x^2 + beta P.y^2).
template <class F>
inline F quadric_distance_vertical(const QuadricRay<F>& r, F t) {
  const F px = r.dir.x * t, py = r.dir.y * t;
  return r.dir.z * t - (r.alpha * px * px + r.beta * py * py);
}

// The ray-quadric distance at t by equation 6: s with P + U s on the quadric, taken as
// -2C / (B + sqrt(B^2 - 4AC)) (the same root, finite as A -> 0); equation 7 where the
// discriminant is negative, or where B + sqrt(...) <= 1e-6 (no finite root along U: a plane seen
// along its normal). Signed: negative above the quadric.
template <class F>
inline F quadric_distance_accurate(const QuadricRay<F>& r, F t) {
  const V3<F> p = r.dir * t;
  const V3<F>& u = r.up;
  const F A = r.alpha * u.x * u.x + r.beta * u.y * u.y;
  const F B = F(2.0f) * (r.alpha * p.x * u.x + r.beta * p.y * u.y) - u.z;
  const F C = r.alpha * p.x * p.x + r.beta * p.y * p.y - p.z;
  const F disc = B * B - F(4.0f) * A * C;
  const F den = B + vsqrt(vmax(disc, F(0.0f)));
  const mask_t<F> ok = (disc >= F(0.0f)) & (den > F(1e-6f));
  const F s = F(-2.0f) * C / select(ok, den, F(1.0f));
  return select(ok, s, quadric_distance_vertical(r, t));
}

template <QuadricDistance kD, class F>
inline F quadric_distance(const QuadricRay<F>& r, F t) {
  if constexpr (kD == QuadricDistance::kAccurate)
    return quadric_distance_accurate(r, t);
  else
    return quadric_distance_vertical(r, t);
}

// The texture-space ray of a fragment: V its tangent-space view direction (unit, V.z < 0 into the
// surface), q = (a, b) its quadric and tile = (sx, sy) its tile size in world units, sz the
// relief depth in world units (all > 0; tiny values are clamped to 1e-12).
template <QuadricDistance kD, class F>
inline QuadricRay<F> make_quadric_ray(V3<F> V, V2<F> q, V2<F> tile, F sz) {
  QuadricRay<F> r;
  const F tiny(1e-12f);
  const F sx = vmax(tile.x, tiny), sy = vmax(tile.y, tiny), s_z = vmax(sz, tiny);
  const V3<F> vt(V.x / sx, V.y / sy, vmax(-V.z, F(kMinRayCos)) / s_z);
  const F len = length(vt);
  r.dir = vt * (F(1.0f) / len);
  r.world_per_t = F(1.0f) / len;
  r.alpha = q.x * sx * sx / s_z;
  r.beta = q.y * sy * sy / s_z;
  // U (equation 4) is perpendicular to the view ray in tangent space, where the paper defines
  // it: the up direction (0, 0, -1) minus its part along the ray, normalised (any horizontal
  // unit vector when the ray is vertical). Stored in texture units per depth unit of s,
  // (Ux sz / sx, Uy sz / sy, Uz), so that equation 6 evaluated in texture space with it gives
  // the tangent-space distance divided by sz. (U taken perpendicular to the texture-space ray
  // instead measures a different, scale-dependent distance: with sz much smaller than sx it runs
  // almost horizontally and reached the quadric's wall long before the relief's depth, which
  // discarded most of a sphere as misses.)
  const V3<F> vo = normalize(V3<F>(V.x, V.y, vmax(-V.z, F(kMinRayCos))));
  const V3<F> up0(F(0.0f), F(0.0f), F(-1.0f));
  const V3<F> uo = normalize_or(up0 - vo * dot(up0, vo), V3<F>(F(1.0f), F(0.0f), F(0.0f)));
  r.up = V3<F>(uo.x * (s_z / sx), uo.y * (s_z / sy), uo.z);
  // section 3.3: the smallest t > 0 with D = 1 (bottom) or D = 0 (return to the surface)
  const V3<F>& d = r.dir;
  const F k = r.alpha * d.x * d.x + r.beta * d.y * d.y;
  const F none(3.0e38f);
  const F t_return = select(k > F(1e-30f), d.z / vmax(k, F(1e-30f)), none);
  F t_bottom;
  if constexpr (kD == QuadricDistance::kAccurate) {
    // s = 1 in equation 5: k t^2 + (2 (alpha dx Ux + beta dy Uy) - dz) t + (A - Uz) = 0
    const V3<F>& u = r.up;
    const F A = r.alpha * u.x * u.x + r.beta * u.y * u.y;
    const F m = F(2.0f) * (r.alpha * d.x * u.x + r.beta * d.y * u.y) - d.z;
    t_bottom = detail::smallest_positive_root(k, m, A - u.z, none);
  } else {
    // D = 1 in equation 7: k t^2 - dz t + 1 = 0
    t_bottom = detail::smallest_positive_root(k, -d.z, F(1.0f), none);
  }
  r.bottom = t_bottom <= t_return;
  r.t_max = vmin(t_bottom, t_return);
  // no root at all (cannot happen with dz > 0, guarded anyway): the planar range
  r.bottom = r.bottom | (r.t_max >= none);
  r.t_max = select(r.t_max >= none, F(1.0f) / d.z, r.t_max);
  return r;
}

// The result of a search along a quadric ray: the hit (uv, distance below the quadric in depth
// units, steps, fetches), its ray parameter t, and the lanes whose ray left the relief without
// a hit (silhouette: discard).
template <class F>
struct QuadricHit {
  SearchHit<F> hit;
  F t;
  mask_t<F> miss;
};

// Linear search over t_i = t_max i / n, i = 0..n (n >= 1 per lane), stopping at the first inside
// sample (depth map <= D(t)); at t_max a bottom ray is inside whatever it reads, a returning ray
// only if the map reads <= 0 there. Then m binary halvings of the last bracket. Lanes outside
// `active` do nothing and return t = 0 at uv.
template <QuadricDistance kD, class F, class Depth>
inline QuadricHit<F> quadric_search(const Depth& depth, V2<F> uv, const QuadricRay<F>& r, F n,
                                    int m, mask_t<F> active) {
  const F dt = r.t_max / n;
  const V2<F> duv(r.dir.x, r.dir.y);
  F t_out(0.0f), t_in(0.0f);
  F steps(0.0f), fetches(0.0f);
  mask_t<F> searching = active, found = false_mask<F>();
  F ahead(0.0f);  // steps i and i + 1 read together (search.h paired_sample)
  for (int i = 0; any(searching); ++i) {
    const F fi = F(static_cast<float>(i));
    const mask_t<F> last = fi >= n;
    const F t = select(last, r.t_max, fi * dt);
    const F fi1 = F(static_cast<float>(i + 1));
    const F t1 = select(fi1 >= n, r.t_max, fi1 * dt);
    const F h = paired_sample(depth, (i & 1) == 0, uv + duv * t, uv + duv * t1, searching, ahead);
    const F D = quadric_distance<kD>(r, t);
    const mask_t<F> in = (h <= D) | (last & r.bottom);
    const mask_t<F> hit = searching & in;
    steps += detail::count<F>(searching);
    fetches += detail::count<F>(searching);
    t_in = select(hit, t, t_in);
    t_out = select(searching & !in, t, t_out);
    found = found | hit;
    searching = searching & !in & !last;
  }
  // binary search between the last outside and the first inside sample
  F lo = t_out, hi = t_in;
  bisect(lo, hi, found & (hi > lo), m, 1.0f, steps, fetches, [&](const F& mid, mask_t<F> refine) {
    return sample_depth(depth, uv + duv * mid, refine) <= quadric_distance<kD>(r, mid);
  });
  QuadricHit<F> out;
  out.t = select(found, hi, F(0.0f));
  out.miss = active & !found;
  out.hit.uv = uv + duv * out.t;
  out.hit.depth = clamp(quadric_distance<kD>(r, out.t), F(0.0f), F(1.0f));
  out.hit.steps = steps;
  out.hit.fetches = fetches;
  return out;
}

// Relaxed cone stepping on the quadric-deformed height field (`search=relaxed_cone`), a
// combination neither paper has: the relaxed cone map of the flat field (Policarpo and Oliveira,
// GPU Gems 3 ch. 18; bake/cone_map.h: uv distance per unit of depth) steps the quadric ray.
// Relative to the deformed field the ray is a parabola: its depth below the quadric, by
// equation 7, is D(t) = dz t - k t^2 with k = alpha dx^2 + beta dy^2, while it moves rho = |dxy|
// in uv per unit of t. From a point outside the surface with gap h = map - D(t) > 0, the step
// dt to the boundary of the texel's cone (apex on the surface, opening upward, ratio r) solves
//   rho dt = r (h - (D'(t) dt - k dt^2)),   D'(t) = dz - 2 k t,
// which is the chapter's equation 3 (dt = r h / (rho + r dz)) when k = 0. No positive root
// (a ray rising faster than the cone opens): the step goes to t_max; a zero ratio: no step. The
// gap h uses the plugin's distance (equation 6 or 7); the step always the vertical parabola.
// The march, its fallback and the halvings all read `depth`, the material's filtering (issue 22:
// marching the nearest-texel field and halving the bilinear one gave brackets that were not
// brackets, so hits in the air), and end bracket-safe as the flat cone family does
// (shaders_cpp/cone.h, cone_finish): a lane stops at the first sample inside (map <= D, or t_max
// on a bottom ray), at t_max (a returning ray: outside there is a silhouette miss), or after n
// steps. A lane the n steps left outside takes k more cone steps of at least min((t_max - t) / k,
// view_floor) (half a texel along the ray; ramped up from view_floor / 2^16 over the first
// fallback_ramp(k), cone.h ramped_floor), then k even samples over what is left of [t, t_max);
// still outside at t_max, a bottom ray is inside there (depth 1), a returning ray a miss. Lanes
// found inside get m halvings of [last outside sample, first inside sample]: every hit is a
// sample of `depth` at or under the deformed surface. Counters: one step and two fetches per
// cone step (depth and cone), one each per even sample and per halving. k >= 1.
template <QuadricDistance kD, class F, class Depth, class Cone>
inline QuadricHit<F> quadric_relaxed_cone_search(const Depth& depth, const Cone& cone, V2<F> uv,
                                                 const QuadricRay<F>& r, int n, int k, int m,
                                                 F view_floor, mask_t<F> active) {
  const V2<F> duv(r.dir.x, r.dir.y);
  const F rho = vsqrt(duv.x * duv.x + duv.y * duv.y);
  const F kk = r.alpha * r.dir.x * r.dir.x + r.beta * r.dir.y * r.dir.y;
  const F none(3.0e38f);
  F t(0.0f), t_out(0.0f), steps(0.0f), fetches(0.0f);
  mask_t<F> marching = active, found = false_mask<F>();
  // one cone step from t for the lanes in `go`, at least `floor`; returns whether t was inside
  const auto cone_step = [&](mask_t<F>& go, F floor) {
    const ConeTexel<F> c = sample_cone_texel(depth, cone, uv + duv * t, go, steps, fetches);
    const mask_t<F> end = t >= r.t_max;
    const F h = c.depth - quadric_distance<kD>(r, t);
    const mask_t<F> in = go & ((h <= F(0.0f)) | (end & r.bottom));
    found = found | in;
    go = go & !in & !end;
    t_out = select(go, t, t_out);
    // the smallest dt > 0 on the cone's boundary: r k dt^2 - (rho + r D') dt + r h = 0
    const F slope = r.dir.z - F(2.0f) * kk * t;
    const F root = detail::smallest_positive_root(c.ratio * kk, F(0.0f) - (rho + c.ratio * slope),
                                                  c.ratio * h, none);
    const F dt = select(c.ratio > F(0.0f), root, F(0.0f));  // a zero cone: no step (equation 3)
    t = select(go, vmin(t + vmax(dt, floor), r.t_max), t);
  };
  for (int i = 0; i < n && any(marching); ++i) cone_step(marching, F(0.0f));
  // the fallback for lanes the march left outside: floored cone steps, then even samples
  const float inv_k = 1.0f / static_cast<float>(k);
  const F floor = vmin((r.t_max - t) * F(inv_k), view_floor);
  const int ramp = fallback_ramp(k);
  for (int j = 0; j < k && any(marching); ++j)
    cone_step(marching, ramped_floor(j, ramp, floor, view_floor));
  const F s0 = t, rest = r.t_max - t;
  for (int j = 0; j < k && any(marching); ++j) {
    t = select(marching, s0 + rest * F(static_cast<float>(j) * inv_k), t);
    const F d = sample_depth(depth, uv + duv * t, marching);
    steps += detail::count<F>(marching);
    fetches += detail::count<F>(marching);
    const mask_t<F> in = marching & (d <= quadric_distance<kD>(r, t));
    found = found | in;
    marching = marching & !in;
    t_out = select(marching, t, t_out);
  }
  // still outside: t_max closes a bottom ray's bracket (depth 1 is under every surface); a
  // returning ray left the relief without a hit
  const mask_t<F> at_end = marching & r.bottom;
  t = select(marching, r.t_max, t);
  found = found | at_end;
  F lo = t_out, hi = t;
  bisect(lo, hi, found & (hi > lo), m, 1.0f, steps, fetches, [&](const F& mid, mask_t<F> refine) {
    return sample_depth(depth, uv + duv * mid, refine) <= quadric_distance<kD>(r, mid);
  });
  QuadricHit<F> out;
  out.t = select(found, hi, F(0.0f));
  out.miss = active & !found;
  out.hit.uv = uv + duv * out.t;
  out.hit.depth = clamp(quadric_distance<kD>(r, out.t), F(0.0f), F(1.0f));
  out.hit.steps = steps;
  out.hit.fetches = fetches;
  return out;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_QUADRIC_H_
