// Textures and sampling for the CPU backend: storage, decoding, mip generation and the GL 4.5
// (section 8.14) minification/magnification rules; anisotropy after EXT_texture_filter_anisotropic.
#include "rasterizer/texture.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iterator>
#include <mutex>

#include "base/check.h"
#include "rasterizer/srgb_bytes.h"

namespace relief {

namespace {

// One row per TexFormat, in enum order: channels, bytes per texel, name.
struct FormatInfo {
  int channels;
  int bytes;
  const char* name;
};
constexpr FormatInfo kFormats[] = {
    {1, 1, "R8"},   {2, 2, "RG8"},     {4, 4, "RGBA8"}, {1, 2, "R16"},
    {1, 2, "R16F"}, {4, 8, "RGBA16F"}, {1, 4, "R32F"},
};
static_assert(std::size(kFormats) == static_cast<size_t>(TexFormat::kR32F) + 1);

}  // namespace

int format_channels(TexFormat f) {
  return kFormats[static_cast<int>(f)].channels;
}
int format_bytes_per_texel(TexFormat f) {
  return kFormats[static_cast<int>(f)].bytes;
}
const char* format_name(TexFormat f) {
  return kFormats[static_cast<int>(f)].name;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Scalar conversions.

// Exact for every half: normals rebias the exponent with one integer add, subnormals and zeros
// are mant * 2^-24 in float arithmetic (a normal float, so no denormal mode can touch it), and
// infinities and NaNs keep their payload. No loop, so it inlines into the texel decoders (the
// normalising loop it replaced kept it out of line: 12% of a `cone_quad` frame, whose RGBA16F cone
// map decodes four halves a read).
inline float half_to_float(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000u) << 16;
  const uint32_t magnitude = h & 0x7fffu;
  uint32_t bits;
  if (magnitude >= 0x7c00u) {
    bits = 0x7f800000u | ((magnitude & 0x3ffu) << 13);  // inf / NaN
  } else if (magnitude >= 0x0400u) {
    bits = (magnitude << 13) + (112u << 23);  // normal: rebias 15 -> 127
  } else {
    const float f = static_cast<float>(magnitude) * 0x1p-24f;  // subnormal or zero
    std::memcpy(&bits, &f, sizeof bits);
  }
  bits |= sign;
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// Round to nearest even; overflow saturates to the largest finite half, NaN becomes 0.
uint16_t float_to_half(float f) {
  uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  const uint16_t sign = static_cast<uint16_t>((bits >> 16) & 0x8000u);
  const uint32_t abs = bits & 0x7fffffffu;
  if (abs > 0x7f800000u) return 0;                                       // NaN
  if (abs >= 0x477ff000u) return static_cast<uint16_t>(sign | 0x7bffu);  // >= 65520 rounds past max
  if (abs >= 0x38800000u) {  // normal half range (>= 2^-14)
    const uint32_t e = (abs >> 23) - 112u;
    const uint32_t m = abs & 0x7fffffu;
    uint32_t h = (e << 10) | (m >> 13);
    const uint32_t rest = m & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;  // carry may bump the exponent
    if (h > 0x7bffu) h = 0x7bffu;
    return static_cast<uint16_t>(sign | h);
  }
  if (abs < 0x33000000u) return sign;  // below half the smallest subnormal: rounds to zero
  // Subnormal half: value = m * 2^-24.
  const uint32_t e = abs >> 23;
  const uint32_t m = (abs & 0x7fffffu) | 0x800000u;
  const uint32_t shift = 126u - e;  // 14..24
  uint32_t h = m >> shift;
  const uint32_t rest = m & ((1u << shift) - 1u);
  const uint32_t halfway = 1u << (shift - 1u);
  if (rest > halfway || (rest == halfway && (h & 1u))) ++h;
  return static_cast<uint16_t>(sign | h);
}

double srgb_to_linear_d(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double linear_to_srgb_d(double c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

struct Tables {
  std::array<float, 256> unorm8;
  std::array<float, 256> srgb8;
  Tables() {
    for (int i = 0; i < 256; ++i) {
      unorm8[i] = static_cast<float>(i / 255.0);
      srgb8[i] = static_cast<float>(srgb_to_linear_d(i / 255.0));
    }
  }
};
const Tables& tables() {
  static const Tables t;
  return t;
}

// Largest magnitude kept in float formats: differences and weighted sums of texels stay finite.
constexpr float kMaxTexelMagnitude = 1.8446744e19f;  // 2^64

float sanitize_float(float v) {
  if (v != v) return 0.0f;
  return std::min(std::max(v, -kMaxTexelMagnitude), kMaxTexelMagnitude);
}

uint8_t encode_unorm8(float v) {
  if (!(v > 0.0f)) return 0;  // also NaN
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(static_cast<double>(v) * 255.0));
}
}  // namespace

uint8_t encode_srgb8(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 255;
  return static_cast<uint8_t>(std::lround(linear_to_srgb_d(v) * 255.0));
}

namespace {

uint16_t encode_unorm16(float v) {
  if (!(v > 0.0f)) return 0;
  if (v >= 1.0f) return 65535;
  return static_cast<uint16_t>(std::lround(static_cast<double>(v) * 65535.0));
}

constexpr float kInv65535 = 1.0f / 65535.0f;

// ---------------------------------------------------------------------------------------------
// Per-format texel codecs. `lut` is the decode table of 8-bit colour channels (unorm or sRGB).

template <TexFormat F>
struct Codec;

template <>
struct Codec<TexFormat::kR8> {
  static constexpr int kBytes = 1;
  static float r(const uint8_t* p, const float* lut) { return lut[p[0]]; }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {lut[p[0]], 0.0f, 0.0f, 1.0f};
  }
};
template <>
struct Codec<TexFormat::kRG8> {
  static constexpr int kBytes = 2;
  static float r(const uint8_t* p, const float* lut) { return lut[p[0]]; }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {lut[p[0]], lut[p[1]], 0.0f, 1.0f};
  }
};
template <>
struct Codec<TexFormat::kRGBA8> {
  static constexpr int kBytes = 4;
  static float r(const uint8_t* p, const float* lut) { return lut[p[0]]; }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {lut[p[0]], lut[p[1]], lut[p[2]], tables().unorm8[p[3]]};
  }
};
template <>
struct Codec<TexFormat::kR16> {
  static constexpr int kBytes = 2;
  static float r(const uint8_t* p, const float*) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return static_cast<float>(v) * kInv65535;
  }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {r(p, lut), 0.0f, 0.0f, 1.0f};
  }
};
template <>
struct Codec<TexFormat::kR16F> {
  static constexpr int kBytes = 2;
  static float r(const uint8_t* p, const float*) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return half_to_float(v);
  }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {r(p, lut), 0.0f, 0.0f, 1.0f};
  }
};
template <>
struct Codec<TexFormat::kRGBA16F> {
  static constexpr int kBytes = 8;
  static float r(const uint8_t* p, const float*) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return half_to_float(v);
  }
  static glm::vec4 rgba(const uint8_t* p, const float*) {
    uint16_t v[4];
    std::memcpy(v, p, 8);
    return {half_to_float(v[0]), half_to_float(v[1]), half_to_float(v[2]), half_to_float(v[3])};
  }
};
template <>
struct Codec<TexFormat::kR32F> {
  static constexpr int kBytes = 4;
  static float r(const uint8_t* p, const float*) {
    float v;
    std::memcpy(&v, p, 4);
    return v;
  }
  static glm::vec4 rgba(const uint8_t* p, const float* lut) {
    return {r(p, lut), 0.0f, 0.0f, 1.0f};
  }
};

