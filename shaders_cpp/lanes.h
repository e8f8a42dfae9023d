// Lane types for kernels written once (DESIGN.md, "The fragment-shader plugin ABI").
//
// A kernel is a template over F, the float lane type: `float` (one fragment, for clarity and tests)
// or `F8` (eight fragments in one SIMD batch, GCC vector extensions, AVX when the build enables
// it). mask_t<F> is the matching predicate type (bool or M8). Every operation here is a plain IEEE
// operation done lane by lane in the same order for both types, and the build disables FP
// contraction, so the two instantiations agree bit for bit (tested in tests/shaders_cpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace relief {

typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));

struct M8 {
  v8i v;
  friend M8 operator&(M8 a, M8 b) { return {a.v & b.v}; }
  friend M8 operator|(M8 a, M8 b) { return {a.v | b.v}; }
  friend M8 operator^(M8 a, M8 b) { return {a.v ^ b.v}; }
  friend M8 operator!(M8 a) { return {~a.v}; }
  M8& operator&=(M8 b) { v &= b.v; return *this; }
  M8& operator|=(M8 b) { v |= b.v; return *this; }
  bool operator[](int i) const { return v[i] != 0; }
};

struct F8 {
  v8f v;
  F8() : v{} {}
  F8(float s) : v{s, s, s, s, s, s, s, s} {}  // NOLINT: broadcast like GLSL
  explicit F8(v8f x) : v(x) {}
  static F8 load(const float* p) {
    F8 r;
    std::memcpy(&r.v, p, sizeof(v8f));
    return r;
  }
  void store(float* p) const { std::memcpy(p, &v, sizeof(v8f)); }
  float operator[](int i) const { return v[i]; }
  void set(int i, float x) { v[i] = x; }

  friend F8 operator+(F8 a, F8 b) { return F8(a.v + b.v); }
  friend F8 operator-(F8 a, F8 b) { return F8(a.v - b.v); }
  friend F8 operator*(F8 a, F8 b) { return F8(a.v * b.v); }
  friend F8 operator/(F8 a, F8 b) { return F8(a.v / b.v); }
  friend F8 operator-(F8 a) { return F8(-a.v); }
  F8& operator+=(F8 b) { v += b.v; return *this; }
  F8& operator-=(F8 b) { v -= b.v; return *this; }
  F8& operator*=(F8 b) { v *= b.v; return *this; }
  F8& operator/=(F8 b) { v /= b.v; return *this; }
  friend M8 operator<(F8 a, F8 b) { return {a.v < b.v}; }
  friend M8 operator<=(F8 a, F8 b) { return {a.v <= b.v}; }
  friend M8 operator>(F8 a, F8 b) { return {a.v > b.v}; }
  friend M8 operator>=(F8 a, F8 b) { return {a.v >= b.v}; }
  friend M8 operator==(F8 a, F8 b) { return {a.v == b.v}; }
  friend M8 operator!=(F8 a, F8 b) { return {a.v != b.v}; }
};

template <class F> struct LaneTraits;
template <> struct LaneTraits<float> {
  using Mask = bool;
  static constexpr int kWidth = 1;
};
template <> struct LaneTraits<F8> {
  using Mask = M8;
  static constexpr int kWidth = 8;
};
template <class F> using mask_t = typename LaneTraits<F>::Mask;
template <class F> inline constexpr int lane_width = LaneTraits<F>::kWidth;

// ---- scalar ----
inline float select(bool m, float a, float b) { return m ? a : b; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline bool none(bool m) { return !m; }
inline bool mask_set(bool, int, bool x) { return x; }
inline float lane(float x, int) { return x; }
inline bool lane(bool x, int) { return x; }
inline void set_lane(float& x, int, float v) { x = v; }
inline void set_lane(bool& x, int, bool v) { x = v; }
inline float vmin(float a, float b) { return b < a ? b : a; }
inline float vmax(float a, float b) { return a < b ? b : a; }
inline float vabs(float a) { return std::fabs(a); }
inline float vsqrt(float a) { return std::sqrt(a); }
inline float vfloor(float a) { return std::floor(a); }
inline float load_lanes(const float* p, float) { return *p; }
inline void store_lanes(float* p, float x) { *p = x; }

// ---- 8 lanes ----
inline F8 select(M8 m, F8 a, F8 b) { return F8(m.v ? a.v : b.v); }
inline bool any(M8 m) {
  for (int i = 0; i < 8; ++i)
    if (m.v[i]) return true;
  return false;
}
inline bool all(M8 m) {
  for (int i = 0; i < 8; ++i)
    if (!m.v[i]) return false;
  return true;
}
inline bool none(M8 m) { return !any(m); }
inline float lane(F8 x, int i) { return x.v[i]; }
inline bool lane(M8 m, int i) { return m.v[i] != 0; }
inline void set_lane(F8& x, int i, float v) { x.v[i] = v; }
inline void set_lane(M8& m, int i, bool v) { m.v[i] = v ? -1 : 0; }
inline F8 vmin(F8 a, F8 b) { return F8(b.v < a.v ? b.v : a.v); }
inline F8 vmax(F8 a, F8 b) { return F8(a.v < b.v ? b.v : a.v); }
inline F8 vabs(F8 a) {
  v8i bits;
  std::memcpy(&bits, &a.v, sizeof bits);
  bits &= 0x7fffffff;
  F8 r;
  std::memcpy(&r.v, &bits, sizeof bits);
  return r;
}
inline F8 vsqrt(F8 a) {
  F8 r;
  for (int i = 0; i < 8; ++i) r.v[i] = std::sqrt(a.v[i]);
  return r;
}
inline F8 vfloor(F8 a) {
  F8 r;
  for (int i = 0; i < 8; ++i) r.v[i] = std::floor(a.v[i]);
  return r;
}
inline F8 load_lanes(const float* p, F8) { return F8::load(p); }
inline void store_lanes(float* p, F8 x) { x.store(p); }

// ---- generic helpers ----
template <class F> inline F clamp(F x, F lo, F hi) { return vmin(vmax(x, lo), hi); }
template <class F> inline F mix(F a, F b, F t) { return a + (b - a) * t; }
template <class F> inline F saturate(F x) { return clamp<F>(x, F(0.0f), F(1.0f)); }
template <class F> inline mask_t<F> true_mask() { return F(0.0f) == F(0.0f); }
template <class F> inline mask_t<F> false_mask() { return F(0.0f) != F(0.0f); }

// Applies a scalar function lane by lane: the bridge to per-lane work such as texture fetches.
template <class Fn> inline float per_lane(float, Fn&& fn) { return fn(0); }
template <class Fn> inline F8 per_lane(F8, Fn&& fn) {
  F8 r;
  for (int i = 0; i < 8; ++i) r.v[i] = fn(i);
  return r;
}

}  // namespace relief
