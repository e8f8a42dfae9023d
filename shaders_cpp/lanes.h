// Lane types for kernels written once (DESIGN.md, "The fragment-shader plugin ABI").
//
// A kernel is a template over F, the float lane type: `float` (one fragment, for clarity and tests)
// or FV<N> (N fragments in one SIMD batch: GCC vector extensions compiled for the SIMD target of
// the enclosing namespace). mask_t<F> is the matching predicate type (bool or MV<N>). Every
// operation here is a plain IEEE operation done lane by lane in the same order for every type, and
// the build disables FP contraction, so all instantiations agree bit for bit (tested in
// tests/shaders_cpp and, per SIMD target, tests/frames/simd_test.cpp).
//
// Per-target header (base/simd.h): it has no include guard of its own but Highway's toggle, so
// that a translation unit built with hwy/foreach_target.h compiles it once per target, inside
// relief::HWY_NAMESPACE. FN, MN and IN are the target's native width, kLanes lanes: 16 on
// AVX-512 (Highway's AVX3 target), 8 elsewhere (AVX2; the baseline EMU128 target runs them as two
// SSE2 halves). F8, I8 and M8 name the 8-lane types on every target. Code outside a foreach_target
// pass (tests, tools) sees the static target's types as relief::F8 and friends through the
// using-directive at the end.
#if defined(RELIEF_SHADERS_LANES_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_LANES_H_
#undef RELIEF_SHADERS_LANES_H_
#else
#define RELIEF_SHADERS_LANES_H_
#endif

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <hwy/highway.h>

#include "base/simd_flatten.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// The target's native lane count.
#if HWY_ARCH_X86 && (HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL)
inline constexpr int kLanes = 16;
#else
inline constexpr int kLanes = 8;
#endif

// GCC vector types of N lanes (N = 8 or 16).
template <int N>
struct VecOf;
template <>
struct VecOf<8> {
  typedef float f __attribute__((vector_size(32)));
  typedef int32_t i __attribute__((vector_size(32)));
};
template <>
struct VecOf<16> {
  typedef float f __attribute__((vector_size(64)));
  typedef int32_t i __attribute__((vector_size(64)));
};
template <int N>
using vf_t = typename VecOf<N>::f;
template <int N>
using vi_t = typename VecOf<N>::i;

namespace detail {
// A scalar copied to every lane: lane 0 set, then a shuffle of lane 0 everywhere. GCC 12 builds
// `vi{s, s, ...}` of a run-time s as a chain of inserts; this form is one vpbroadcastd
// (vbroadcastss) on AVX2 and AVX-512 and pshufd in baseline code, and a constant s still folds to
// a constant. Always inline: a broadcast left out of line is a call per use.
// (Clang: __builtin_shufflevector, the same operation.) V is a vf_t or vi_t, S its lane type.
template <class V, class S>
__attribute__((always_inline)) inline V broadcast(S s) {
  V t{};
  t[0] = s;
  constexpr int n = sizeof(V) / 4;
#if defined(__clang__)
  if constexpr (n == 8)
    return __builtin_shufflevector(t, t, 0, 0, 0, 0, 0, 0, 0, 0);
  else
    return __builtin_shufflevector(t, t, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0);
#else
  return __builtin_shuffle(t, vi_t<n>{});
#endif
}
}  // namespace detail

// The operators are namespace-scope templates, never friends defined in the class: GCC compiles a
// friend defined inside a class without the target options of the region around it (and an
// implicitly defined constructor likewise), which would make it baseline code with the baseline
// calling convention, called from this target's code (tests/tools/check-per-target.sh fails the
// build on such a friend in any per-target file).
template <int N>
struct MV {
  vi_t<N> v;
  MV& operator&=(MV b) {
    v &= b.v;
    return *this;
  }
  MV& operator|=(MV b) {
    v |= b.v;
    return *this;
  }
  bool operator[](int i) const { return v[i] != 0; }
};
template <int N>
inline MV<N> operator&(MV<N> a, MV<N> b) {
  return {a.v & b.v};
}
template <int N>
inline MV<N> operator|(MV<N> a, MV<N> b) {
  return {a.v | b.v};
}
template <int N>
inline MV<N> operator^(MV<N> a, MV<N> b) {
  return {a.v ^ b.v};
}
template <int N>
inline MV<N> operator!(MV<N> a) {
  return {~a.v};
}

