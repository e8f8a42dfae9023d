// Texture sampling over lanes: the GLSL texture(), textureLod() and textureGrad() of kernels.
//
// 8-bit textures (R8, RG8, RGBA8) and R32F with nearest, bilinear, trilinear or (without
// derivatives) anisotropic filtering and repeat or clamp wrapping take a path written once over
// the lane type F: level choice, texel coordinates, weights and lerps run on all lanes at once.
// Texel loads and sRGB table lookups are gathers (Highway's GatherOffset and GatherIndex) on the
// SIMD targets that have them (AVX2, AVX-512) and lane by lane otherwise; both read the same
// bytes, so the results are the same bits. It follows rasterizer/texture.cpp operation for
// operation (GL 4.5, section 8.14), so textureLod equals sample_lod bit for bit; textureGrad takes
// its LOD from vlog2 (lanes.h), within 1e-7 of std::log2. Other textures and filters call the
// scalar sampler per lane. float and the lane types agree bit for bit either way. Kernels call the
// native-width sampler through the out-of-line entries of shaders_cpp/sampling_simd.h. Per-target
// header (lanes.h says how).

#if defined(RELIEF_SHADERS_CPP_SAMPLING_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_SAMPLING_H_
#undef RELIEF_SHADERS_CPP_SAMPLING_H_
#else
#define RELIEF_SHADERS_CPP_SAMPLING_H_
#endif

#include <bit>
#include <climits>
#include <type_traits>

#include "rasterizer/texture.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct V4 {
  F x, y, z, w;
  V3<F> xyz() const { return {x, y, z}; }
};

namespace detail {

// Whether the lane-parallel path serves this texture and sampler (textureLod rules).
// Wraps the lane paths compute (wrap_lanes): clamp and repeat on both axes.
inline bool lane_wraps_ok(const SamplerState& s) {
  const auto ok = [](Wrap w) { return w == Wrap::kClamp || w == Wrap::kRepeat; };
  return ok(s.wrap_u) && ok(s.wrap_v);
}

inline bool vector_sampling_ok(const Texture& t, const SamplerState& s) {
  const TexFormat f = t.format();
  const bool lanes = f == TexFormat::kR8 || f == TexFormat::kRG8 || f == TexFormat::kRGBA8 ||
                     f == TexFormat::kR32F;
  return lanes && lane_wraps_ok(s) && !t.empty();
}

// Wraps integer texel coordinates; `pow2` says every level size is a power of two.
template <class I>
inline I wrap_lanes(I i, I size, Wrap w, bool pow2) {
  if (w == Wrap::kClamp) return vmin(vmax(i, I(0)), size - I(1));
  if (pow2) return i & (size - I(1));  // two's complement: repeat for negative i too
  I r = i;
  for (int k = 0; k < lane_width<decltype(to_float(i))>; ++k)
    set_lane(r, k, wrap_texel(lane(i, k), lane(size, k), w));
  return r;
}

// The native-width reads below use Highway's ops on the targets that have gathers and a rounding
// instruction (AVX2 and AVX-512); elsewhere (the baseline EMU128 target, 8-lane types on a
// 16-lane target, float) they run lane by lane. Both read the same bytes and round the same way,
// so the results are the same bits.
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
inline constexpr bool kHaveGather = true;
#else
inline constexpr bool kHaveGather = false;
#endif
template <class F>
inline constexpr bool kHwyLanes = kHaveGather&& std::is_same_v<F, FN>;

#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
namespace hn = hwy::HWY_NAMESPACE;
using DF = hn::ScalableTag<float>;  // kLanes floats: FN
using DI = hn::RebindToSigned<DF>;
using DU = hn::RebindToUnsigned<DF>;
static_assert(hn::MaxLanes(DF()) == kLanes);
// FN / IN to and from Highway vectors of the same bits (both are GCC vectors underneath).
inline hn::Vec<DF> to_hwy(const FN& x) {
  hn::Vec<DF> r;
  r.raw = reinterpret_cast<decltype(r.raw)>(x.v);
  return r;
}
inline hn::Vec<DI> to_hwy(const IN& x) {
  hn::Vec<DI> r;
  r.raw = reinterpret_cast<decltype(r.raw)>(x.v);
  return r;
}
inline FN from_hwy(hn::Vec<DF> x) {
  return FN(reinterpret_cast<vf_t<kLanes>>(x.raw));
}
inline IN from_hwy(hn::Vec<DI> x) {
  return IN(reinterpret_cast<vi_t<kLanes>>(x.raw));
}
#endif

// vfloor of a texel coordinate (finite, from texel_coord): one rounding instruction on targets
// that have it, which rounds down exactly as std::floor does for every value but NaN (quieted,
// where vfloor passes the bits), which texel_coord never gives it.
template <class F>
[[gnu::always_inline]] inline F floor_coord(const F& x) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (kHwyLanes<F>) return from_hwy(hn::Floor(to_hwy(x)));
#endif
  return vfloor(x);
}

