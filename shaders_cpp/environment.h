// Image-based light lookups over lanes (shaders_cpp/environment_maps.h holds the data and its
// conventions): irradiance from spherical harmonics, prefiltered specular radiance from the
// octahedral chain and the split-sum BRDF table. Every operation is a lane operation of lanes.h
// or a lane-parallel textureLod of the maps' R32F channel planes (the RGBA16F maps' texels, which
// that sampler does not serve, split by channel: environment_maps.h), so float and the lane types
// agree bit for bit, and the texture reads are GL's textureLod on the same levels (texture.h).
// Per-target header (lanes.h says how).
#if defined(RELIEF_SHADERS_CPP_ENVIRONMENT_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_ENVIRONMENT_H_
#undef RELIEF_SHADERS_CPP_ENVIRONMENT_H_
#else
#define RELIEF_SHADERS_CPP_ENVIRONMENT_H_
#endif

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/texture.h"
#include "shaders_cpp/environment_maps.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// +1 for x >= 0 (and +0, -0), else -1: the octahedral fold's signNotZero.
template <class F>
inline F sign_not_zero(F x) {
  return select(x < F(0.0f), F(-1.0f), F(1.0f));
}

// Octahedral uv in [0, 1]^2 of direction d (any length; zero reads as +Y): environment_maps.h.
template <class F>
inline V2<F> octahedral_uv(V3<F> d) {
  const F sum = vmax(vabs(d.x) + vabs(d.y) + vabs(d.z), F(1e-30f));
  const F px = d.x / sum, pz = d.z / sum;
  const mask_t<F> lower = d.y < F(0.0f);
  const F fx = (F(1.0f) - vabs(pz)) * sign_not_zero(px);
  const F fz = (F(1.0f) - vabs(px)) * sign_not_zero(pz);
  return {select(lower, fx, px) * F(0.5f) + F(0.5f), select(lower, fz, pz) * F(0.5f) + F(0.5f)};
}

// The unit direction at octahedral uv (the inverse of octahedral_uv on [0, 1]^2).
template <class F>
inline V3<F> octahedral_direction(V2<F> uv) {
  const F px = uv.x * F(2.0f) - F(1.0f), pz = uv.y * F(2.0f) - F(1.0f);
  const F y = F(1.0f) - vabs(px) - vabs(pz);
  const mask_t<F> lower = y < F(0.0f);
  const F x = select(lower, (F(1.0f) - vabs(pz)) * sign_not_zero(px), px);
  const F z = select(lower, (F(1.0f) - vabs(px)) * sign_not_zero(pz), pz);
  return normalize(V3<F>(x, y, z));
}

// World direction w in the environment's frame: the environment turned by the view's angle
// about +Y, so the lookup turns w the other way (x' = c x - s z, z' = s x + c z).
template <class F>
inline V3<F> env_direction(const EnvironmentView& view, V3<F> w) {
  const F c(view.cos_rotation), s(view.sin_rotation);
  return {c * w.x - s * w.z, w.y, s * w.x + c * w.z};
}

// The 9 real SH basis functions at unit n, in environment_maps.h's order.
template <class F>
inline void sh_basis(V3<F> n, F out[kEnvShCount]) {
  out[0] = F(0.28209479177387814f);
  out[1] = F(0.48860251190291992f) * n.y;
  out[2] = F(0.48860251190291992f) * n.z;
  out[3] = F(0.48860251190291992f) * n.x;
  out[4] = F(1.09254843059207907f) * (n.x * n.y);
  out[5] = F(1.09254843059207907f) * (n.y * n.z);
  out[6] = F(0.31539156525252005f) * (F(3.0f) * (n.z * n.z) - F(1.0f));
  out[7] = F(1.09254843059207907f) * (n.x * n.z);
  out[8] = F(0.54627421529603959f) * (n.x * n.x - n.y * n.y);
}

// E(n) / pi times the view's intensity at unit world normal n: the diffuse light (a Lambertian
// surface of albedo rho reflects rho * env_irradiance).
template <class F>
inline V3<F> env_irradiance(const EnvironmentMaps& maps, const EnvironmentView& view, V3<F> n) {
  F y[kEnvShCount];
  sh_basis(env_direction(view, n), y);
  V3<F> e(F(0.0f), F(0.0f), F(0.0f));
  for (int i = 0; i < kEnvShCount; ++i) e += V3<F>(maps.sh[i]) * y[i];
  return e * F(view.intensity);
}

namespace env_detail {
// textureLod of the RGBA16F map `t` (rgb) through its R32F channel planes on the lane-parallel
// sampler (environment_maps.h: the same bits); lane by lane through sample_lod when the planes
// are absent (maps built without split_channels).
template <class F, size_t N>
inline V3<F> read_lod(const Texture& t, const std::array<Texture, N>& planes, const SamplerState& s,
                      V2<F> uv, F lod) {
  V3<F> c(F(0.0f), F(0.0f), F(0.0f));
  if (!planes[0].empty()) {
    c.x = texture_r_lod_call(planes[0], s, uv, lod);
    c.y = texture_r_lod_call(planes[1], s, uv, lod);
    if constexpr (N > 2) c.z = texture_r_lod_call(planes[2], s, uv, lod);
    return c;
  }
  for (int i = 0; i < lane_width<F>; ++i) {
    const glm::vec4 v = sample_lod(t, s, glm::vec2(lane(uv.x, i), lane(uv.y, i)), lane(lod, i));
    set_lane(c.x, i, v.x);
    set_lane(c.y, i, v.y);
    set_lane(c.z, i, N > 2 ? v.z : 0.0f);
  }
  return c;
}
}  // namespace env_detail

// Prefiltered specular radiance times the view's intensity along world direction r (the
// reflection of the view about the normal; any length) at perceptual roughness in [0, 1]
// (clamped; NaN reads as 0): trilinear at lod = roughness * (levels - 1), clamp to edge.
template <class F>
inline V3<F> env_specular(const EnvironmentMaps& maps, const EnvironmentView& view, V3<F> r,
                          F roughness) {
  if (maps.specular.empty()) return V3<F>(F(0.0f), F(0.0f), F(0.0f));
  const V2<F> uv = octahedral_uv(env_direction(view, r));
  const F rough = vmin(vmax(select(roughness == roughness, roughness, F(0.0f)), F(0.0f)), F(1.0f));
  const F lod = rough * F(static_cast<float>(maps.specular.levels() - 1));
  const SamplerState s{Filter::kTrilinear, Wrap::kClamp, Wrap::kClamp, 1};
  return env_detail::read_lod(maps.specular, maps.specular_planes, s, uv, lod) * F(view.intensity);
}

// The split-sum BRDF terms (A, B) at NdotV and perceptual roughness (both clamped to [0, 1] by
// the clamp-to-edge read): specular = env_specular * (F0 * A + B).
template <class F>
inline V2<F> env_brdf(const EnvironmentMaps& maps, F ndotv, F roughness) {
  if (maps.brdf_lut.empty()) return V2<F>(F(0.0f), F(0.0f));
  const SamplerState s{Filter::kBilinear, Wrap::kClamp, Wrap::kClamp, 1};
  const V3<F> ab =
      env_detail::read_lod(maps.brdf_lut, maps.brdf_planes, s, V2<F>(ndotv, roughness), F(0.0f));
  return V2<F>(ab.x, ab.y);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_ENVIRONMENT_H_