// N int32 lanes: the integer companion of FV (texel addresses, exponent bits).
template <int N>
struct IV {
  vi_t<N> v;
  IV() : v{} {}
  // NOLINTNEXTLINE: implicit broadcast
  __attribute__((always_inline)) IV(int32_t s) : v(detail::broadcast<vi_t<N>>(s)) {}
  explicit IV(vi_t<N> x) : v(x) {}
  int32_t operator[](int i) const { return v[i]; }
};

template <int N>
struct FV {
  vf_t<N> v;
  FV() : v{} {}
  // NOLINTNEXTLINE: implicit broadcast, like GLSL
  __attribute__((always_inline)) FV(float s) : v(detail::broadcast<vf_t<N>>(s)) {}
  explicit FV(vf_t<N> x) : v(x) {}
  static FV load(const float* p) {
    FV r;
    std::memcpy(&r.v, p, sizeof(r.v));
    return r;
  }
  void store(float* p) const { std::memcpy(p, &v, sizeof(v)); }
  float operator[](int i) const { return v[i]; }
  void set(int i, float x) { v[i] = x; }
  FV& operator+=(FV b) {
    v += b.v;
    return *this;
  }
  FV& operator-=(FV b) {
    v -= b.v;
    return *this;
  }
  FV& operator*=(FV b) {
    v *= b.v;
    return *this;
  }
  FV& operator/=(FV b) {
    v /= b.v;
    return *this;
  }
};

// Binary operators of lanes T<N> with scalar S (broadcast, like GLSL) on either side.
#define RELIEF_LANE_BINARY(T, S, R, OP)  \
  template <int N>                       \
  inline R operator OP(T<N> a, T<N> b) { \
    return R{a.v OP b.v};                \
  }                                      \
  template <int N>                       \
  inline R operator OP(T<N> a, S b) {    \
    return R{a.v OP T<N>(b).v};          \
  }                                      \
  template <int N>                       \
  inline R operator OP(S a, T<N> b) {    \
    return R{T<N>(a).v OP b.v};          \
  }
RELIEF_LANE_BINARY(FV, float, FV<N>, +)
RELIEF_LANE_BINARY(FV, float, FV<N>, -)
RELIEF_LANE_BINARY(FV, float, FV<N>, *)
RELIEF_LANE_BINARY(FV, float, FV<N>, /)
RELIEF_LANE_BINARY(FV, float, MV<N>, <)
RELIEF_LANE_BINARY(FV, float, MV<N>, <=)
RELIEF_LANE_BINARY(FV, float, MV<N>, >)
RELIEF_LANE_BINARY(FV, float, MV<N>, >=)
RELIEF_LANE_BINARY(FV, float, MV<N>, ==)
RELIEF_LANE_BINARY(FV, float, MV<N>, !=)
RELIEF_LANE_BINARY(IV, int32_t, IV<N>, +)
RELIEF_LANE_BINARY(IV, int32_t, IV<N>, -)
RELIEF_LANE_BINARY(IV, int32_t, IV<N>, *)
RELIEF_LANE_BINARY(IV, int32_t, IV<N>, &)
RELIEF_LANE_BINARY(IV, int32_t, IV<N>, |)
RELIEF_LANE_BINARY(IV, int32_t, MV<N>, <)
RELIEF_LANE_BINARY(IV, int32_t, MV<N>, >)
RELIEF_LANE_BINARY(IV, int32_t, MV<N>, >=)
RELIEF_LANE_BINARY(IV, int32_t, MV<N>, ==)
#undef RELIEF_LANE_BINARY
template <int N>
inline FV<N> operator-(FV<N> a) {
  return FV<N>(-a.v);
}
template <int N>
inline IV<N> operator<<(IV<N> a, int n) {
  return IV<N>(a.v << n);
}
template <int N>
inline IV<N> operator>>(IV<N> a, int n) {
  return IV<N>(a.v >> n);
}
template <int N>
inline IV<N> operator>>(IV<N> a, IV<N> n) {
  return IV<N>(a.v >> n.v);
}