// u * size - offset with NaN read as 0, kept in int range (texture.cpp's scaled_coord). Highway's
// Max and Min with the bound first are x86's max_ps and min_ps, which are vmax and vmin (lanes.h)
// including NaN: a < b ? b : a.
template <class F>
inline F texel_coord(F u, F size, F offset) {
  const F x = select(u == u, u, F(0.0f)) * size - offset;
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (kHwyLanes<F>) {
    const DF d;
    return from_hwy(hn::Min(hn::Set(d, 67108864.0f), hn::Max(hn::Set(d, -67108864.0f), to_hwy(x))));
  }
#endif
  return vmin(vmax(x, F(-67108864.0f)), F(67108864.0f));
}

// base[idx] per lane (the sRGB table, shadow-map depths): a gather where the target has one.
template <class F>
[[gnu::always_inline]] inline F gather_f32(const float* lut, const int_t<F>& idx) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (kHwyLanes<F>) return from_hwy(hn::GatherIndex(DF(), lut, to_hwy(idx)));
#endif
  F r;
  for (int k = 0; k < lane_width<F>; ++k) set_lane(r, k, lut[lane(idx, k)]);
  return r;
}

// Whether bilinear_at gathers its texel words from `level`: native lanes on a target with
// gathers, a level of at least 4 bytes and small enough for 32-bit offsets; elsewhere it loads
// lane by lane.
template <class F>
inline bool can_gather(const MipLevel& level) {
  const size_t bytes = level.data.size();
  return kHwyLanes<F> && bytes >= 4 && bytes <= size_t(INT_MAX);
}

// kBytes * kTexels bytes (1 to 4) per lane of `level` at texel indices idx (can_gather said
// yes), in the low bytes of each lane's word with zeros above, as a lane-by-lane memcpy into a
// zeroed word makes it; with kTexels = 2, texels idx and idx + 1 in one word (idx + 1 must lie in
// the level), the first in the low kBytes bytes. Fewer than 4 bytes are read by a 4-byte load
// that ends inside the level: at the offset, or at bytes - 4 and shifted down near the end. A
// 4-byte span must lie inside the level.
template <int kBytes, int kTexels = 1, class I>
[[gnu::always_inline]] inline I gather_word(const MipLevel& level, const I& idx) {
  constexpr int kSpan = kBytes * kTexels;
  static_assert(kSpan <= 4);
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (std::is_same_v<I, IN>) {
    const DI di;
    const int32_t* base = reinterpret_cast<const int32_t*>(level.data.data());
    const IN off = idx * IN(kBytes);
    if constexpr (kSpan == 4) {
      return from_hwy(hn::GatherOffset(di, base, to_hwy(off)));
    } else {
      const IN at = vmin(off, IN(static_cast<int32_t>(level.data.size()) - 4));
      const auto word = hn::BitCast(DU(), hn::GatherOffset(di, base, to_hwy(at)));
      const auto shift = hn::BitCast(DU(), to_hwy((off - at) * IN(8)));
      const IN shifted = from_hwy(hn::BitCast(di, hn::Shr(word, shift)));
      return shifted & IN((1 << (8 * kSpan)) - 1);
    }
  }
#endif
  (void)level;
  return idx;  // not reached: can_gather is false wherever this is not a gather
}

// 32-bit words[idx] per lane (native lanes on a gather target only).
template <class I>
[[gnu::always_inline]] inline I gather_u32(const uint32_t* words, const I& idx) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if constexpr (std::is_same_v<I, IN>)
    return from_hwy(hn::GatherIndex(DI(), reinterpret_cast<const int32_t*>(words), to_hwy(idx)));
#endif
  (void)words;
  return idx;  // not reached: only bilinear_at's footprint path on a gather target calls it
}

// footprint_cell (rasterizer/texture.h) over lanes: repeat is the wrapped coordinate itself.
template <class I>
inline I footprint_cells(const I& i, const I& size, Wrap w, bool pow2) {
  if (w == Wrap::kClamp) return vmin(vmax(i, I(-1)), size - I(1)) + I(1);
  return wrap_lanes(i, size, w, pow2);
}

