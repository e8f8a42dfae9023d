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
//
// Cone sources: any object with `float operator()(int lane, float u, float v) const` returning
// the ratio that lane's ray may use at (u, v). TextureCone reads the first channel of a cone map;
// QuadTextureCone reads the four quad-directional ratios (+u, -u, +v, -v) and returns, for a ray
// whose uv direction has signs (su, sv), max(r[su], r[sv]): the ray stays in both closed
// half-planes, so either ratio is safe and the wider one is used.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/texture.h"
#include "shaders_cpp/lanes.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/vec.h"

namespace relief {

// The nearest-texel depth field the relaxed cones are defined on: a TextureDepth whose sampler
// is `sampler` with nearest filtering (kept here, so the reader can be copied freely).
struct NearestTextureDepth {
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[8] = {};
  mutable RLodPlan plan;  // as TextureDepth's
  float operator()(int lane, float u, float v) const {
    return sample_r_lod(*texture, sampler, glm::vec2(u, v), lod[lane]);
  }
  template <class F> F lanes(V2<F> uv) const {
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
  float lod[8] = {};
  mutable RLodPlan plan;  // as TextureDepth's
  float operator()(int lane, float u, float v) const {
    return sample_lod(*texture, sampler, glm::vec2(u, v), lod[lane]).x;
  }
  // sample_r_lod is sample_lod's first channel for every format.
  template <class F> F lanes(V2<F> uv) const {
    return r_lod_lanes(*texture, sampler, lod, uv, plan);
  }
};

// Quad-directional cones: channel cu (0: +u, 1: -u) and cv (2: +v, 3: -v) per lane, set by aim().
struct QuadTextureCone {
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[8] = {};
  int cu[8] = {}, cv[8] = {};
  // Picks each lane's pair of channels from the signs of its uv direction.
  template <class F>
  void aim(V2<F> ds) {
    for (int i = 0; i < lane_width<F>; ++i) {
      cu[i] = lane(ds.x, i) >= 0.0f ? 0 : 1;
      cv[i] = lane(ds.y, i) >= 0.0f ? 2 : 3;
    }
  }
  float operator()(int lane, float u, float v) const {
    const glm::vec4 r = sample_lod(*texture, sampler, glm::vec2(u, v), lod[lane]);
    const float a = r[cu[lane]], b = r[cv[lane]];
    return a < b ? b : a;
  }
};

// What a cone step reads at p: the depth and the cone ratio, for the marching lanes; counts one
// step and two fetches per marching lane.
template <class F> struct ConeTexel {
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

// Cone stepping (n steps at most) from depth 0: the last position reached is the hit (for
// conservative cones, a point at or above the first intersection once the cones are exact; it
// has converged onto the surface only if enough steps were taken). t_max <= 1 per lane caps the
// march. Counters: one step and two fetches per iteration of a marching lane.
template <class F, class Depth, class Cone>
inline SearchHit<F> cone_march(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds, int n,
                               F t_max, mask_t<F> active) {
  const F ray_ratio = vsqrt(ds.x * ds.x + ds.y * ds.y);
  F t(0.0f), steps(0.0f), fetches(0.0f);
  mask_t<F> marching = active & (t < t_max);
  for (int i = 0; i < n && any(marching); ++i) {
    const ConeTexel<F> c = sample_cone_texel(depth, cone, uv + ds * t, marching, steps, fetches);
    const F r = c.ratio;
    const F h = c.depth - t;
    marching = marching & (h > F(0.0f));
    // distance to the cone's surface along the ray (equation 3)
    const F den = ray_ratio + r;
    const mask_t<F> moves = marching & (den > F(0.0f));
    const F step = r * h / select(moves, den, F(1.0f));
    t = select(moves, vmin(t + step, t_max), t);
    marching = marching & (t < t_max);
  }
  return {uv + ds * t, t, steps, fetches};
}

// Conservative (Dummer) or quad-directional cone stepping: the march itself is the search.
template <class F, class Depth, class Cone>
inline SearchHit<F> cone_search(const Depth& depth, const Cone& cone, V2<F> uv, V2<F> ds, int n,
                                mask_t<F> active, F t_max = F(1.0f)) {
  return cone_march(depth, cone, uv, ds, n, t_max, active);
}

// Relaxed cone stepping (n steps) then m halvings of the segment from H to K (figure 18-10): K
// is where the march stopped (depth t_K, inside the surface if the ray pierced it) and H the
// point half-way between the fragment and K (depth t_K / 2). The march reads `march_depth`, the
// nearest-texel field the relaxed cones are defined on (bake/cone_map.h), the binary search
// `depth` (the material's filtering). A lane whose march never got inside converges to K.
// Returns the inside end of the last bracket, as binary_search does.
template <class F, class MarchDepth, class Depth, class Cone>
inline SearchHit<F> relaxed_cone_search(const MarchDepth& march_depth, const Depth& depth,
                                        const Cone& cone, V2<F> uv, V2<F> ds, int n, int m,
                                        mask_t<F> active, F t_max = F(1.0f)) {
  SearchHit<F> hit = cone_march(march_depth, cone, uv, ds, n, t_max, active);
  const Bracket<F> hk{hit.depth * F(0.5f), F(0.0f), hit.depth, F(0.0f)};
  return binary_search(depth, uv, ds, hk, m, active, hit);
}

template <class F>
struct ConeShadow {
  F visibility;  // 1 lit, 0 shadowed
  F steps;       // iterations of the light ray's search, per lane
  F fetches;     // texture samples, per lane
};

// Hard self-shadow with the view ray's own search (Policarpo et al. 2005, figure 10: does the
// light ray reach the shaded point before any other surface point?), with the exact reference's
// bias semantics (shadowed where the surface is above the shadow ray by more than `bias`): the
// light ray lowered by `bias` enters the depth range at E = uv + dl t_max, t_max = t - bias, and
// runs down along -dl to depth t_max; `search(E, -dl, t_max, active)` is the technique's march
// capped at t_max. The point is shadowed where the march stops before t_max: it reached the
// surface (or, out of steps, stalled on the way; conservative cones never pass an occluder, so
// they err only towards shadow). Lanes with L.z <= 0 get visibility 0 and take no step; inactive
// lanes get 1.
template <class F, class Search>
inline ConeShadow<F> light_ray_shadow(V2<F> uv, F t, V2<F> dl, F lz, float bias, mask_t<F> active,
                                      Search&& search) {
  const mask_t<F> lit_side = lz > F(0.0f);
  const F t_max = t - F(bias);
  const mask_t<F> trace = active & lit_side & (t_max > F(0.0f));
  F vis = select(active & !lit_side, F(0.0f), F(1.0f));
  ConeShadow<F> r{vis, F(0.0f), F(0.0f)};
  if (none(trace)) return r;
  const V2<F> entry = uv + dl * t_max;
  const V2<F> down{F(0.0f) - dl.x, F(0.0f) - dl.y};
  const SearchHit<F> h = search(entry, down, t_max, trace);
  r.visibility = select(trace & (h.depth < t_max), F(0.0f), vis);
  r.steps = h.steps;
  r.fetches = h.fetches;
  return r;
}

}  // namespace relief