// Calls f(std::integral_constant<TexFormat, F>{}) for the runtime format: one switch per call.
template <class Fn>
decltype(auto) dispatch(TexFormat format, Fn&& f) {
  switch (format) {
    case TexFormat::kR8:
      return f(std::integral_constant<TexFormat, TexFormat::kR8>{});
    case TexFormat::kRG8:
      return f(std::integral_constant<TexFormat, TexFormat::kRG8>{});
    case TexFormat::kRGBA8:
      return f(std::integral_constant<TexFormat, TexFormat::kRGBA8>{});
    case TexFormat::kR16:
      return f(std::integral_constant<TexFormat, TexFormat::kR16>{});
    case TexFormat::kR16F:
      return f(std::integral_constant<TexFormat, TexFormat::kR16F>{});
    case TexFormat::kRGBA16F:
      return f(std::integral_constant<TexFormat, TexFormat::kRGBA16F>{});
    case TexFormat::kR32F:
      return f(std::integral_constant<TexFormat, TexFormat::kR32F>{});
  }
  return f(std::integral_constant<TexFormat, TexFormat::kR8>{});
}

bool is_8bit(TexFormat f) {
  return f == TexFormat::kR8 || f == TexFormat::kRG8 || f == TexFormat::kRGBA8;
}

// Decodes a whole level to linear float channels (format_channels per texel).
std::vector<float> decode_level(TexFormat format, ColorSpace cs, const MipLevel& level) {
  const int ch = format_channels(format);
  const int bpt = format_bytes_per_texel(format);
  const size_t n = static_cast<size_t>(level.width) * level.height;
  const float* lut = cs == ColorSpace::kSRGB ? tables().srgb8.data() : tables().unorm8.data();
  std::vector<float> out(n * ch);
  dispatch(format, [&](auto fc) {
    using C = Codec<decltype(fc)::value>;
    for (size_t i = 0; i < n; ++i) {
      const glm::vec4 v = C::rgba(level.data.data() + i * bpt, lut);
      for (int c = 0; c < ch; ++c) out[i * ch + c] = v[c];
    }
  });
  return out;
}

