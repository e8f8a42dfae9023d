// Small vectors over a lane type F (float or F8): the GLSL vec2/vec3/vec4 of kernels.
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "shaders_cpp/lanes.h"

namespace relief {

template <class F> struct V2 {
  F x, y;
  V2() = default;
  V2(F a, F b) : x(a), y(b) {}
  explicit V2(glm::vec2 v) : x(v.x), y(v.y) {}
  friend V2 operator+(V2 a, V2 b) { return {a.x + b.x, a.y + b.y}; }
  friend V2 operator-(V2 a, V2 b) { return {a.x - b.x, a.y - b.y}; }
  friend V2 operator*(V2 a, F s) { return {a.x * s, a.y * s}; }
  friend V2 operator*(V2 a, V2 b) { return {a.x * b.x, a.y * b.y}; }
};

template <class F> struct V3 {
  F x, y, z;
  V3() = default;
  V3(F a, F b, F c) : x(a), y(b), z(c) {}
  explicit V3(glm::vec3 v) : x(v.x), y(v.y), z(v.z) {}
  friend V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend V3 operator-(V3 a) { return {-a.x, -a.y, -a.z}; }
  friend V3 operator*(V3 a, F s) { return {a.x * s, a.y * s, a.z * s}; }
  friend V3 operator*(V3 a, V3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
  V3& operator+=(V3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
};

template <class F> inline F dot(V3<F> a, V3<F> b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class F> inline V3<F> cross(V3<F> a, V3<F> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F> inline F length(V3<F> a) { return vsqrt(dot(a, a)); }
// Normalises; a zero vector stays zero (no NaN).
template <class F> inline V3<F> normalize(V3<F> a) {
  F len2 = dot(a, a);
  F inv = select(len2 > F(1e-30f), F(1.0f) / vsqrt(vmax(len2, F(1e-30f))), F(0.0f));
  return a * inv;
}
template <class F> inline V3<F> select(mask_t<F> m, V3<F> a, V3<F> b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class F> inline V2<F> select(mask_t<F> m, V2<F> a, V2<F> b) {
  return {select(m, a.x, b.x), select(m, a.y, b.y)};
}
template <class F> inline V3<F> mix(V3<F> a, V3<F> b, F t) { return a + (b - a) * t; }

}  // namespace relief
