// Per-fragment tangent frames: interpolated T, B-sign and N re-orthonormalised (Gram-Schmidt),
// with a finite fallback when the interpolated tangent is zero or parallel to N (degenerate uv),
// so no NaN ever leaves here. The frame is T along +u and B = sign * cross(N, T) along +v (the
// relief searches turn a tangent-space ray into a uv step with it); glTF files store the opposite
// sign (their bitangent points to the image top, -v: scene/gltf.cpp negates it), and normal maps
// are glTF-convention, green along -B (plugins/surface.h normal_from_texel).

#if defined(RELIEF_SHADERS_CPP_FRAME_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_FRAME_H_
#undef RELIEF_SHADERS_CPP_FRAME_H_
#else
#define RELIEF_SHADERS_CPP_FRAME_H_
#endif

#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct TangentFrame {
  V3<F> t, b, n;  // orthonormal; t along +u, b along +v, n out of the surface

  V3<F> to_tangent(V3<F> w) const { return {dot(w, t), dot(w, b), dot(w, n)}; }
  V3<F> to_world(V3<F> v) const { return t * v.x + b * v.y + n * v.z; }
};

// Any unit vector perpendicular to unit n (Duff et al. 2017, "Building an orthonormal basis,
// revisited"), used when the interpolated tangent is unusable.
template <class F>
inline V3<F> any_perpendicular(V3<F> n) {
  F sign = select(n.z >= F(0.0f), F(1.0f), F(-1.0f));
  F a = F(-1.0f) / (sign + n.z);
  F b = n.x * n.y * a;
  return {F(1.0f) + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

// `normal` and `tangent` need not be unit length; `sign` is the bitangent sign (+1 or -1).
template <class F>
inline TangentFrame<F> make_tangent_frame(V3<F> normal, V3<F> tangent, F sign) {
  TangentFrame<F> f;
  V3<F> n = normalize(normal);
  n = select(dot(n, n) > F(0.5f), n, V3<F>(F(0.0f), F(0.0f), F(1.0f)));
  V3<F> t = tangent - n * dot(n, tangent);
  const F len2 = dot(t, t);
  const mask_t<F> good = len2 > F(1e-12f) * vmax(dot(tangent, tangent), F(1e-30f));
  // any_perpendicular (a division) only where some lane needs it: select would take the other
  // side everywhere else.
  t = all(good) ? normalize(t) : select(good, normalize(t), any_perpendicular(n));
  f.n = n;
  f.t = t;
  f.b = cross(n, t) * select(sign < F(0.0f), F(-1.0f), F(1.0f));
  return f;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_FRAME_H_
