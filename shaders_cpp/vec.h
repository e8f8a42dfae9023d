// Small vectors over a lane type F (float or F8): the GLSL vec2/vec3/vec4 of kernels.

#if defined(RELIEF_SHADERS_CPP_VEC_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_VEC_H_
#undef RELIEF_SHADERS_CPP_VEC_H_
#else
#define RELIEF_SHADERS_CPP_VEC_H_
#endif

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <type_traits>

#include "shaders_cpp/lanes.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct V2 {
  F x, y;
  V2() = default;
  V2(F a, F b) : x(a), y(b) {}
  explicit V2(glm::vec2 v) : x(v.x), y(v.y) {}
};

template <class F>
struct V3 {
  F x, y, z;
  V3() = default;
  V3(F a, F b, F c) : x(a), y(b), z(c) {}
  explicit V3(glm::vec3 v) : x(v.x), y(v.y), z(v.z) {}
  V3& operator+=(V3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
};

// Namespace-scope operators, not friends: see lanes.h. The scalar operand of `*` is not deduced,
// so `v * 0.5f` broadcasts as with a friend.
template <class F>
inline V2<F> operator+(V2<F> a, V2<F> b) {
  return {a.x + b.x, a.y + b.y};
}
template <class F>
inline V2<F> operator-(V2<F> a, V2<F> b) {
  return {a.x - b.x, a.y - b.y};
}
template <class F>
inline V2<F> operator*(V2<F> a, std::type_identity_t<F> s) {
  return {a.x * s, a.y * s};
}
template <class F>
inline V2<F> operator*(V2<F> a, V2<F> b) {
  return {a.x * b.x, a.y * b.y};
}
template <class F>
inline V3<F> operator+(V3<F> a, V3<F> b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class F>
inline V3<F> operator-(V3<F> a, V3<F> b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class F>
inline V3<F> operator-(V3<F> a) {
  return {-a.x, -a.y, -a.z};
}
template <class F>
inline V3<F> operator*(V3<F> a, std::type_identity_t<F> s) {
  return {a.x * s, a.y * s, a.z * s};
}
template <class F>
inline V3<F> operator*(V3<F> a, V3<F> b) {
  return {a.x * b.x, a.y * b.y, a.z * b.z};
}

template <class F>
inline F dot(V3<F> a, V3<F> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class F>
inline V3<F> cross(V3<F> a, V3<F> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
inline F length(V3<F> a) {
  return vsqrt(dot(a, a));
}
// Normalises; a zero vector stays zero (no NaN).
template <class F>
inline V3<F> normalize(V3<F> a) {
  F len2 = dot(a, a);
  F inv = select(len2 > F(1e-30f), F(1.0f) / vsqrt(vmax(len2, F(1e-30f))), F(0.0f));
  return a * inv;
}
template <class F>
inline V3<F> select(mask_t<F> m, V3<F> a, V3<F> b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class F>
inline V2<F> select(mask_t<F> m, V2<F> a, V2<F> b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y)};
}
template <class F>
inline V3<F> mix(V3<F> a, V3<F> b, F t) {
  return a + (b - a) * t;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_VEC_H_