// 4-byte words idx and idx + 1 of a level (both inside it, can_gather said yes) a lane: two texels
// of a 4-byte format (RGBA8, R32F), or the two halves of the RGBA16F texel idx / 2. One 8-byte
// gather per lane (two 8-lane gathers for 16 lanes, two 4-lane gathers for 8), split into the
// first and second word. Half the gathered elements of two 4-byte gathers, the same words.
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
template <int N>
[[gnu::always_inline]] inline void gather_pair4(const MipLevel& level, const IV<N>& idx,
                                                IV<N>& first, IV<N>& second) {
  const auto* base = reinterpret_cast<const long long*>(level.data.data());
  const IV<N> off = idx * IV<N>(4);
  if constexpr (N == 16) {
    const __m512i o = reinterpret_cast<__m512i>(off.v);
    const __m512i lo = _mm512_i32gather_epi64(_mm512_castsi512_si256(o), base, 1);
    const __m512i hi = _mm512_i32gather_epi64(_mm512_extracti64x4_epi64(o, 1), base, 1);
    const __m512i even =
        _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    const __m512i odd =
        _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
    first = IV<N>(reinterpret_cast<vi_t<N>>(_mm512_permutex2var_epi32(lo, even, hi)));
    second = IV<N>(reinterpret_cast<vi_t<N>>(_mm512_permutex2var_epi32(lo, odd, hi)));
  } else {
    const __m256i o = reinterpret_cast<__m256i>(off.v);
    const __m256i lo = _mm256_i32gather_epi64(base, _mm256_castsi256_si128(o), 1);
    const __m256i hi = _mm256_i32gather_epi64(base, _mm256_extracti128_si256(o, 1), 1);
    // Per 128-bit half: lo's two even (odd) words, then hi's; then the halves' middle words swap.
    const __m256 lf = _mm256_castsi256_ps(lo), hf = _mm256_castsi256_ps(hi);
    const __m256i e = _mm256_castps_si256(_mm256_shuffle_ps(lf, hf, _MM_SHUFFLE(2, 0, 2, 0)));
    const __m256i d = _mm256_castps_si256(_mm256_shuffle_ps(lf, hf, _MM_SHUFFLE(3, 1, 3, 1)));
    first = IV<N>(reinterpret_cast<vi_t<N>>(_mm256_permute4x64_epi64(e, _MM_SHUFFLE(3, 1, 2, 0))));
    second = IV<N>(reinterpret_cast<vi_t<N>>(_mm256_permute4x64_epi64(d, _MM_SHUFFLE(3, 1, 2, 0))));
  }
}
#endif

// The formats of the lane-parallel path: bytes a texel and channels stored.
constexpr int texel_bytes(TexFormat f) {
  return f == TexFormat::kRG8 ? 2 : (f == TexFormat::kR8 ? 1 : 4);
}
constexpr int texel_channels(TexFormat f) {
  return f == TexFormat::kRGBA8 ? 4 : (f == TexFormat::kRG8 ? 2 : 1);
}

// byte / 255 (byte in [0, 255]) without the divider: 1/255 split into a 9-bit head, whose
// product with an 8-bit integer is exact, and a tail; the one rounding of the sum gives the
// correctly rounded quotient for all 256 bytes (tests/shaders_cpp/sampling_test.cpp checks
// every byte). The build never contracts the two products into an FMA (-ffp-contract=off). A
// 16-lane division is a long, poorly pipelined instruction on the way to every 8-bit read.
template <class F>
[[gnu::always_inline]] inline F unorm8_decode(const F& byte) {
  return byte * F(0x1.01p-8f) + byte * F(0x1.010102p-24f);
}

// Channel c (0..3) of 8-bit texels packed little-endian in `word`, decoded like texture.cpp.
template <int kChannels, class F>
inline F decode8(int_t<F> word, int c, const float* lut, bool srgb) {
  using I = int_t<F>;
  if (c >= kChannels) return F(c == 3 ? 1.0f : 0.0f);
  const I byte = (word >> (8 * c)) & I(0xff);
  if (!srgb || c == 3) return unorm8_decode(to_float(byte));  // == unorm8_table (tested)
  return gather_f32<F>(lut, byte);
}

// IEEE half (the low 16 bits of each lane of h) to float, texture.cpp's half_to_float over lanes:
// a normal half rebiased by one integer add, a subnormal (or zero) as mant * 2^-24 in float
// arithmetic (exact: a normal float), infinities and NaNs with their payload, then the sign. The
// same bits as the scalar function for all 65536 halves (tests/shaders_cpp/sampling_test.cpp).
template <class F>
[[gnu::always_inline]] inline F half_to_float_lanes(const int_t<F>& h) {
  using I = int_t<F>;
  const I sign = (h & I(0x8000)) << 16;
  const I mag = h & I(0x7fff);
  const I normal = (mag << 13) + I(112 << 23);
  const I special = I(0x7f800000) | ((mag & I(0x3ff)) << 13);
  const I subnormal = bits_of(to_float(mag) * F(0x1p-24f));
  const I bits = select(mag >= I(0x7c00), special, select(mag >= I(0x0400), normal, subnormal));
  return float_of_bits(bits | sign);
}

