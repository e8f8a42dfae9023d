// Self-shadowing through the height field, over the lane type F (float or F8):
//   hard shadows: Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal
//     Surfaces", I3D 2005 (section 3, figure 10: is there a surface point between the light and
//     the shaded point?);
//   the upward march and its soft variant: McGuire and McGuire, "Steep Parallax Mapping", I3D 2005
//     poster ("the shadow loop is the same ... except we increase height each iteration").
//
// Conventions: see shaders_cpp/ray.h. The shaded point is the hit (uv, t). L is the unit
// tangent-space direction toward the light (L.z > 0 above the surface); dl = light_step(L,
// depth_scale). The shadow ray is (uv + dl * s, t - s) for s in (0, t]: it leaves the surface
// upward and is above everything once its depth reaches 0. A sample occludes when the surface is
// above the ray by more than `bias`: D(uv + dl * s) < t - s - bias.

#if defined(RELIEF_SHADERS_CPP_SHADOW_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_SHADOW_H_
#undef RELIEF_SHADERS_CPP_SHADOW_H_
#else
#define RELIEF_SHADERS_CPP_SHADOW_H_
#endif

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct ShadowResult {
  F visibility;  // 1 lit, 0 in shadow (soft: in between)
  F steps;       // shadow-ray iterations, per lane
  F fetches;     // depth samples, per lane
};

// Marches up from the hit in depth steps of 1 / n (samples at s = 1/n, 2/n, ... below t, so a
// point at depth t takes at most ceil(t * n) - 1 steps). Hard (kSoft = false): visibility 0 at the
// first occluding sample, and the lane stops. Soft (kSoft = true, McGuire's variant): visibility
// = 1 - saturate(softness * max_i (t - s_i - D_i) * (1 - s_i / t)), every sample taken. Lanes with
// L.z <= 0 (light below the surface) get visibility 0 and take no step; inactive lanes get 1.
template <bool kSoft = false, class F, class Depth>
inline ShadowResult<F> self_shadow(const Depth& depth, V2<F> uv, F t, V2<F> dl, F lz, int n,
                                   float bias, mask_t<F> active, float softness = 4.0f) {
  F inv_n = F(1.0f) / F(static_cast<float>(n));
  mask_t<F> lit_side = lz > F(0.0f);
  F vis = select(active & !lit_side, F(0.0f), F(1.0f));
  F occl(0.0f);
  F steps(0.0f), fetches(0.0f);
  mask_t<F> marching = active & lit_side;
  F inv_t = F(1.0f) / vmax(t, F(1e-30f));
  F ahead(0.0f);  // steps i and i + 1 (odd i) read together (search.h paired_sample)
  for (int i = 1; any(marching); ++i) {
    F s = F(static_cast<float>(i)) * inv_n;
    marching = marching & (s < t);
    if (none(marching)) break;
    const F s1 = F(static_cast<float>(i + 1)) * inv_n;
    F d = paired_sample(depth, (i & 1) != 0, uv + dl * s, uv + dl * s1, marching, ahead);
    F above = (t - s) - d;  // > 0: surface above the ray
    steps += select(marching, F(1.0f), F(0.0f));
    fetches += select(marching, F(1.0f), F(0.0f));
    if constexpr (kSoft) {
      occl = select(marching, vmax(occl, (above - F(bias)) * (F(1.0f) - s * inv_t)), occl);
    } else {
      mask_t<F> blocked = marching & (above > F(bias));
      vis = select(blocked, F(0.0f), vis);
      marching = marching & !blocked;
    }
  }
  if constexpr (kSoft) {
    vis = select(active & lit_side, F(1.0f) - saturate(occl * F(softness)), vis);
  }
  return {vis, steps, fetches};
}

// Self-shadowing approximated as darkening that grows with depth (Lengyel, Praun, Finkelstein and
// Hoppe, "Real-time fur over arbitrary surfaces", I3D 2001; the trick the steep parallax poster's
// "Fur and Grass" borrows instead of shadow rays): 1 at the tips (depth 0), 1 - strength at the
// deepest point (depth 1). No depth reads. Steep parallax's `shadow=depth` and `shells` both use
// it, for each light's visibility and for the indirect light.
template <class F>
inline F depth_darkening(const F& depth, float strength) {
  return F(1.0f) - F(strength) * saturate(depth);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_SHADOW_H_