// One mip level from the level above (sw x sh, ch channels) into dst (dw x dh): output texel i
// covers source [i*sw/dw, (i+1)*sw/dw), a 2-texel block for even sizes and a 3-texel block
// (middle texel shared, half weight) for odd ones, so min/max stay conservative; the average
// weights each source texel by its overlap, in double.
void reduce_level(const float* src, int sw, int sh, int dw, int dh, int ch, MipReduce reduce,
                  float* dst) {
  for (int j = 0; j < dh; ++j) {
    const double y_lo = static_cast<double>(j) * sh / dh;
    const double y_hi = static_cast<double>(j + 1) * sh / dh;
    const int y0 = static_cast<int>(std::floor(y_lo));
    const int y1 = std::min(sh, static_cast<int>(std::ceil(y_hi)));
    for (int i = 0; i < dw; ++i) {
      const double x_lo = static_cast<double>(i) * sw / dw;
      const double x_hi = static_cast<double>(i + 1) * sw / dw;
      const int x0 = static_cast<int>(std::floor(x_lo));
      const int x1 = std::min(sw, static_cast<int>(std::ceil(x_hi)));
      float* out = dst + (static_cast<size_t>(j) * dw + i) * ch;
      for (int c = 0; c < ch; ++c) {
        double acc = reduce == MipReduce::kAverage ? 0.0
                     : reduce == MipReduce::kMin   ? HUGE_VAL
                                                   : -HUGE_VAL;
        double wsum = 0.0;
        for (int y = y0; y < y1; ++y) {
          const double wyv = std::min<double>(y + 1, y_hi) - std::max<double>(y, y_lo);
          for (int x = x0; x < x1; ++x) {
            const double v = src[(static_cast<size_t>(y) * sw + x) * ch + c];
            if (reduce == MipReduce::kAverage) {
              const double w = wyv * (std::min<double>(x + 1, x_hi) - std::max<double>(x, x_lo));
              acc += w * v;
              wsum += w;
            } else if (reduce == MipReduce::kMin) {
              acc = std::min(acc, v);
            } else {
              acc = std::max(acc, v);
            }
          }
        }
        out[c] = static_cast<float>(reduce == MipReduce::kAverage ? acc / wsum : acc);
      }
    }
  }
}

// reduce_level's average where both sizes halve exactly: every output texel is the 2 x 2 block
// under it, every weight 1, so the sum runs in the same order on the same doubles and gives the
// same bits without the overlap arithmetic.
void average_2x2(const float* src, int sw, int dw, int dh, int ch, float* dst) {
  for (int j = 0; j < dh; ++j) {
    const float* row0 = src + static_cast<size_t>(2 * j) * sw * ch;
    const float* row1 = row0 + static_cast<size_t>(sw) * ch;
    float* out = dst + static_cast<size_t>(j) * dw * ch;
    for (int i = 0; i < dw; ++i)
      for (int c = 0; c < ch; ++c) {
        const size_t a = static_cast<size_t>(2 * i) * ch + c, b = a + ch;
        double acc = 0.0;
        acc += static_cast<double>(row0[a]);
        acc += static_cast<double>(row0[b]);
        acc += static_cast<double>(row1[a]);
        acc += static_cast<double>(row1[b]);
        out[static_cast<size_t>(i) * ch + c] = static_cast<float>(acc / 4.0);
      }
  }
}