// Channel c of a texel word of format kFmt: 8-bit channels through decode8, R32F's one float as
// its bits (texture.cpp's Codec: missing channels read 0, alpha 1).
template <TexFormat kFmt, class F>
[[gnu::always_inline]] inline F decode_texel(int_t<F> word, int c, const float* lut, bool srgb) {
  if constexpr (kFmt == TexFormat::kR32F)
    return c == 0 ? float_of_bits(word) : F(c == 3 ? 1.0f : 0.0f);
  else
    return decode8<texel_channels(kFmt), F>(word, c, lut, srgb);
}

// The texel words at indices idx of per-lane level lvl, lane by lane (from `one` when every
// lane reads that one level, else from each lane's level).
template <int kBytes, class F>
[[gnu::always_inline]] inline int_t<F> load_words(const Texture& t, int_t<F> lvl,
                                                  const MipLevel* one, const int_t<F>& idx) {
  using I = int_t<F>;
  I r;
  const uint8_t* d0 = one ? one->data.data() : nullptr;
  for (int k = 0; k < lane_width<F>; ++k) {
    const uint8_t* d = d0 ? d0 : t.level(lane(lvl, k)).data.data();
    uint32_t v = 0;
    std::memcpy(&v, d + size_t(lane(idx, k)) * kBytes, kBytes);
    set_lane(r, k, static_cast<int32_t>(v));
  }
  return r;
}

// Where the texel words at per-lane level lvl come from: `level` when every lane reads one level
// (the usual case: LOD is per quad), else null; gathered from it when can_gather says so, else
// load_words.
struct WordSource {
  const MipLevel* level;
  bool gather;
  // the level's R8 footprints for the sampler's wraps (Texture::r8_footprints), where a prepared
  // read (prepare_r_lod) asked for them; bilinear_at then gathers one word a read
  Texture::Footprints footprints = {};
};
template <class F>
[[gnu::always_inline]] inline WordSource word_source(const Texture& t, int_t<F> lvl) {
  using I = int_t<F>;
  const int lvl0 = lane(lvl, 0);
  if (!all(lvl == I(lvl0))) return {nullptr, false};
  const MipLevel& level = t.level(lvl0);
  return {&level, can_gather<F>(level)};
}

// Each lane's level size in texels (at least 1), and log2 of the width where the texture's sizes
// are powers of two (rows are then addressed by a shift: a multiply is a long latency on the way
// to the gather).
template <class I>
struct LevelSize {
  I w, h, w_shift;
};
inline int width_log2(const Texture& t) {
  return std::countr_zero(static_cast<unsigned>(t.width()));
}
template <class I>
inline LevelSize<I> level_size(const Texture& t, I lvl) {
  return {vmax(I(t.width()) >> lvl, I(1)), vmax(I(t.height()) >> lvl, I(1)),
          vmax(I(width_log2(t)) - lvl, I(0))};
}
// Row offset y * w of each lane: y << w_shift for power-of-two textures (the same value).
template <class I>
inline I row_offset(const I& y, const LevelSize<I>& size, bool pow2) {
  if (!pow2) return y * size.w;
  if constexpr (is_lanes_v<decltype(to_float(y))>)
    return I(y.v << size.w_shift.v);
  else
    return y << size.w_shift;
}

// Where a read at per-lane mip level `lvl` finds its texels: the level's sizes and word source.
// A prepared read (RLodPlan, sampling_simd.h) computes it once for many reads.
template <class I>
struct LevelAccess {
  I lvl;
  LevelSize<I> size;
  WordSource src;
};
template <class F>
inline LevelAccess<int_t<F>> level_access(const Texture& t, int_t<F> lvl) {
  return {lvl, level_size(t, lvl), word_source<F>(t, lvl)};
}

// The texel space of a bilinear read at uv on a level of size (w, h): the integer corner (ix, iy)
// of its 2x2 footprint and the weights a, b of its second column and row.
template <class F>
struct BilinearCorner {
  int_t<F> ix, iy;
  F a, b;
};
// The level's size (w, h) as floats: bilinear_corner_sized; as integers: bilinear_corner.
template <class F>
[[gnu::always_inline]] inline BilinearCorner<F> bilinear_corner_sized(const V2<F>& uv, const F& w,
                                                                      const F& h) {
  const F xf = texel_coord(uv.x, w, F(0.5f));
  const F yf = texel_coord(uv.y, h, F(0.5f));
  const F fx = floor_coord(xf), fy = floor_coord(yf);
  return {trunc_to_int(fx), trunc_to_int(fy), xf - fx, yf - fy};
}
template <class F>
[[gnu::always_inline]] inline BilinearCorner<F> bilinear_corner(const V2<F>& uv, const int_t<F>& w,
                                                                const int_t<F>& h) {
  return bilinear_corner_sized<F>(uv, to_float(w), to_float(h));
}

