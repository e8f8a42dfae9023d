// Ambient occlusion from the height field (issue 24), over the lane type F (float or F8): a
// horizon-based estimate in tangent space at the relief hit, in the spirit of horizon-based
// ambient occlusion (Bavoil, Sainz and Dimitrov, "Image-Space Horizon-Based Ambient Occlusion",
// SIGGRAPH 2008 talk) but marched over the depth map instead of a depth buffer.
//
// Conventions: see shaders_cpp/ray.h. From the hit's uv, `rays` azimuth directions evenly spaced
// (angle 2 pi k / rays, fixed and deterministic), kHeightAoSteps samples each at t = radius *
// (j + 1) / kHeightAoSteps uv units. d0 is the depth map at the hit itself (read, not the
// search's hit depth: a layered search's hit can lie up to a layer below the surface). A
// direction's horizon tangent is h = max(0, max_j (d0 - D(sample_j) - kHeightAoBias) *
// depth_scale / t_j) (relief height over distance, both in uv units); it leaves the fraction
// 1 - sin(atan h) = 1 - h / sqrt(1 + h^2) of the cosine-weighted sky unoccluded on its side; AO is
// the mean over the directions. kHeightAoBias keeps a flat map (equal texels, bilinear rounding)
// at AO exactly 1. The depth reads go through the search's depth source (its LOD).
// gl/shaders/relief_shell.glsl height_field_ao is the twin.

#if defined(RELIEF_SHADERS_CPP_HEIGHT_AO_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_HEIGHT_AO_H_
#undef RELIEF_SHADERS_CPP_HEIGHT_AO_H_
#else
#define RELIEF_SHADERS_CPP_HEIGHT_AO_H_
#endif

#include <cmath>

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

inline constexpr int kHeightAoSteps = 4;
inline constexpr float kHeightAoBias = 1.0f / 1024.0f;  // depth units
// Horizon tangents are clamped here (sin = 1 - 5e-9): h * h stays finite for any radius > 0.
inline constexpr float kHeightAoMaxTangent = 1e4f;

template <class F>
struct HeightAoResult {
  F ao;       // in [0, 1]; 1 unoccluded
  F fetches;  // depth samples, per lane
};

// AO of the lanes `active` at uv (the hit) over `rays` directions of radius `radius` uv units;
// depth_scale is the relief height in uv units. Inactive lanes, rays <= 0 and radius <= 0 give
// AO 1 without a fetch.
template <class F, class Depth>
inline HeightAoResult<F> height_field_ao(const Depth& depth, V2<F> uv, int rays, float radius,
                                         float depth_scale, mask_t<F> active) {
  if (rays <= 0 || !(radius > 0.0f) || none(active)) return {F(1.0f), F(0.0f)};
  const F d0 = sample_depth(depth, uv, active);
  F sum(0.0f);
  for (int k = 0; k < rays; ++k) {
    const double a = 6.283185307179586 * k / rays;
    const V2<F> dir(F(static_cast<float>(std::cos(a))), F(static_cast<float>(std::sin(a))));
    F h(0.0f);
    for (int j = 1; j <= kHeightAoSteps; ++j) {
      const float t = radius * static_cast<float>(j) / static_cast<float>(kHeightAoSteps);
      const float slope = std::fmin(depth_scale / t, 1e30f);  // finite for a denormal t
      const F d = sample_depth(depth, uv + dir * F(t), active);
      h = vmax(h, (d0 - d - F(kHeightAoBias)) * F(slope));
    }
    h = vmin(h, F(kHeightAoMaxTangent));
    sum += F(1.0f) - h / vsqrt(F(1.0f) + h * h);
  }
  const F ao = select(active, sum / F(static_cast<float>(rays)), F(1.0f));
  const F n = F(static_cast<float>(1 + rays * kHeightAoSteps));
  return {ao, select(active, n, F(0.0f))};
}

// The factor height-field AO multiplies SurfaceColor::occlusion by: 1 - strength * (1 - ao).
template <class F>
inline F height_ao_factor(const F& ao, float strength) {
  return F(1.0f) - F(strength) * (F(1.0f) - ao);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_HEIGHT_AO_H_