// Encodes linear float channels into `format` (sRGB colour for 8-bit formats when cs is kSRGB).
void encode_level(TexFormat format, ColorSpace cs, const float* values, size_t n,
                  std::vector<uint8_t>& out) {
  const int ch = format_channels(format);
  const int bpt = format_bytes_per_texel(format);
  out.assign(n * bpt, 0);
  const bool srgb = cs == ColorSpace::kSRGB;
  for (size_t i = 0; i < n; ++i) {
    uint8_t* p = out.data() + i * bpt;
    const float* v = values + i * ch;
    switch (format) {
      case TexFormat::kR8:
      case TexFormat::kRG8:
      case TexFormat::kRGBA8:
        for (int c = 0; c < ch; ++c) {
          const bool colour = srgb && c < 3;
          p[c] = colour ? srgb_byte(v[c]) : encode_unorm8(v[c]);  // encode_srgb8's byte
        }
        break;
      case TexFormat::kR16: {
        const uint16_t h = encode_unorm16(v[0]);
        std::memcpy(p, &h, 2);
        break;
      }
      case TexFormat::kR16F:
      case TexFormat::kRGBA16F:
        for (int c = 0; c < ch; ++c) {
          const uint16_t h = float_to_half(v[c]);
          std::memcpy(p + 2 * c, &h, 2);
        }
        break;
      case TexFormat::kR32F: {
        const float f = sanitize_float(v[0]);
        std::memcpy(p, &f, 4);
        break;
      }
    }
  }
}