// The four R8 texels (t00, t10, t01, t11 in bytes 0 to 3) of the bilinear footprint with corner
// (ix, iy) on a level whose footprint words (Texture::r8_footprints) are `words`, `pitch` of them
// a row: one gathered word.
template <class I>
[[gnu::always_inline]] inline I footprint_word(const uint32_t* words, const I& pitch,
                                               const SamplerState& s, const I& ix, const I& iy,
                                               const LevelSize<I>& size, bool pow2) {
  const I col = footprint_cells(ix, size.w, s.wrap_u, pow2);
  const I row = footprint_cells(iy, size.h, s.wrap_v, pow2);
  // repeat across: a row is the level's width, a shift where it is a power of two
  const I idx = s.wrap_u == Wrap::kRepeat ? row_offset(row, size, pow2) + col : row * pitch + col;
  return gather_u32(words, idx);
}

// Channels 0 .. kUsed - 1 of the bilinear blend of four texel words: each corner decoded, then
// lerped along x by a and along y by b (GL's decode-then-filter order).
template <TexFormat kFmt, int kUsed, class F>
[[gnu::always_inline]] inline V4<F> bilinear_blend(const int_t<F>& t00, const int_t<F>& t10,
                                                   const int_t<F>& t01, const int_t<F>& t11,
                                                   const F& a, const F& b, const float* lut,
                                                   bool srgb) {
  F out[4] = {F(0.0f), F(0.0f), F(0.0f), F(0.0f)};
  for (int c = 0; c < kUsed; ++c) {
    const F c00 = decode_texel<kFmt, F>(t00, c, lut, srgb);
    const F c10 = decode_texel<kFmt, F>(t10, c, lut, srgb);
    const F c01 = decode_texel<kFmt, F>(t01, c, lut, srgb);
    const F c11 = decode_texel<kFmt, F>(t11, c, lut, srgb);
    const F top = c00 + a * (c10 - c00);
    const F bottom = c01 + a * (c11 - c01);
    out[c] = top + b * (bottom - top);
  }
  return {out[0], out[1], out[2], out[3]};
}

// A level as a planned read takes it, every value already in lanes (RLodPlan keeps one per level
// of its footprint and nearest reads: no broadcast or conversion per read): its size, and its
// footprint words where it has them.
template <class F>
struct LevelLanes {
  F w, h;                    // the level's size, as floats
  LevelSize<int_t<F>> size;  // and as integers, for the wraps
  int_t<F> pitch;            // footprint words a row
  const uint32_t* words;     // Texture::r8_footprints, or null
};
template <class F>
inline LevelLanes<F> level_lanes(const LevelSize<int32_t>& size, const Texture::Footprints& fp) {
  using I = int_t<F>;
  return {F(static_cast<float>(size.w)),
          F(static_cast<float>(size.h)),
          {I(size.w), I(size.h), I(size.w_shift)},
          I(fp.width),
          fp.words};
}

// GL bilinear of an R8 level with footprint words, channel 0: bilinear_at's bits, with none of
// its other paths. `lut` is srgb8_table() for an sRGB texture, else null.
template <class F>
[[gnu::always_inline]] inline F bilinear_footprint_at(const SamplerState& s, const V2<F>& uv,
                                                      const LevelLanes<F>& l, bool pow2,
                                                      const float* lut) {
  const BilinearCorner<F> k = bilinear_corner_sized<F>(uv, l.w, l.h);
  const int_t<F> word = footprint_word(l.words, l.pitch, s, k.ix, k.iy, l.size, pow2);
  return bilinear_blend<TexFormat::kR8, 1, F>(word, word >> 8, word >> 16, word >> 24, k.a, k.b,
                                              lut, lut != nullptr)
      .x;
}