// Lay the lane types out here, inside this target's region. GCC instantiates function templates at
// the end of the translation unit, after the region has closed; a class template it first meets
// there is laid out for the baseline target, and a function returning it then disagrees with its
// callers about where the value is (GCC 12: a vzeroupper before `ret` wiped the upper lanes of a
// returned mask; tests/frames/simd_test.cpp caught it on relief_dual). A class that holds one
// lane value and nothing else must be instantiated here the same way.
static_assert(sizeof(FV<8>) == 32 && sizeof(IV<8>) == 32 && sizeof(MV<8>) == 32);
static_assert(sizeof(FV<16>) == 64 && sizeof(IV<16>) == 64 && sizeof(MV<16>) == 64);

using F8 = FV<8>;
using I8 = IV<8>;
using M8 = MV<8>;
using FN = FV<kLanes>;  // the target's native width
using IN = IV<kLanes>;
using MN = MV<kLanes>;

template <class F>
struct LaneTraits;
template <>
struct LaneTraits<float> {
  using Mask = bool;
  using Int = int32_t;
  static constexpr int kWidth = 1;
};
template <int N>
struct LaneTraits<FV<N>> {
  using Mask = MV<N>;
  using Int = IV<N>;
  static constexpr int kWidth = N;
};
template <class F>
using mask_t = typename LaneTraits<F>::Mask;
template <class F>
using int_t = typename LaneTraits<F>::Int;
template <class F>
inline constexpr int lane_width = LaneTraits<F>::kWidth;
// Whether F is a SIMD lane type (not float).
template <class F>
inline constexpr bool is_lanes_v = lane_width<F> > 1;

// ---- scalar ----
inline float select(bool m, float a, float b) {
  return m ? a : b;
}
inline bool any(bool m) {
  return m;
}
inline bool all(bool m) {
  return m;
}
inline bool none(bool m) {
  return !m;
}
inline bool mask_set(bool, int, bool x) {
  return x;
}
inline float lane(float x, int) {
  return x;
}
inline bool lane(bool x, int) {
  return x;
}
inline void set_lane(float& x, int, float v) {
  x = v;
}
inline void set_lane(bool& x, int, bool v) {
  x = v;
}
inline float vmin(float a, float b) {
  return b < a ? b : a;
}
inline float vmax(float a, float b) {
  return a < b ? b : a;
}
inline float vabs(float a) {
  return std::fabs(a);
}
inline float vsqrt(float a) {
  return std::sqrt(a);
}
inline float vfloor(float a) {
  return std::floor(a);
}
inline float load_lanes(const float* p, float) {
  return *p;
}
inline void store_lanes(float* p, float x) {
  *p = x;
}
inline int32_t select(bool m, int32_t a, int32_t b) {
  return m ? a : b;
}
inline int32_t vmin(int32_t a, int32_t b) {
  return b < a ? b : a;
}
inline int32_t vmax(int32_t a, int32_t b) {
  return a < b ? b : a;
}
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
inline float to_float(int32_t i) {
  return static_cast<float>(i);
}
inline int32_t lane(int32_t x, int) {
  return x;
}
inline void set_lane(int32_t& x, int, int32_t v) {
  x = v;
}
inline int32_t trunc_to_int(float x) {
  return static_cast<int32_t>(x);
}  // |x| < 2^31

// ---- N lanes ----
template <int N>
inline FV<N> select(MV<N> m, FV<N> a, FV<N> b) {
  return FV<N>(m.v ? a.v : b.v);
}
// A lane is true when its word is not zero. any/all test the whole mask at once: one test
// instruction of the mask against itself where the target has it (vptestmd on AVX-512, vptest
// on AVX2 and up), else an OR of its 64-bit words; branch-free either way, where a lane-by-lane
// loop costs a branch a lane (a search loop asks every step).
template <int N>
inline bool any(MV<N> m) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (N == 8) {
    const __m256i v = (__m256i)m.v;
    return !_mm256_testz_si256(v, v);
  }
