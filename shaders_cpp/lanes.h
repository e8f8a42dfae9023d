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

#include "rasterizer/simd.h"  // v8f, v8i

namespace relief {

namespace detail {
// A scalar copied to all eight lanes: lane 0 set, then a shuffle of lane 0 everywhere. GCC 12
// builds `v8i{s, s, s, s, s, s, s, s}` of a run-time s inside a target("avx2") clone as vmovd,
// three vpinsrd and a vinserti128 (vinsertps chains for floats); this form is one vpbroadcastd
// (vbroadcastss) there and pshufd in baseline code, and a constant s still folds to a constant.
// Always inline: a broadcast left out of line is a call per use (session 8 found I8(int) as a
// .constprop clone called from the sampler clones).
// (Clang: __builtin_shufflevector, the same operation.) V is v8i or v8f, S its lane type.
template <class V, class S>
__attribute__((always_inline)) inline V broadcast8(S s) {
  V t{};
  t[0] = s;
#if defined(__clang__)
  return __builtin_shufflevector(t, t, 0, 0, 0, 0, 0, 0, 0, 0);
#else
  return __builtin_shuffle(t, v8i{});
#endif
}
}  // namespace detail

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

// Eight int32 lanes: the integer companion of F8 (texel addresses, exponent bits).
struct I8 {
  v8i v;
  I8() : v{} {}
  // NOLINTNEXTLINE: implicit broadcast
  __attribute__((always_inline)) I8(int32_t s) : v(detail::broadcast8<v8i>(s)) {}
  explicit I8(v8i x) : v(x) {}
  int32_t operator[](int i) const { return v[i]; }
  friend I8 operator+(I8 a, I8 b) { return I8(a.v + b.v); }
  friend I8 operator-(I8 a, I8 b) { return I8(a.v - b.v); }
  friend I8 operator*(I8 a, I8 b) { return I8(a.v * b.v); }
  friend I8 operator&(I8 a, I8 b) { return I8(a.v & b.v); }
  friend I8 operator|(I8 a, I8 b) { return I8(a.v | b.v); }
  friend I8 operator<<(I8 a, int n) { return I8(a.v << n); }
  friend I8 operator>>(I8 a, int n) { return I8(a.v >> n); }
  friend I8 operator>>(I8 a, I8 n) { return I8(a.v >> n.v); }
  friend M8 operator<(I8 a, I8 b) { return {a.v < b.v}; }
  friend M8 operator>(I8 a, I8 b) { return {a.v > b.v}; }
  friend M8 operator>=(I8 a, I8 b) { return {a.v >= b.v}; }
  friend M8 operator==(I8 a, I8 b) { return {a.v == b.v}; }
};

struct F8 {
  v8f v;
  F8() : v{} {}
  // NOLINTNEXTLINE: implicit broadcast, like GLSL
  __attribute__((always_inline)) F8(float s) : v(detail::broadcast8<v8f>(s)) {}
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
  using Int = int32_t;
  static constexpr int kWidth = 1;
};
template <> struct LaneTraits<F8> {
  using Mask = M8;
  using Int = I8;
  static constexpr int kWidth = 8;
};
template <class F> using mask_t = typename LaneTraits<F>::Mask;
template <class F> using int_t = typename LaneTraits<F>::Int;
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
inline int32_t select(bool m, int32_t a, int32_t b) { return m ? a : b; }
inline int32_t vmin(int32_t a, int32_t b) { return b < a ? b : a; }
inline int32_t vmax(int32_t a, int32_t b) { return a < b ? b : a; }
inline int32_t bits_of(float x) {
  int32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}
inline float float_of_bits(int32_t b) {
  float x;
  std::memcpy(&x, &b, 4);
  return x;
}
inline float to_float(int32_t i) { return static_cast<float>(i); }
inline int32_t lane(int32_t x, int) { return x; }
inline void set_lane(int32_t& x, int, int32_t v) { x = v; }
inline int32_t trunc_to_int(float x) { return static_cast<int32_t>(x); }  // |x| < 2^31

// ---- 8 lanes ----
inline F8 select(M8 m, F8 a, F8 b) { return F8(m.v ? a.v : b.v); }
// A lane is true when its word is not zero. any/all OR the mask's four 64-bit words together:
// branch-free, where a lane-by-lane loop costs a branch a lane (a search loop asks every step).
inline bool any(M8 m) {
  uint64_t w[4];
  std::memcpy(w, &m.v, sizeof w);
  return (w[0] | w[1] | w[2] | w[3]) != 0;
}
inline bool all(M8 m) { return !any(M8{m.v == 0}); }
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
// std::floor over the lanes, bit for bit (-0 stays -0, NaN and |a| >= 2^23 pass through), without
// SSE4.1's round instruction, which the baseline target lacks: truncate to int, step down where
// that rounded a negative value up, and put the sign back (floor(-0.5) = -1, floor(-0.0) = -0).
inline F8 vfloor(F8 a) {
  const v8i bits = reinterpret_cast<v8i>(a.v);
  const v8f mag = reinterpret_cast<v8f>(bits & 0x7fffffff);
  const v8i small = mag < 8388608.0f;  // false for NaN
  const v8f x = small ? a.v : v8f{};
  const v8f t = __builtin_convertvector(__builtin_convertvector(x, v8i), v8f);
  const v8f f = t > x ? t - 1.0f : t;
  const v8i signed_f = reinterpret_cast<v8i>(f) | (bits & int32_t(0x80000000u));
  return F8(reinterpret_cast<v8f>(small ? signed_f : bits));
}
inline F8 load_lanes(const float* p, F8) { return F8::load(p); }
inline void store_lanes(float* p, F8 x) { x.store(p); }
inline I8 select(M8 m, I8 a, I8 b) { return I8(m.v ? a.v : b.v); }
inline I8 vmin(I8 a, I8 b) { return I8(b.v < a.v ? b.v : a.v); }
inline I8 vmax(I8 a, I8 b) { return I8(a.v < b.v ? b.v : a.v); }
inline I8 bits_of(F8 x) {
  I8 b;
  std::memcpy(&b.v, &x.v, sizeof b.v);
  return b;
}
inline F8 float_of_bits(I8 b) {
  F8 x;
  std::memcpy(&x.v, &b.v, sizeof x.v);
  return x;
}
inline int32_t lane(I8 x, int i) { return x.v[i]; }
inline void set_lane(I8& x, int i, int32_t v) { x.v[i] = v; }
inline F8 to_float(I8 i) { return F8(__builtin_convertvector(i.v, v8f)); }
inline I8 trunc_to_int(F8 x) { return I8(__builtin_convertvector(x.v, v8i)); }

// ---- generic helpers ----
template <class F> inline F clamp(F x, F lo, F hi) { return vmin(vmax(x, lo), hi); }
template <class F> inline F mix(F a, F b, F t) { return a + (b - a) * t; }
template <class F> inline F saturate(F x) { return clamp<F>(x, F(0.0f), F(1.0f)); }
template <class F> inline mask_t<F> true_mask() { return F(0.0f) == F(0.0f); }
template <class F> inline mask_t<F> false_mask() { return F(0.0f) != F(0.0f); }

// log2 of x > 0 (normal numbers; smaller inputs read as FLT_MIN), absolute error below 1e-7:
// exponent bits plus an odd series of atanh over the mantissa in [sqrt(1/2), sqrt(2)). Written
// over F, so float and F8 give the same bits.
template <class F> inline F vlog2(F x) {
  using I = int_t<F>;
  const I bits = bits_of(vmax(x, F(1.17549435e-38f)));
  I e = ((bits >> 23) & I(0xff)) - I(127);
  F m = float_of_bits((bits & I(0x7fffff)) | I(0x3f800000));  // [1, 2)
  const mask_t<F> big = m > F(1.41421356f);
  m = select(big, m * F(0.5f), m);
  e = select(big, e + I(1), e);
  const F t = (m - F(1.0f)) / (m + F(1.0f));  // |t| <= 0.1716
  const F t2 = t * t;
  const F series =
      t * (F(2.0f) + t2 * (F(0.666666667f) + t2 * (F(0.4f) + t2 * (F(0.285714286f) +
                                                                      t2 * F(0.222222222f)))));
  return to_float(e) + series * F(1.44269504f);  // ln -> log2
}

// 2^y, relative error below 3e-7 (Cephes exp2f: y = n + f, |f| <= 1/2, 2^f = 1 + f P(f)), exact
// at whole y; y below -126 gives 0, above 127 gives 2^127 (finite), NaN reads as 0.
template <class F> inline F vexp2(F y) {
  using I = int_t<F>;
  const mask_t<F> tiny = y < F(-126.0f);
  y = clamp<F>(select(y == y, y, F(0.0f)), F(-126.0f), F(127.0f));
  const F n = vfloor(y + F(0.5f));
  const F f = y - n;
  const F p = F(1.0f) + f * (F(6.931472028550421e-1f) + f * (F(2.402264791363012e-1f) +
              f * (F(5.550332471162809e-2f) + f * (F(9.618437357674640e-3f) +
              f * (F(1.339887440266574e-3f) + f * F(1.535336188319500e-4f))))));
  const F scale = float_of_bits((trunc_to_int(n) + I(127)) << 23);
  return select(tiny, F(0.0f), p * scale);
}

// x^e for x >= 0 (GLSL pow's domain): exp2(e * log2(x)), relative error below
// 3e-7 * max(1, |e log2 x|) (float rounding of the exponent); 0^e is 0 for e > 0, 1 for e == 0.
template <class F> inline F vpow_fast(F x, float e) {
  const F r = vexp2(F(e) * vlog2(x));
  return select(x > F(0.0f), r, F(e == 0.0f ? 1.0f : 0.0f));
}

// Applies a scalar function lane by lane: the bridge to per-lane work such as texture fetches.
template <class Fn> inline float per_lane(float, Fn&& fn) { return fn(0); }
template <class Fn> inline F8 per_lane(F8, Fn&& fn) {
  F8 r;
  for (int i = 0; i < 8; ++i) r.v[i] = fn(i);
  return r;
}

}  // namespace relief