// GL bilinear at the mip level(s) `at` of a texture of format kFmt.
template <TexFormat kFmt, int kUsed, class F>
[[gnu::always_inline]] inline V4<F> bilinear_at(const Texture& t, const SamplerState& s, V2<F> uv,
                                                const LevelAccess<int_t<F>>& at, bool pow2) {
  using I = int_t<F>;
  const I& lvl = at.lvl;
  const I &w = at.size.w, &h = at.size.h;
  const BilinearCorner<F> k = bilinear_corner<F>(uv, w, h);
  const I &ix = k.ix, &iy = k.iy;
  const WordSource& src = at.src;
  constexpr int kB = texel_bytes(kFmt);
  I t00, t10, t01, t11;
  bool gathered = false;
  if constexpr (kHwyLanes<F> && kFmt == TexFormat::kR8) {
    if (src.footprints.words) {  // the four texels in one word (Texture::r8_footprints)
      gathered = true;
      const I word =
          footprint_word(src.footprints.words, I(src.footprints.width), s, ix, iy, at.size, pow2);
      t00 = word;  // decode8 takes each texel's byte
      t10 = word >> 8;
      t01 = word >> 16;
      t11 = word >> 24;
    }
  }
  if (!gathered) {  // the texels of the four corners, wrapped apart
    const I x0 = wrap_lanes(ix, w, s.wrap_u, pow2), x1 = wrap_lanes(ix + I(1), w, s.wrap_u, pow2);
    const I y0 = wrap_lanes(iy, h, s.wrap_v, pow2), y1 = wrap_lanes(iy + I(1), h, s.wrap_v, pow2);
    const I r0 = row_offset(y0, at.size, pow2), r1 = row_offset(y1, at.size, pow2);
    if constexpr (kHwyLanes<F>) {
      if (src.gather) {
        gathered = true;
        const MipLevel& level = *src.level;
        // No lane on the wrap seam: each row's two texels in one word (R8, RG8) or one 8-byte
        // gather (4-byte texels).
        const bool pairs = all(x1 == x0 + I(1));
        if (pairs) {
          if constexpr (kB <= 2) {
            constexpr int32_t kMask = (1 << (8 * kB)) - 1;
            const I top = gather_word<kB, 2>(level, r0 + x0);
            const I bottom = gather_word<kB, 2>(level, r1 + x0);
            t00 = top & I(kMask);
            t10 = (top >> (8 * kB)) & I(kMask);
            t01 = bottom & I(kMask);
            t11 = (bottom >> (8 * kB)) & I(kMask);
          } else {
            gather_pair4(level, r0 + x0, t00, t10);
            gather_pair4(level, r1 + x0, t01, t11);
          }
        } else {
          t00 = gather_word<kB>(level, r0 + x0);
          t10 = gather_word<kB>(level, r0 + x1);
          t01 = gather_word<kB>(level, r1 + x0);
          t11 = gather_word<kB>(level, r1 + x1);
        }
      }
    }
    if (!gathered) {
      t00 = load_words<kB, F>(t, lvl, src.level, r0 + x0);
      t10 = load_words<kB, F>(t, lvl, src.level, r0 + x1);
      t01 = load_words<kB, F>(t, lvl, src.level, r1 + x0);
      t11 = load_words<kB, F>(t, lvl, src.level, r1 + x1);
    }
  }
  const bool srgb = t.color_space() == ColorSpace::kSRGB;
  const float* lut = srgb ? srgb8_table() : nullptr;  // decode8 reads it for sRGB only
  return bilinear_blend<kFmt, kUsed, F>(t00, t10, t01, t11, k.a, k.b, lut, srgb);
}

// The texel GL nearest filtering reads at uv on a level of size n, (w, h) as floats
// (texture.cpp's sample_nearest): its index in the level, row by row.
template <class F>
[[gnu::always_inline]] inline int_t<F> nearest_index_sized(const SamplerState& s, V2<F> uv,
                                                           const F& w, const F& h,
                                                           const LevelSize<int_t<F>>& n,
                                                           bool pow2) {
  using I = int_t<F>;
  const F xf = floor_coord(texel_coord(uv.x, w, F(0.0f)));
  const F yf = floor_coord(texel_coord(uv.y, h, F(0.0f)));
  const I x = wrap_lanes(trunc_to_int(xf), n.w, s.wrap_u, pow2);
  const I y = wrap_lanes(trunc_to_int(yf), n.h, s.wrap_v, pow2);
  return row_offset(y, n, pow2) + x;
}
template <class F>
[[gnu::always_inline]] inline int_t<F> nearest_index(const SamplerState& s, V2<F> uv,
                                                     const LevelSize<int_t<F>>& n, bool pow2) {
  return nearest_index_sized<F>(s, uv, to_float(n.w), to_float(n.h), n, pow2);
}

// The texel at index idx of the level(s) lvl, whose words `src` holds, decoded (nearest_at's
// read; the level's size is in idx already).
template <TexFormat kFmt, int kUsed, class F>
[[gnu::always_inline]] inline V4<F> nearest_texel(const Texture& t, const int_t<F>& idx,
                                                  const int_t<F>& lvl, const WordSource& src) {
  using I = int_t<F>;
  constexpr int kB = texel_bytes(kFmt);
  I word;
  if constexpr (kHwyLanes<F>)
    word =
        src.gather ? gather_word<kB>(*src.level, idx) : load_words<kB, F>(t, lvl, src.level, idx);
  else
    word = load_words<kB, F>(t, lvl, src.level, idx);
  const bool srgb = t.color_space() == ColorSpace::kSRGB;
  const float* lut = srgb ? srgb8_table() : nullptr;
  F out[4] = {F(0.0f), F(0.0f), F(0.0f), F(0.0f)};
  for (int c = 0; c < kUsed; ++c) out[c] = decode_texel<kFmt, F>(word, c, lut, srgb);
  return {out[0], out[1], out[2], out[3]};
}

