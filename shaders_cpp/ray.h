// Eye rays in tangent and texture space, and depth correction, after Policarpo, Oliveira and Comba,
// "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005 (appendix: ds = s.xy *
// depth / s.z; depth correction of the hit point).
//
// Conventions (DESIGN.md): depth map in [0, 1], 0 at the reference surface, 1 deepest. Tangent
// frame T = dP/du, B = dP/dv, N out of the surface. The view direction in tangent space V points
// from the eye to the surface, so V.z < 0 looks into it. A texture-space ray starts at (u, v, 0)
// and reaches depth t in [0, 1] at (u, v) + t * ds, ds = V.xy * depth_scale / (-V.z), where
// depth_scale is the height of the relief in uv units. Depth is float reversed-Z in [0, 1]
// (near = 1, far = 0).

#if defined(RELIEF_SHADERS_CPP_RAY_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_RAY_H_
#undef RELIEF_SHADERS_CPP_RAY_H_
#else
#define RELIEF_SHADERS_CPP_RAY_H_
#endif

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "shaders_cpp/frame.h"
#include "shaders_cpp/lanes.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// The smallest -V.z (and light L.z) a texture-space step divides by: rays grazing closer than
// about 0.006 degrees, or leaving the surface, step as if at that angle, so ds stays finite.
inline constexpr float kMinRayCos = 1e-4f;

// Normalises `a`; a zero, huge, Inf or NaN vector gives `fallback` instead.
template <class F>
inline V3<F> normalize_or(V3<F> a, V3<F> fallback) {
  F len2 = dot(a, a);
  mask_t<F> ok = (len2 > F(1e-30f)) & (len2 < F(1e30f));
  F inv = F(1.0f) / vsqrt(select(ok, len2, F(1.0f)));
  return select(ok, a * inv, fallback);
}

// Gram-Schmidt per fragment from T, B and N (any lengths): n = N normalised, t = T minus its n
// part normalised, b = B minus its n and t parts normalised, which is sign * cross(n, t) with the
// sign of dot(B, cross(n, t)). Degenerate or NaN inputs fall back to a finite orthonormal frame
// (shaders_cpp/frame.h make_tangent_frame, which takes the bitangent sign directly).
template <class F>
inline TangentFrame<F> orthonormal_frame(V3<F> N, V3<F> T, V3<F> B) {
  F sign = select(dot(B, cross(N, T)) < F(0.0f), F(-1.0f), F(1.0f));
  return make_tangent_frame(N, T, sign);
}

// Unit world view direction, eye -> fragment: normalize(pos - eye), or view_dir when orthographic.
// A fragment at the eye falls back to -n (looking straight into the surface).
template <class F>
inline V3<F> world_view_dir(V3<F> world_pos, glm::vec3 eye, bool orthographic, glm::vec3 view_dir,
                            V3<F> fallback) {
  V3<F> d = orthographic ? V3<F>(view_dir) : world_pos - V3<F>(eye);
  return normalize_or(d, fallback);
}

// The tangent-space view direction V (unit, V.z < 0 into the surface) of a fragment.
template <class F>
inline V3<F> tangent_view_dir(const TangentFrame<F>& f, V3<F> world_pos, glm::vec3 eye,
                              bool orthographic = false, glm::vec3 view_dir = glm::vec3(0, 0, -1)) {
  V3<F> w = world_view_dir(world_pos, eye, orthographic, view_dir, -f.n);
  return f.to_tangent(w);
}

// Texture-space uv step per unit depth of the ray along V: V.xy * depth_scale / max(-V.z, kMin).
template <class F>
inline V2<F> texture_step(V3<F> V, F depth_scale) {
  F s = depth_scale / vmax(-V.z, F(kMinRayCos));
  return {V.x * s, V.y * s};
}

// Texture-space uv step per unit of depth *decrease* toward a light at tangent direction L (unit,
// L.z > 0 above the surface): the shadow ray (uv, t) + s * (dl, -1) leaves the surface upward.
template <class F>
inline V2<F> light_step(V3<F> L, F depth_scale) {
  F s = depth_scale / vmax(L.z, F(kMinRayCos));
  return {L.x * s, L.y * s};
}

// Relief step count from the view angle (paper, section 3: fewer steps facing the surface):
// round(mix(steps, min_steps, |V.z|)), at least 1.
template <class F>
inline F relief_step_count(F vz, float min_steps, float steps) {
  F n = vfloor(mix(F(steps), F(min_steps), saturate(vabs(vz))) + F(0.5f));
  return vmax(n, F(1.0f));
}

// World position of the hit at ray depth t: pos + w_view * (t * world_height / max(-V.z, kMin)),
// where world_height is the relief height in world units (depth_scale times world units per uv).
template <class F>
inline V3<F> hit_world_position(V3<F> world_pos, V3<F> w_view, F vz, F t, F world_height) {
  F dist = t * world_height / vmax(-vz, F(kMinRayCos));
  return world_pos + w_view * dist;
}

// Reversed-Z depth of a world point: clip = view_proj * (p, 1), depth = clip.z / clip.w clamped to
// [0, 1]; a point at or behind the eye plane (w <= 0), or any NaN, gives `fallback`.
template <class F>
inline F reversed_z_depth(const glm::mat4& view_proj, V3<F> p, F fallback) {
  const glm::mat4& m = view_proj;
  F z = p.x * F(m[0][2]) + p.y * F(m[1][2]) + p.z * F(m[2][2]) + F(m[3][2]);
  F w = p.x * F(m[0][3]) + p.y * F(m[1][3]) + p.z * F(m[2][3]) + F(m[3][3]);
  mask_t<F> ok = w > F(1e-30f);
  F d = z / select(ok, w, F(1.0f));
  ok = ok & (d == d);
  return select(ok, saturate(d), saturate(select(fallback == fallback, fallback, F(0.0f))));
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_RAY_H_