// Replaces NaN and out-of-range values in float storage so that sampling stays finite.
void sanitize_level(TexFormat format, MipLevel& level) {
  const size_t n = static_cast<size_t>(level.width) * level.height;
  if (format == TexFormat::kR32F) {
    for (size_t i = 0; i < n; ++i) {
      float f;
      std::memcpy(&f, level.data.data() + 4 * i, 4);
      f = sanitize_float(f);
      std::memcpy(level.data.data() + 4 * i, &f, 4);
    }
  } else if (format == TexFormat::kR16F || format == TexFormat::kRGBA16F) {
    const size_t halves = n * format_channels(format);
    for (size_t i = 0; i < halves; ++i) {
      uint16_t h;
      std::memcpy(&h, level.data.data() + 2 * i, 2);
      if ((h & 0x7c00u) == 0x7c00u) {  // inf -> largest finite, NaN -> 0
        h = (h & 0x3ffu) ? uint16_t{0} : static_cast<uint16_t>((h & 0x8000u) | 0x7bffu);
        std::memcpy(level.data.data() + 2 * i, &h, 2);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Addressing.

// Texel coordinates beyond this are meaningless in float and would overflow int arithmetic.
constexpr float kMaxCoord = 67108864.0f;  // 2^26

// u * size - offset, with NaN treated as 0 and the result kept in int range.
inline float scaled_coord(float u, int size, float offset) {
  if (u != u) u = 0.0f;
  const float x = u * static_cast<float>(size) - offset;
  return std::min(std::max(x, -kMaxCoord), kMaxCoord);
}

inline int wrap_coord(int i, int size, Wrap w) {
  return wrap_texel(i, size, w);
}

struct Level {
  const uint8_t* data;
  int width;
  int height;
};

template <TexFormat F, class Out>
inline Out decode(const uint8_t* p, const float* lut) {
  if constexpr (std::is_same_v<Out, float>) {
    return Codec<F>::r(p, lut);
  } else {
    return Codec<F>::rgba(p, lut);
  }
}

template <TexFormat F, class Out>
inline Out sample_nearest(const Level& L, const SamplerState& s, glm::vec2 uv, const float* lut) {
  const int x = wrap_coord(static_cast<int>(std::floor(scaled_coord(uv.x, L.width, 0.0f))), L.width,
                           s.wrap_u);
  const int y = wrap_coord(static_cast<int>(std::floor(scaled_coord(uv.y, L.height, 0.0f))),
                           L.height, s.wrap_v);
  const size_t off = (static_cast<size_t>(y) * L.width + x) * Codec<F>::kBytes;
  return decode<F, Out>(L.data + off, lut);
}

// GL bilinear: u*w - 0.5, floor, fraction weights; lerp form keeps constant regions exact.
template <TexFormat F, class Out>
inline Out sample_bilinear(const Level& L, const SamplerState& s, glm::vec2 uv, const float* lut) {
  const float xf = scaled_coord(uv.x, L.width, 0.5f);
  const float yf = scaled_coord(uv.y, L.height, 0.5f);
  const float fx = std::floor(xf);
  const float fy = std::floor(yf);
  const float a = xf - fx;
  const float b = yf - fy;
  const int ix = static_cast<int>(fx);
  const int iy = static_cast<int>(fy);
  const int x0 = wrap_coord(ix, L.width, s.wrap_u);
  const int x1 = wrap_coord(ix + 1, L.width, s.wrap_u);
  const int y0 = wrap_coord(iy, L.height, s.wrap_v);
  const int y1 = wrap_coord(iy + 1, L.height, s.wrap_v);
  constexpr size_t kB = Codec<F>::kBytes;
  const uint8_t* r0 = L.data + static_cast<size_t>(y0) * L.width * kB;
  const uint8_t* r1 = L.data + static_cast<size_t>(y1) * L.width * kB;
  const Out t00 = decode<F, Out>(r0 + x0 * kB, lut);
  const Out t10 = decode<F, Out>(r0 + x1 * kB, lut);
  const Out t01 = decode<F, Out>(r1 + x0 * kB, lut);
  const Out t11 = decode<F, Out>(r1 + x1 * kB, lut);
  const Out top = t00 + a * (t10 - t00);
  const Out bottom = t01 + a * (t11 - t01);
  return top + b * (bottom - top);
}

inline Level get_level(const Texture& t, int i) {
  const MipLevel& m = t.level(i);
  return {m.data.data(), m.width, m.height};
}

inline float sanitize_lod(float lod) {
  if (lod != lod) return 0.0f;
  return std::min(std::max(lod, -64.0f), 64.0f);
}

// GL's *_MIPMAP_NEAREST level choice for lambda > 0 (section 8.14.3).
inline int nearest_level(float lod, int q) {
  if (lod <= 0.5f) return 0;
  if (lod > static_cast<float>(q) + 0.5f) return q;
  return std::min(static_cast<int>(std::ceil(lod + 0.5f)) - 1, q);
}

// textureLod for one format; Out is float (first channel) or glm::vec4.
template <TexFormat F, class Out>
Out sample_lod_impl(const Texture& t, const SamplerState& s, glm::vec2 uv, float lod) {
  const float* lut =
      t.color_space() == ColorSpace::kSRGB ? tables().srgb8.data() : tables().unorm8.data();
  lod = sanitize_lod(lod);
  const int q = t.levels() - 1;
  const bool nearest = s.filter == Filter::kNearest;
  if (q == 0 || lod <= 0.0f) {
    const Level L = get_level(t, 0);
    return nearest ? sample_nearest<F, Out>(L, s, uv, lut) : sample_bilinear<F, Out>(L, s, uv, lut);
  }
  if (nearest || s.filter == Filter::kBilinear) {
    const Level L = get_level(t, nearest_level(lod, q));
    return nearest ? sample_nearest<F, Out>(L, s, uv, lut) : sample_bilinear<F, Out>(L, s, uv, lut);
  }
  // Trilinear (and anisotropic without derivatives): blend the two levels around lod.
  if (lod >= static_cast<float>(q)) return sample_bilinear<F, Out>(get_level(t, q), s, uv, lut);
  const float fl = std::floor(lod);
  const int d1 = static_cast<int>(fl);
  const float f = lod - fl;
  const Out t1 = sample_bilinear<F, Out>(get_level(t, d1), s, uv, lut);
  if (f == 0.0f) return t1;
  const Out t2 = sample_bilinear<F, Out>(get_level(t, d1 + 1), s, uv, lut);
  return t1 + f * (t2 - t1);
}

inline float footprint(const Texture& t, glm::vec2 d) {
  const float x = d.x * static_cast<float>(t.width());
  const float y = d.y * static_cast<float>(t.height());
  return std::sqrt(x * x + y * y);
}

}  // namespace

const float* unorm8_table() {
  return tables().unorm8.data();
}
const float* srgb8_table() {
  return tables().srgb8.data();
}

// ---------------------------------------------------------------------------------------------
// Texture.

Texture::Texture(TexFormat format, int width, int height, const void* texels,
                 ColorSpace color_space)
    : format_(format), color_space_(is_8bit(format) ? color_space : ColorSpace::kLinear) {
  CHECK_GE(width, 1);
  CHECK_GE(height, 1);
  CHECK(texels != nullptr);
  MipLevel level;
  level.width = width;
  level.height = height;
  const size_t bytes = static_cast<size_t>(width) * height * format_bytes_per_texel(format);
  const auto* p = static_cast<const uint8_t*>(texels);
  level.data.assign(p, p + bytes);
  sanitize_level(format, level);
  levels_.push_back(std::move(level));
  reset_footprints();
}

Texture Texture::from_floats(TexFormat format, int width, int height, const float* values,
                             ColorSpace color_space) {
  CHECK_GE(width, 1);
  CHECK_GE(height, 1);
  CHECK(values != nullptr);
  Texture t;
  t.format_ = format;
  t.color_space_ = is_8bit(format) ? color_space : ColorSpace::kLinear;
  MipLevel level;
  level.width = width;
  level.height = height;
  encode_level(format, t.color_space_, values, static_cast<size_t>(width) * height, level.data);
  t.levels_.push_back(std::move(level));
  t.reset_footprints();
  return t;
}

Texture Texture::from_levels(TexFormat format, std::vector<MipLevel> levels,
                             ColorSpace color_space) {
  CHECK(!levels.empty());
  const int w = levels[0].width, h = levels[0].height;
  CHECK_GE(w, 1);
  CHECK_GE(h, 1);
  Texture t;
  t.format_ = format;
  t.color_space_ = is_8bit(format) ? color_space : ColorSpace::kLinear;
  for (size_t k = 0; k < levels.size(); ++k) {
    MipLevel& level = levels[k];
    CHECK_LT(k, size_t{31});
    const int want_w = std::max(1, w >> k), want_h = std::max(1, h >> k);
    CHECK_EQ(level.width, want_w);
    CHECK_EQ(level.height, want_h);
    CHECK_EQ(level.data.size(),
             static_cast<size_t>(level.width) * level.height * format_bytes_per_texel(format));
    sanitize_level(format, level);
  }
  t.levels_ = std::move(levels);
  t.reset_footprints();
  return t;
}

void Texture::generate_mips(MipReduce reduce) {
  CHECK(!levels_.empty());
  levels_.resize(1);
  const int ch = format_channels(format_);
  std::vector<float> src = decode_level(format_, color_space_, levels_[0]);
  int sw = levels_[0].width;
  int sh = levels_[0].height;
  while (sw > 1 || sh > 1) {
    const int dw = std::max(1, sw / 2);
    const int dh = std::max(1, sh / 2);
    std::vector<float> dst(static_cast<size_t>(dw) * dh * ch);
    if (reduce == MipReduce::kAverage && sw == 2 * dw && sh == 2 * dh) {
      average_2x2(src.data(), sw, dw, dh, ch, dst.data());
    } else {
      reduce_level(src.data(), sw, sh, dw, dh, ch, reduce, dst.data());
    }
    MipLevel level;
    level.width = dw;
    level.height = dh;
    encode_level(format_, color_space_, dst.data(), static_cast<size_t>(dw) * dh, level.data);
    levels_.push_back(std::move(level));
    // Reduce the next level from the stored (quantised) values, as a reader of this level sees.
    src = decode_level(format_, color_space_, levels_.back());
    sw = dw;
    sh = dh;
  }
  reset_footprints();
}

void Texture::dilate_mips(MipReduce reduce, Wrap wrap_u, Wrap wrap_v) {
  if (reduce == MipReduce::kAverage) return;
  const int ch = format_channels(format_);
  for (size_t l = 1; l < levels_.size(); ++l) {
    MipLevel& level = levels_[l];
    const int w = level.width, h = level.height;
    const std::vector<float> src = decode_level(format_, color_space_, level);
    std::vector<float> dst(src.size());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < ch; ++c) {
          float acc = src[(static_cast<size_t>(y) * w + x) * ch + c];
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int sx = wrap_texel(x + dx, w, wrap_u), sy = wrap_texel(y + dy, h, wrap_v);
              const float v = src[(static_cast<size_t>(sy) * w + sx) * ch + c];
              acc = reduce == MipReduce::kMin ? std::min(acc, v) : std::max(acc, v);
            }
          dst[(static_cast<size_t>(y) * w + x) * ch + c] = acc;
        }
    encode_level(format_, color_space_, dst.data(), static_cast<size_t>(w) * h, level.data);
  }
  reset_footprints();
}

// Per level and wrap pair (repeat or clamp each way): the footprint words, built once. `built`
// is set (release) after the words are, so a reader that sees it (acquire) skips call_once:
// libstdc++'s call_once writes thread-local state on every call, even when the work is done.
struct Texture::FootprintCache {
  explicit FootprintCache(size_t levels) : once(levels * 4), built(levels * 4), words(levels * 4) {}
  std::vector<std::once_flag> once;
  std::vector<std::atomic<bool>> built;      // value-initialised: false
  std::vector<std::vector<uint32_t>> words;  // a row is the level's width (+ 1 for clamp)
};

void Texture::reset_footprints() {
  footprints_ = format_ == TexFormat::kR8 && !levels_.empty()
                    ? std::make_shared<FootprintCache>(levels_.size())
                    : nullptr;
}

Texture::Footprints Texture::r8_footprints(int level, Wrap wrap_u, Wrap wrap_v) const {
  constexpr size_t kMaxWords = size_t{1} << 24;
  if (!footprints_ || level < 0 || level >= levels() || wrap_u == Wrap::kMirror ||
      wrap_v == Wrap::kMirror)
    return {};
  const MipLevel& m = levels_[level];
  const int cols = m.width + (wrap_u == Wrap::kClamp ? 1 : 0);
  const int rows = m.height + (wrap_v == Wrap::kClamp ? 1 : 0);
  if (static_cast<size_t>(cols) * static_cast<size_t>(rows) > kMaxWords) return {};
  FootprintCache& c = *footprints_;
  const size_t slot = static_cast<size_t>(level) * 4 + (wrap_u == Wrap::kClamp ? 2 : 0) +
                      (wrap_v == Wrap::kClamp ? 1 : 0);
  if (c.built[slot].load(std::memory_order_acquire)) return {c.words[slot].data(), cols};
  std::call_once(c.once[slot], [&] {
    // the integer corner each cell stands for: the cell itself (repeat), one before (clamp)
    const int du = wrap_u == Wrap::kClamp ? -1 : 0, dv = wrap_v == Wrap::kClamp ? -1 : 0;
    std::vector<uint32_t>& w = c.words[slot];
    w.resize(static_cast<size_t>(cols) * static_cast<size_t>(rows));
    const uint8_t* d = m.data.data();
    for (int r = 0; r < rows; ++r) {
      const size_t y0 = static_cast<size_t>(wrap_texel(r + dv, m.height, wrap_v)) * m.width;
      const size_t y1 = static_cast<size_t>(wrap_texel(r + dv + 1, m.height, wrap_v)) * m.width;
      for (int col = 0; col < cols; ++col) {
        const int x0 = wrap_texel(col + du, m.width, wrap_u);
        const int x1 = wrap_texel(col + du + 1, m.width, wrap_u);
        w[static_cast<size_t>(r) * cols + col] = uint32_t{d[y0 + x0]} | uint32_t{d[y0 + x1]} << 8 |
                                                 uint32_t{d[y1 + x0]} << 16 |
                                                 uint32_t{d[y1 + x1]} << 24;
      }
    }
    c.built[slot].store(true, std::memory_order_release);
  });
  return {c.words[slot].data(), cols};
}

glm::vec4 Texture::fetch(int level, int x, int y) const {
  DCHECK_GE(level, 0);
  DCHECK_LT(level, levels());
  const MipLevel& m = levels_[level];
  DCHECK(x >= 0 && x < m.width && y >= 0 && y < m.height);
  const float* lut =
      color_space_ == ColorSpace::kSRGB ? tables().srgb8.data() : tables().unorm8.data();
  const uint8_t* p =
      m.data.data() + (static_cast<size_t>(y) * m.width + x) * format_bytes_per_texel(format_);
  return dispatch(format_, [&](auto fc) { return Codec<decltype(fc)::value>::rgba(p, lut); });
}

float Texture::fetch_r(int level, int x, int y) const {
  DCHECK_GE(level, 0);
  DCHECK_LT(level, levels());
  const MipLevel& m = levels_[level];
  DCHECK(x >= 0 && x < m.width && y >= 0 && y < m.height);
  const size_t idx = static_cast<size_t>(y) * m.width + x;
  const uint8_t* d = m.data.data();
  switch (format_) {
    case TexFormat::kR8:
    case TexFormat::kRG8:
    case TexFormat::kRGBA8: {
      const float* lut =
          color_space_ == ColorSpace::kSRGB ? tables().srgb8.data() : tables().unorm8.data();
      return lut[d[idx * format_bytes_per_texel(format_)]];
    }
    case TexFormat::kR16:
      return Codec<TexFormat::kR16>::r(d + idx * 2, nullptr);
    case TexFormat::kR16F:
      return Codec<TexFormat::kR16F>::r(d + idx * 2, nullptr);
    case TexFormat::kRGBA16F:
      return Codec<TexFormat::kRGBA16F>::r(d + idx * 8, nullptr);
    case TexFormat::kR32F:
      return Codec<TexFormat::kR32F>::r(d + idx * 4, nullptr);
  }
  return 0.0f;
}

// ---------------------------------------------------------------------------------------------
// Sampling.

float compute_lod(const Texture& t, glm::vec2 duv_dx, glm::vec2 duv_dy) {
  const float rho = std::max(footprint(t, duv_dx), footprint(t, duv_dy));
  if (rho != rho) return 0.0f;  // NaN derivatives
  if (rho <= 0.0f) return -64.0f;
  return sanitize_lod(std::log2(rho));
}

glm::vec4 sample_lod(const Texture& t, const SamplerState& s, glm::vec2 uv, float lod) {
  DCHECK(!t.empty());
  return dispatch(t.format(), [&](auto fc) {
    return sample_lod_impl<decltype(fc)::value, glm::vec4>(t, s, uv, lod);
  });
}

float sample_r_lod(const Texture& t, const SamplerState& s, glm::vec2 uv, float lod) {
  DCHECK(!t.empty());
  return dispatch(t.format(), [&](auto fc) {
    return sample_lod_impl<decltype(fc)::value, float>(t, s, uv, lod);
  });
}

glm::vec4 sample_grad(const Texture& t, const SamplerState& s, glm::vec2 uv, glm::vec2 duv_dx,
                      glm::vec2 duv_dy) {
  DCHECK(!t.empty());
  if (s.filter != Filter::kAnisotropic) return sample_lod(t, s, uv, compute_lod(t, duv_dx, duv_dy));
  // EXT_texture_filter_anisotropic: N trilinear probes along the major axis at log2(Pmax / N).
  const float px = footprint(t, duv_dx);
  const float py = footprint(t, duv_dy);
  const float pmax = std::max(px, py);
  const float pmin = std::min(px, py);
  const int max_aniso = std::min(std::max(s.max_aniso, 1), 16);
  int n = 1;
  if (pmax > 0.0f && pmax == pmax) {
    // A relative tolerance keeps rounding noise in an isotropic footprint from doubling N.
    const float ratio = pmin > 0.0f ? pmax / pmin : static_cast<float>(max_aniso);
    // written so that a NaN ratio (infinite footprints on both axes) takes the maximum: float to
    // int of NaN is undefined (UBSan found it)
    const float tolerant = ratio * (1.0f - 1e-4f);
    const float capped =
        tolerant < static_cast<float>(max_aniso) ? tolerant : static_cast<float>(max_aniso);
    n = std::max(1, static_cast<int>(std::ceil(capped)));
  }
  SamplerState tri = s;
  tri.filter = Filter::kTrilinear;
  if (n == 1) return sample_lod(t, tri, uv, compute_lod(t, duv_dx, duv_dy));
  const float lod = std::log2(pmax / static_cast<float>(n));
  const glm::vec2 major = px >= py ? duv_dx : duv_dy;
  return dispatch(t.format(), [&](auto fc) {
    constexpr TexFormat F = decltype(fc)::value;
    glm::vec4 sum(0.0f);
    for (int i = 1; i <= n; ++i) {
      const float k = static_cast<float>(i) / static_cast<float>(n + 1) - 0.5f;
      sum += sample_lod_impl<F, glm::vec4>(t, tri, uv + k * major, lod);
    }
    return sum * (1.0f / static_cast<float>(n));
  });
}

}  // namespace relief