// GL nearest at the mip level(s) `at` (texture.cpp's sample_nearest).
template <TexFormat kFmt, int kUsed, class F>
[[gnu::always_inline]] inline V4<F> nearest_at(const Texture& t, const SamplerState& s, V2<F> uv,
                                               const LevelAccess<int_t<F>>& at, bool pow2) {
  return nearest_texel<kFmt, kUsed, F>(t, nearest_index<F>(s, uv, at.size, pow2), at.lvl, at.src);
}

template <class F>
inline V4<F> lerp4(V4<F> p, V4<F> q, F f) {
  return {p.x + f * (q.x - p.x), p.y + f * (q.y - p.y), p.z + f * (q.z - p.z),
          p.w + f * (q.w - p.w)};
}

// The mip levels textureLod reads at lod (texture.cpp's sample_lod_impl, lane by lane): `lo`,
// and for trilinear (or anisotropic without derivatives) `hi` weighted by f, f = 0 where one
// level is exact. Nearest and bilinear filters read the level nearest to lod (f = 0).
template <class F>
struct LodLevels {
  int_t<F> lo, hi;
  F f;
};
template <class F>
inline LodLevels<F> lod_levels(int levels, Filter filter, F lod) {
  using I = int_t<F>;
  const int q = levels - 1;
  lod = vmin(vmax(select(lod == lod, lod, F(0.0f)), F(-64.0f)), F(64.0f));
  if (q == 0) return {I(0), I(0), F(0.0f)};
  const F fq = F(static_cast<float>(q));
  if (filter == Filter::kNearest || filter == Filter::kBilinear) {
    // NEAREST_MIPMAP_NEAREST and LINEAR_MIPMAP_NEAREST: the level nearest to lod.
    I lvl = vmin(trunc_to_int(-vfloor(-(lod + F(0.5f)))) - I(1), I(q));  // ceil
    lvl = select(lod <= F(0.5f), I(0), select(lod > fq + F(0.5f), I(q), lvl));
    return {lvl, lvl, F(0.0f)};
  }
  const mask_t<F> base = lod <= F(0.0f);
  const F fl = vfloor(lod);
  const mask_t<F> top = lod >= fq;
  const I d1 = select(base, I(0), select(top, I(q), trunc_to_int(vmax(fl, F(0.0f)))));
  return {d1, vmin(d1 + I(1), I(q)), select(base | top, F(0.0f), lod - fl)};
}

// Whether every level size of t is a power of two (wrap_lanes' shortcut).
inline bool pow2_texture(const Texture& t) {
  return (t.width() & (t.width() - 1)) == 0 && (t.height() & (t.height() - 1)) == 0;
}

// One filtered read at the level(s) `at`: nearest or bilinear by the sampler's filter.
template <TexFormat kFmt, int kUsed, class F>
[[gnu::always_inline]] inline V4<F> filter_at(const Texture& t, const SamplerState& s, V2<F> uv,
                                              const LevelAccess<int_t<F>>& at, bool pow2) {
  return s.filter == Filter::kNearest ? nearest_at<kFmt, kUsed, F>(t, s, uv, at, pow2)
                                      : bilinear_at<kFmt, kUsed, F>(t, s, uv, at, pow2);
}

// textureLod on the lane-parallel path (texture.cpp's sample_lod_impl, lane by lane).
template <TexFormat kFmt, int kUsed, class F>
inline V4<F> sample_lod_texels(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  const bool pow2 = pow2_texture(t);
  const LodLevels<F> l = lod_levels(t.levels(), s.filter, lod);
  const V4<F> t1 = filter_at<kFmt, kUsed, F>(t, s, uv, level_access<F>(t, l.lo), pow2);
  if (none(l.f != F(0.0f))) return t1;
  const V4<F> t2 = bilinear_at<kFmt, kUsed, F>(t, s, uv, level_access<F>(t, l.hi), pow2);
  return lerp4(t1, t2, l.f);
}

template <int kUsed, class F>
inline V4<F> sample_lod_lanes(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  switch (t.format()) {
    case TexFormat::kR8:
      return sample_lod_texels<TexFormat::kR8, kUsed, F>(t, s, uv, lod);
    case TexFormat::kRG8:
      return sample_lod_texels<TexFormat::kRG8, kUsed, F>(t, s, uv, lod);
    case TexFormat::kR32F:
      return sample_lod_texels<TexFormat::kR32F, kUsed, F>(t, s, uv, lod);
    default:
      return sample_lod_texels<TexFormat::kRGBA8, kUsed, F>(t, s, uv, lod);
  }
}