#endif
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
  if constexpr (N == 16) {
    const __m512i v = (__m512i)m.v;
    return _mm512_test_epi32_mask(v, v) != 0;
  }
#endif
  uint64_t w[N / 2];
  std::memcpy(w, &m.v, sizeof w);
  uint64_t r = 0;
  for (int i = 0; i < N / 2; ++i) r |= w[i];
  return r != 0;
}
template <int N>
inline bool all(MV<N> m) {
  return !any(MV<N>{m.v == 0});
}
template <int N>
inline bool none(MV<N> m) {
  return !any(m);
}
template <int N>
inline float lane(FV<N> x, int i) {
  return x.v[i];
}
template <int N>
inline bool lane(MV<N> m, int i) {
  return m.v[i] != 0;
}
template <int N>
inline void set_lane(FV<N>& x, int i, float v) {
  x.v[i] = v;
}
template <int N>
inline void set_lane(MV<N>& m, int i, bool v) {
  m.v[i] = v ? -1 : 0;
}
template <int N>
inline FV<N> vmin(FV<N> a, FV<N> b) {
  return FV<N>(b.v < a.v ? b.v : a.v);
}
template <int N>
inline FV<N> vmax(FV<N> a, FV<N> b) {
  return FV<N>(a.v < b.v ? b.v : a.v);
}
template <int N>
inline FV<N> vabs(FV<N> a) {
  vi_t<N> bits;
  std::memcpy(&bits, &a.v, sizeof bits);
  bits &= 0x7fffffff;
  FV<N> r;
  std::memcpy(&r.v, &bits, sizeof bits);
  return r;
}
template <int N>
inline FV<N> vsqrt(FV<N> a) {
  FV<N> r;
  for (int i = 0; i < N; ++i) r.v[i] = std::sqrt(a.v[i]);
  return r;
}
// std::floor over the lanes, bit for bit (-0 stays -0, NaN and |a| >= 2^23 pass through), without
// SSE4.1's round instruction, which the baseline target lacks: truncate to int, step down where
// that rounded a negative value up, and put the sign back (floor(-0.5) = -1, floor(-0.0) = -0).
template <int N>
inline FV<N> vfloor(FV<N> a) {
  using vi = vi_t<N>;
  using vf = vf_t<N>;
  const vi bits = reinterpret_cast<vi>(a.v);
  const vf mag = reinterpret_cast<vf>(bits & 0x7fffffff);
  const vi small = mag < 8388608.0f;  // false for NaN
  const vf x = small ? a.v : vf{};
  const vf t = __builtin_convertvector(__builtin_convertvector(x, vi), vf);
  const vf f = t > x ? t - 1.0f : t;
  const vi signed_f = reinterpret_cast<vi>(f) | (bits & int32_t(0x80000000u));
  return FV<N>(reinterpret_cast<vf>(small ? signed_f : bits));
}
template <int N>
inline FV<N> load_lanes(const float* p, FV<N>) {
  return FV<N>::load(p);
}
template <int N>
inline void store_lanes(float* p, FV<N> x) {
  x.store(p);
}
template <int N>
inline IV<N> select(MV<N> m, IV<N> a, IV<N> b) {
  return IV<N>(m.v ? a.v : b.v);
}
template <int N>
inline IV<N> vmin(IV<N> a, IV<N> b) {
  return IV<N>(b.v < a.v ? b.v : a.v);
}
template <int N>
inline IV<N> vmax(IV<N> a, IV<N> b) {
  return IV<N>(a.v < b.v ? b.v : a.v);
}
template <int N>
inline IV<N> bits_of(FV<N> x) {
  IV<N> b;
  std::memcpy(&b.v, &x.v, sizeof b.v);
  return b;
}
template <int N>
inline FV<N> float_of_bits(IV<N> b) {
  FV<N> x;
  std::memcpy(&x.v, &b.v, sizeof x.v);
  return x;
}
template <int N>
inline int32_t lane(IV<N> x, int i) {
  return x.v[i];
}
template <int N>
inline void set_lane(IV<N>& x, int i, int32_t v) {
  x.v[i] = v;
}
template <int N>
inline FV<N> to_float(IV<N> i) {
  return FV<N>(__builtin_convertvector(i.v, vf_t<N>));
}
template <int N>
inline IV<N> trunc_to_int(FV<N> x) {
  return IV<N>(__builtin_convertvector(x.v, vi_t<N>));
}