// GL's LOD from uv derivatives (texture.cpp's compute_lod) with vlog2. rho = max(|a|, |b|) is
// taken as sqrt(max(|a|^2, |b|^2)): the same bits (a correctly rounded sqrt never reverses an
// order, and vmax keeps the first operand on ties and NaN) for one square root instead of two.
template <class F>
inline F lod_from_grad(const Texture& t, V2<F> dx, V2<F> dy) {
  const F w(static_cast<float>(t.width())), h(static_cast<float>(t.height()));
  const F ax = dx.x * w, ay = dx.y * h, bx = dy.x * w, by = dy.y * h;
  const F rho = vsqrt(vmax(ax * ax + ay * ay, bx * bx + by * by));
  const F lod = vmin(vmax(vlog2(rho), F(-64.0f)), F(64.0f));
  return select(rho == rho, select(rho <= F(0.0f), F(-64.0f), lod), F(0.0f));
}

// Lane i of r = c.
template <class F>
inline void set_lane4(V4<F>& r, int i, const glm::vec4& c) {
  set_lane(r.x, i, c.x);
  set_lane(r.y, i, c.y);
  set_lane(r.z, i, c.z);
  set_lane(r.w, i, c.w);
}

}  // namespace detail

// The LOD texture_grad's lane path computed last (detail::lod_from_grad), for the texture size
// and uv derivatives it was computed from: a kernel reads several textures with the same
// derivatives (colour, normal map, ...), mostly of one size, and the LOD (a square root and a
// logarithm with a division, on the way to the first texel load) is then computed once a packet.
// Reuse is decided on the inputs' bits, so it gives the bits of computing it again.
template <class F>
struct GradLodMemo {
  // User-provided, so that it is compiled for this namespace's target (plugins/shading.h,
  // ShadeOut).
  GradLodMemo() {}
  int width = 0, height = 0;  // 0: nothing kept yet
  V2<F> dx, dy;
  F lod;

  // The LOD for texture t and derivatives dx, dy: kept, or computed and kept.
  const F& lod_for(const Texture& t, const V2<F>& dx_now, const V2<F>& dy_now) {
    const auto same = [](const F& a, const F& b) { return all(bits_of(a) == bits_of(b)); };
    if (width != t.width() || height != t.height() || !same(dx.x, dx_now.x) ||
        !same(dx.y, dx_now.y) || !same(dy.x, dy_now.x) || !same(dy.y, dy_now.y)) {
      width = t.width();
      height = t.height();
      dx = dx_now;
      dy = dy_now;
      lod = detail::lod_from_grad(t, dx_now, dy_now);
    }
    return lod;
  }
};

// Whether texture_grad reads t through the lane path at a LOD from detail::lod_from_grad (else
// it reads lane by lane through the scalar sampler, anisotropic filtering included).
inline bool grad_reads_at_lod(const Texture& t, const SamplerState& s) {
  return s.filter != Filter::kAnisotropic && detail::vector_sampling_ok(t, s);
}

template <class F>
inline V4<F> texture_grad(const Texture& t, const SamplerState& s, V2<F> uv, V2<F> dx, V2<F> dy) {
  if (grad_reads_at_lod(t, s))
    return detail::sample_lod_lanes<4>(t, s, uv, detail::lod_from_grad(t, dx, dy));
  V4<F> r;
  for (int i = 0; i < lane_width<F>; ++i) {
    const glm::vec4 c = sample_grad(t, s, {lane(uv.x, i), lane(uv.y, i)},
                                    {lane(dx.x, i), lane(dx.y, i)}, {lane(dy.x, i), lane(dy.y, i)});
    detail::set_lane4(r, i, c);
  }
  return r;
}

template <class F>
inline V4<F> texture_lod(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  if (detail::vector_sampling_ok(t, s)) return detail::sample_lod_lanes<4>(t, s, uv, lod);
  V4<F> r;
  for (int i = 0; i < lane_width<F>; ++i) {
    const glm::vec4 c = sample_lod(t, s, {lane(uv.x, i), lane(uv.y, i)}, lane(lod, i));
    detail::set_lane4(r, i, c);
  }
  return r;
}

template <class F>
inline F texture_r_lod(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  if (detail::vector_sampling_ok(t, s)) return detail::sample_lod_lanes<1>(t, s, uv, lod).x;
  return per_lane(uv.x, [&](int i) {
    return sample_r_lod(t, s, {lane(uv.x, i), lane(uv.y, i)}, lane(lod, i));
  });
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_SAMPLING_H_