// ---- generic helpers ----
template <class F>
inline F clamp(F x, F lo, F hi) {
  return vmin(vmax(x, lo), hi);
}
template <class F>
inline F mix(F a, F b, F t) {
  return a + (b - a) * t;
}
template <class F>
inline F saturate(F x) {
  return clamp<F>(x, F(0.0f), F(1.0f));
}
template <class F>
inline mask_t<F> true_mask() {
  return F(0.0f) == F(0.0f);
}
template <class F>
inline mask_t<F> false_mask() {
  return F(0.0f) != F(0.0f);
}

// log2 of x > 0 (normal numbers; smaller inputs read as FLT_MIN), absolute error below 1e-7:
// exponent bits plus an odd series of atanh over the mantissa in [sqrt(1/2), sqrt(2)). Written
// over F, so float and F8 give the same bits.
template <class F>
inline F vlog2(F x) {
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
      t * (F(2.0f) +
           t2 * (F(0.666666667f) + t2 * (F(0.4f) + t2 * (F(0.285714286f) + t2 * F(0.222222222f)))));
  return to_float(e) + series * F(1.44269504f);  // ln -> log2
}

// 2^y, relative error below 3e-7 (Cephes exp2f: y = n + f, |f| <= 1/2, 2^f = 1 + f P(f)), exact
// at whole y; y below -126 gives 0, above 127 gives 2^127 (finite), NaN reads as 0.
template <class F>
inline F vexp2(F y) {
  using I = int_t<F>;
  const mask_t<F> tiny = y < F(-126.0f);
  y = clamp<F>(select(y == y, y, F(0.0f)), F(-126.0f), F(127.0f));
  const F n = vfloor(y + F(0.5f));
  const F f = y - n;
  const F p = F(1.0f) +
              f * (F(6.931472028550421e-1f) +
                   f * (F(2.402264791363012e-1f) +
                        f * (F(5.550332471162809e-2f) +
                             f * (F(9.618437357674640e-3f) +
                                  f * (F(1.339887440266574e-3f) + f * F(1.535336188319500e-4f))))));
  const F scale = float_of_bits((trunc_to_int(n) + I(127)) << 23);
  return select(tiny, F(0.0f), p * scale);
}

// x^e for x >= 0 (GLSL pow's domain): exp2(e * log2(x)), relative error below
// 3e-7 * max(1, |e log2 x|) (float rounding of the exponent); 0^e is 0 for e > 0, 1 for e == 0.
template <class F>
inline F vpow_fast(F x, float e) {
  const F r = vexp2(F(e) * vlog2(x));
  return select(x > F(0.0f), r, F(e == 0.0f ? 1.0f : 0.0f));
}

// Applies a scalar function lane by lane: the bridge to per-lane work such as texture fetches.
template <class Fn>
inline float per_lane(float, Fn&& fn) {
  return fn(0);
}
template <int N, class Fn>
inline FV<N> per_lane(FV<N>, Fn&& fn) {
  FV<N> r;
  for (int i = 0; i < N; ++i) r.v[i] = fn(i);
  return r;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
// Code outside the per-target passes (tests, tools, scalar callers) names the static target's
// lane types and kernels as relief::F8, relief::V3 and so on.
namespace relief {
using namespace relief::HWY_NAMESPACE;
}
#endif

#endif  // RELIEF_SHADERS_LANES_H_
