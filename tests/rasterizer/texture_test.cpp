// Tests for rasterizer/texture: formats, sRGB, mips, wrap modes, GL filtering and LOD. The
// references here are written independently of the implementation, in double precision.
#include "rasterizer/texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

namespace relief {
namespace {

// Small deterministic generator (portable, no <random> distribution differences).
struct Lcg {
  uint64_t s;
  explicit Lcg(uint64_t seed) : s(seed * 6364136223846793005ull + 1442695040888963407ull) {}
  double next() {  // [0, 1)
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(s >> 11) * (1.0 / 9007199254740992.0);
  }
  float uniform(double lo, double hi) { return static_cast<float>(lo + (hi - lo) * next()); }
};

std::vector<float> random_values(int n, uint64_t seed, double lo = 0.0, double hi = 1.0) {
  Lcg r(seed);
  std::vector<float> v(n);
  for (float& x : v) x = r.uniform(lo, hi);
  return v;
}

// Wrap of an integer texel index, written from the definitions rather than GL's table.
int ref_wrap(long long i, int size, Wrap w) {
  const long long n = size;
  switch (w) {
    case Wrap::kRepeat:
      return static_cast<int>(((i % n) + n) % n);
    case Wrap::kClamp:
      return static_cast<int>(i < 0 ? 0 : (i >= n ? n - 1 : i));
    case Wrap::kMirror: {
      const long long m = ((i % (2 * n)) + 2 * n) % (2 * n);
      return static_cast<int>(m < n ? m : 2 * n - 1 - m);
    }
  }
  return 0;
}

// GL bilinear on one level, first channel, from fetched texels, weights form, in double.
double ref_bilinear_r(const Texture& t, int level, Wrap wu, Wrap wv, double u, double v) {
  const int w = t.width(level);
  const int h = t.height(level);
  const double x = u * w - 0.5;
  const double y = v * h - 0.5;
  const long long i0 = static_cast<long long>(std::floor(x));
  const long long j0 = static_cast<long long>(std::floor(y));
  const double a = x - std::floor(x);
  const double b = y - std::floor(y);
  auto tex = [&](long long i, long long j) {
    return static_cast<double>(t.fetch(level, ref_wrap(i, w, wu), ref_wrap(j, h, wv)).x);
  };
  return (1 - a) * (1 - b) * tex(i0, j0) + a * (1 - b) * tex(i0 + 1, j0) +
         (1 - a) * b * tex(i0, j0 + 1) + a * b * tex(i0 + 1, j0 + 1);
}

double ref_nearest_r(const Texture& t, int level, Wrap wu, Wrap wv, double u, double v) {
  const int w = t.width(level);
  const int h = t.height(level);
  const long long i = static_cast<long long>(std::floor(u * w));
  const long long j = static_cast<long long>(std::floor(v * h));
  return t.fetch(level, ref_wrap(i, w, wu), ref_wrap(j, h, wv)).x;
}

Texture random_r32f(int w, int h, uint64_t seed) {
  const std::vector<float> v = random_values(w * h, seed);
  return Texture::from_floats(TexFormat::kR32F, w, h, v.data());
}

SamplerState sampler(Filter f, Wrap wu = Wrap::kRepeat, Wrap wv = Wrap::kRepeat) {
  SamplerState s;
  s.filter = f;
  s.wrap_u = wu;
  s.wrap_v = wv;
  return s;
}

constexpr TexFormat kAllFormats[] = {TexFormat::kR8,  TexFormat::kRG8,  TexFormat::kRGBA8,
                                     TexFormat::kR16, TexFormat::kR16F, TexFormat::kRGBA16F,
                                     TexFormat::kR32F};
constexpr Wrap kAllWraps[] = {Wrap::kRepeat, Wrap::kClamp, Wrap::kMirror};
constexpr Filter kAllFilters[] = {Filter::kNearest, Filter::kBilinear, Filter::kTrilinear,
                                  Filter::kAnisotropic};

TEST(Texture, FormatMetadata) {
  EXPECT_EQ(format_channels(TexFormat::kR8), 1);
  EXPECT_EQ(format_channels(TexFormat::kRG8), 2);
  EXPECT_EQ(format_channels(TexFormat::kRGBA8), 4);
  EXPECT_EQ(format_channels(TexFormat::kRGBA16F), 4);
  EXPECT_EQ(format_bytes_per_texel(TexFormat::kR16), 2);
  EXPECT_EQ(format_bytes_per_texel(TexFormat::kR16F), 2);
  EXPECT_EQ(format_bytes_per_texel(TexFormat::kRGBA16F), 8);
  EXPECT_EQ(format_bytes_per_texel(TexFormat::kR32F), 4);
  EXPECT_STREQ(format_name(TexFormat::kRGBA16F), "RGBA16F");
  const Texture t(TexFormat::kRG8, 3, 2, std::vector<uint8_t>(12, 7).data());
  EXPECT_EQ(t.width(), 3);
  EXPECT_EQ(t.height(), 2);
  EXPECT_EQ(t.levels(), 1);
  EXPECT_EQ(t.level(0).data.size(), 12u);
}

TEST(Texture, FormatsRoundTripWithinPrecision) {
  const int w = 5, h = 3;
  for (TexFormat f : kAllFormats) {
    const int ch = format_channels(f);
    const std::vector<float> v = random_values(w * h * ch, 11 + static_cast<int>(f));
    const Texture t = Texture::from_floats(f, w, h, v.data());
    float tol = 0.0f;
    switch (f) {
      case TexFormat::kR8:
      case TexFormat::kRG8:
      case TexFormat::kRGBA8:
        tol = 0.5f / 255.0f + 1e-6f;
        break;
      case TexFormat::kR16:
        tol = 0.5f / 65535.0f + 1e-7f;
        break;
      case TexFormat::kR16F:
      case TexFormat::kRGBA16F:
        tol = 1.0f / 2048.0f;
        break;  // half ulp of values < 1
      case TexFormat::kR32F:
        tol = 0.0f;
        break;
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::vec4 got = t.fetch(0, x, y);
        for (int c = 0; c < 4; ++c) {
          const float want = c < ch ? v[(y * w + x) * ch + c] : (c == 3 ? 1.0f : 0.0f);
          EXPECT_NEAR(got[c], want, tol) << format_name(f) << " c=" << c;
        }
        EXPECT_EQ(t.fetch_r(0, x, y), got.x) << format_name(f);
      }
  }
}

// Every half bit pattern but infinities and NaNs (exponent field 31).
std::vector<uint16_t> finite_halves() {
  std::vector<uint16_t> all;
  for (uint32_t b = 0; b < 0x10000; ++b)
    if ((b & 0x7c00u) != 0x7c00u) all.push_back(static_cast<uint16_t>(b));
  return all;
}

TEST(Texture, HalfFloatEncodingAndDecoding) {
  // Raw half bits decode exactly.
  const uint16_t bits[] = {0x3c00, 0xc000, 0x0001, 0x03ff, 0x7bff, 0x3555, 0x8000};
  const float want[] = {
      1.0f, -2.0f, std::ldexp(1.0f, -24), std::ldexp(1023.0f, -24), 65504.0f, 0.333251953125f,
      -0.0f};
  const Texture t(TexFormat::kR16F, 7, 1, bits);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(t.fetch_r(0, i, 0), want[i]) << i;

  // Encoding: exact values stay exact; ties round to even; overflow saturates; NaN is 0.
  const float in[] = {0.5f,
                      1.0f + std::ldexp(1.0f, -11),      // tie between 1 and 1+2^-10 -> 1
                      1.0f + 3 * std::ldexp(1.0f, -11),  // tie -> 1 + 2^-9 (even)
                      1e6f,
                      -1e6f,
                      std::numeric_limits<float>::quiet_NaN(),
                      std::ldexp(1.0f, -24),
                      std::ldexp(1.0f, -26),   // below half the smallest subnormal
                      std::ldexp(3.0f, -25)};  // 1.5 subnormal steps -> 2 (even)
  const float out[] = {0.5f,
                       1.0f,
                       1.0f + std::ldexp(1.0f, -9),
                       65504.0f,
                       -65504.0f,
                       0.0f,
                       std::ldexp(1.0f, -24),
                       0.0f,
                       std::ldexp(2.0f, -24)};
  const Texture e = Texture::from_floats(TexFormat::kR16F, 9, 1, in);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(e.fetch_r(0, i, 0), out[i]) << i;

  // Every finite half survives float -> half -> float unchanged.
  const std::vector<uint16_t> all = finite_halves();
  const Texture a(TexFormat::kR16F, static_cast<int>(all.size()), 1, all.data());
  std::vector<float> f(all.size());
  for (size_t i = 0; i < all.size(); ++i) f[i] = a.fetch_r(0, static_cast<int>(i), 0);
  const Texture b = Texture::from_floats(TexFormat::kR16F, static_cast<int>(f.size()), 1, f.data());
  EXPECT_EQ(std::memcmp(a.level(0).data.data(), b.level(0).data.data(), all.size() * 2), 0);
}

// Every finite half (zeros, subnormals, normals, both signs) decodes to the value of its fields,
// bit for bit (so -0 stays -0), in R16F and in each channel of RGBA16F.
TEST(Texture, EveryFiniteHalfDecodesToItsValue) {
  const std::vector<uint16_t> all = finite_halves();
  const int n = static_cast<int>(all.size());
  const Texture r(TexFormat::kR16F, n, 1, all.data());
  std::vector<uint16_t> quads(all.size() * 4);
  for (size_t i = 0; i < all.size(); ++i)
    for (int c = 0; c < 4; ++c) quads[4 * i + c] = all[(i + 4096 * c) % all.size()];
  const Texture q(TexFormat::kRGBA16F, n, 1, quads.data());
  auto value = [](uint16_t h) {
    const int e = (h >> 10) & 0x1f, m = h & 0x3ff;
    const float v = e == 0 ? std::ldexp(static_cast<float>(m), -24)
                           : std::ldexp(static_cast<float>(1024 + m), e - 25);
    return (h & 0x8000u) ? -v : v;
  };
  auto same_bits = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  int wrong = 0;
  for (int i = 0; i < n; ++i) {
    if (!same_bits(r.fetch_r(0, i, 0), value(all[i])) && ++wrong <= 5)
      ADD_FAILURE() << "R16F 0x" << std::hex << all[i] << ": " << r.fetch_r(0, i, 0);
    const glm::vec4 t = q.fetch(0, i, 0);
    for (int c = 0; c < 4; ++c)
      if (!same_bits(t[c], value(quads[4 * i + c])) && ++wrong <= 5)
        ADD_FAILURE() << "RGBA16F 0x" << std::hex << quads[4 * i + c] << ": " << t[c];
  }
  EXPECT_EQ(wrong, 0);
}

TEST(Texture, NonFiniteStoredValuesAreSanitized) {
  const float in[] = {std::numeric_limits<float>::quiet_NaN(),
                      std::numeric_limits<float>::infinity(),
                      -std::numeric_limits<float>::infinity(), 2.0f};
  const Texture t(TexFormat::kR32F, 4, 1, in);
  EXPECT_EQ(t.fetch_r(0, 0, 0), 0.0f);
  EXPECT_TRUE(std::isfinite(t.fetch_r(0, 1, 0)));
  EXPECT_GT(t.fetch_r(0, 1, 0), 1e18f);
  EXPECT_LT(t.fetch_r(0, 2, 0), -1e18f);
  EXPECT_EQ(t.fetch_r(0, 3, 0), 2.0f);
  const uint16_t hb[] = {0x7c00, 0xfc00, 0x7e00, 0x3c00};
  const Texture h(TexFormat::kR16F, 4, 1, hb);
  EXPECT_EQ(h.fetch_r(0, 0, 0), 65504.0f);
  EXPECT_EQ(h.fetch_r(0, 1, 0), -65504.0f);
  EXPECT_EQ(h.fetch_r(0, 2, 0), 0.0f);
  EXPECT_EQ(h.fetch_r(0, 3, 0), 1.0f);
  // Bilinear between the extremes stays finite.
  const SamplerState s = sampler(Filter::kBilinear);
  for (float u = 0.0f; u <= 1.0f; u += 0.0625f)
    EXPECT_TRUE(std::isfinite(sample_r_lod(t, s, {u, 0.5f}, 0.0f))) << u;
}

TEST(Texture, SrgbDecode) {
  std::vector<uint8_t> texels(256 * 4);
  for (int i = 0; i < 256; ++i)
    for (int c = 0; c < 4; ++c) texels[i * 4 + c] = static_cast<uint8_t>(i);
  const Texture t(TexFormat::kRGBA8, 256, 1, texels.data(), ColorSpace::kSRGB);
  const Texture lin(TexFormat::kRGBA8, 256, 1, texels.data(), ColorSpace::kLinear);
  EXPECT_EQ(t.color_space(), ColorSpace::kSRGB);
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    const double want = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    const glm::vec4 got = t.fetch(0, i, 0);
    EXPECT_NEAR(got.r, want, 1e-6) << i;
    EXPECT_NEAR(got.g, want, 1e-6) << i;
    EXPECT_NEAR(got.b, want, 1e-6) << i;
    EXPECT_NEAR(got.a, c, 1e-7) << i;  // alpha stays linear
    EXPECT_EQ(t.fetch_r(0, i, 0), got.r);
    EXPECT_NEAR(lin.fetch(0, i, 0).r, c, 1e-7);
  }
  EXPECT_EQ(t.fetch(0, 0, 0).r, 0.0f);
  EXPECT_EQ(t.fetch(0, 255, 0).r, 1.0f);
  EXPECT_NEAR(t.fetch(0, 188, 0).r, 0.5029, 1e-4);

  // from_floats takes linear values and encodes sRGB: every table value maps back to its byte.
  std::vector<float> decoded(256 * 4);
  for (int i = 0; i < 256; ++i)
    for (int c = 0; c < 4; ++c) decoded[i * 4 + c] = t.fetch(0, i, 0)[c];
  const Texture back =
      Texture::from_floats(TexFormat::kRGBA8, 256, 1, decoded.data(), ColorSpace::kSRGB);
  EXPECT_EQ(back.level(0).data, texels);
}

TEST(Texture, NearestWrapModes) {
  const float v[] = {0.0f, 1.0f, 2.0f, 3.0f};
  const Texture t = Texture::from_floats(TexFormat::kR32F, 4, 1, v);
  struct Case {
    float u;
    float repeat, clamp, mirror;
  };
  // Texel index i = floor(4u); values worked out by hand from GL's wrap table.
  const Case cases[] = {
      {0.10f, 0, 0, 0}, {0.60f, 2, 2, 2}, {-0.10f, 3, 0, 0}, {-0.30f, 2, 0, 1}, {1.10f, 0, 3, 3},
      {1.90f, 3, 3, 0}, {2.10f, 0, 3, 0}, {-1.10f, 3, 0, 3}, {-1.90f, 0, 0, 0}, {5.60f, 2, 3, 1},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(sample_r_lod(t, sampler(Filter::kNearest, Wrap::kRepeat), {c.u, 0.5f}, 0), c.repeat)
        << c.u;
    EXPECT_EQ(sample_r_lod(t, sampler(Filter::kNearest, Wrap::kClamp), {c.u, 0.5f}, 0), c.clamp)
        << c.u;
    EXPECT_EQ(sample_r_lod(t, sampler(Filter::kNearest, Wrap::kMirror), {c.u, 0.5f}, 0), c.mirror)
        << c.u;
  }
  // The v axis wraps independently of u.
  const Texture tv = Texture::from_floats(TexFormat::kR32F, 1, 4, v);
  EXPECT_EQ(
      sample_r_lod(tv, sampler(Filter::kNearest, Wrap::kClamp, Wrap::kRepeat), {7.0f, -0.1f}, 0),
      3.0f);
  EXPECT_EQ(
      sample_r_lod(tv, sampler(Filter::kNearest, Wrap::kRepeat, Wrap::kMirror), {7.0f, -0.1f}, 0),
      0.0f);
}

TEST(Texture, BilinearWrapModesAtTheEdge) {
  const float v[] = {0.0f, 1.0f, 2.0f, 3.0f};
  const Texture t = Texture::from_floats(TexFormat::kR32F, 4, 1, v);
  // u = 0: halfway between texel -1 and texel 0.
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kRepeat), {0.0f, 0.5f}, 0),
                  1.5f);
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kClamp), {0.0f, 0.5f}, 0), 0.0f);
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kMirror), {0.0f, 0.5f}, 0),
                  0.0f);
  // u = 1: halfway between texel 3 and texel 4.
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kRepeat), {1.0f, 0.5f}, 0),
                  1.5f);
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kClamp), {1.0f, 0.5f}, 0), 3.0f);
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kMirror), {1.0f, 0.5f}, 0),
                  3.0f);
  // A quarter texel outside on the left: repeat blends texel 3 and 0, mirror texel 0 and 0.
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kRepeat), {-1.0f / 16, 0.5f}, 0),
                  0.75f * 3.0f);
  EXPECT_FLOAT_EQ(sample_r_lod(t, sampler(Filter::kBilinear, Wrap::kMirror), {1.0f / 16, 0.5f}, 0),
                  0.0f);
}

TEST(Texture, BilinearMatchesFloatReference) {
  const Texture t = random_r32f(7, 5, 3);
  Lcg r(99);
  for (Wrap wu : kAllWraps)
    for (Wrap wv : kAllWraps) {
      const SamplerState s = sampler(Filter::kBilinear, wu, wv);
      for (int k = 0; k < 200; ++k) {
        const float u = r.uniform(-2.0, 3.0);
        const float v = r.uniform(-2.0, 3.0);
        const double want = ref_bilinear_r(t, 0, wu, wv, u, v);
        EXPECT_NEAR(sample_r_lod(t, s, {u, v}, 0.0f), want, 2e-6) << u << "," << v;
        EXPECT_NEAR(sample_lod(t, s, {u, v}, -1.0f).x, want, 2e-6);
      }
    }
}

TEST(Texture, BilinearAtTexelCentresReturnsTheTexel) {
  const Texture t = random_r32f(6, 4, 5);
  const SamplerState s = sampler(Filter::kBilinear);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      EXPECT_EQ(sample_r_lod(t, s, {(x + 0.5f) / 6, (y + 0.5f) / 4}, 0), t.fetch_r(0, x, y));
}

TEST(Texture, NearestAndBilinearPickTheNearestLevel) {
  Texture t = random_r32f(32, 16, 8);
  t.generate_mips();
  ASSERT_EQ(t.levels(), 6);
  Lcg r(4);
  // (lod, level) pairs from GL's *_MIPMAP_NEAREST rule: d = ceil(lod + 1/2) - 1, clamped.
  const std::pair<float, int> picks[] = {{0.3f, 0},  {0.5f, 0}, {0.51f, 1}, {1.49f, 1},
                                         {1.51f, 2}, {3.7f, 4}, {4.6f, 5},  {9.0f, 5}};
  for (auto [lod, level] : picks)
    for (int k = 0; k < 10; ++k) {
      const float u = r.uniform(-1.0, 2.0), v = r.uniform(-1.0, 2.0);
      EXPECT_NEAR(sample_r_lod(t, sampler(Filter::kBilinear), {u, v}, lod),
                  ref_bilinear_r(t, level, Wrap::kRepeat, Wrap::kRepeat, u, v), 2e-6)
          << lod;
      EXPECT_EQ(sample_r_lod(t, sampler(Filter::kNearest), {u, v}, lod),
                ref_nearest_r(t, level, Wrap::kRepeat, Wrap::kRepeat, u, v))
          << lod;
    }
}

TEST(Texture, TrilinearMatchesFloatReference) {
  Texture t = random_r32f(16, 8, 21);
  t.generate_mips();
  ASSERT_EQ(t.levels(), 5);
  Lcg r(7);
  for (Wrap w : kAllWraps) {
    const SamplerState s = sampler(Filter::kTrilinear, w, w);
    for (int k = 0; k < 200; ++k) {
      const float u = r.uniform(-1.5, 2.5), v = r.uniform(-1.5, 2.5);
      const float lod = r.uniform(-1.0, 5.0);
      double want;
      if (lod <= 0.0f) {
        want = ref_bilinear_r(t, 0, w, w, u, v);
      } else if (lod >= 4.0f) {
        want = ref_bilinear_r(t, 4, w, w, u, v);
      } else {
        const int d = static_cast<int>(std::floor(lod));
        const double f = lod - d;
        want =
            (1 - f) * ref_bilinear_r(t, d, w, w, u, v) + f * ref_bilinear_r(t, d + 1, w, w, u, v);
      }
      EXPECT_NEAR(sample_r_lod(t, s, {u, v}, lod), want, 3e-6) << u << "," << v << " lod " << lod;
      EXPECT_NEAR(sample_lod(t, s, {u, v}, lod).x, want, 3e-6);
    }
  }
}

TEST(Texture, SampleRLodEqualsRedOfSampleLod) {
  for (TexFormat f : kAllFormats) {
    const int ch = format_channels(f);
    const std::vector<float> vals = random_values(9 * 6 * ch, 50 + static_cast<int>(f));
    Texture t = Texture::from_floats(f, 9, 6, vals.data());
    t.generate_mips();
    Lcg r(3);
    for (Filter filter : kAllFilters)
      for (Wrap w : kAllWraps)
        for (int k = 0; k < 30; ++k) {
          const glm::vec2 uv(r.uniform(-2, 3), r.uniform(-2, 3));
          const float lod = r.uniform(-1, 5);
          const SamplerState s = sampler(filter, w, w);
          EXPECT_EQ(sample_r_lod(t, s, uv, lod), sample_lod(t, s, uv, lod).x) << format_name(f);
        }
  }
}

TEST(Texture, LodFromDerivatives) {
  const std::vector<float> v(512 * 512, 0.5f);
  const Texture t = Texture::from_floats(TexFormat::kR32F, 512, 512, v.data());
  // A plane facing the camera at distance z = 4, focal length f = 256 px, one texture tile per
  // W = 2 world units: one pixel spans z / f world units, so du/dx = z / (f W) and
  // rho = 512 z / (f W) = 4 texels per pixel: lod 2.
  const float z = 4.0f, focal = 256.0f, tile = 2.0f;
  const float d = z / (focal * tile);
  EXPECT_FLOAT_EQ(compute_lod(t, {d, 0.0f}, {0.0f, d}), 2.0f);
  // Twice as far: one level coarser.
  EXPECT_FLOAT_EQ(compute_lod(t, {2 * d, 0.0f}, {0.0f, 2 * d}), 3.0f);
  // rho is the longer of the two footprints (lengths, not components).
  EXPECT_FLOAT_EQ(compute_lod(t, {3.0f / 512, 4.0f / 512}, {0.0f, 1.0f / 512}), std::log2(5.0f));
  EXPECT_FLOAT_EQ(compute_lod(t, {0.0f, 1.0f / 512}, {8.0f / 512, 0.0f}), 3.0f);
  // Magnification gives a negative lod.
  EXPECT_FLOAT_EQ(compute_lod(t, {0.5f / 512, 0.0f}, {0.0f, 0.5f / 512}), -1.0f);
  // Non-square texture: each axis scales by its own size.
  const std::vector<float> v2(256 * 64, 0.5f);
  const Texture t2 = Texture::from_floats(TexFormat::kR32F, 256, 64, v2.data());
  EXPECT_FLOAT_EQ(compute_lod(t2, {0.0f, 1.0f / 16}, {1.0f / 256, 0.0f}), 2.0f);
  EXPECT_FLOAT_EQ(compute_lod(t2, {1.0f / 16, 0.0f}, {0.0f, 1.0f / 64}), 4.0f);
  // Zero derivatives: a finite, magnifying lod.
  const float l0 = compute_lod(t, {0, 0}, {0, 0});
  EXPECT_TRUE(std::isfinite(l0));
  EXPECT_LT(l0, 0.0f);
}

TEST(Texture, SampleGradUsesTheLodFromDerivatives) {
  Texture t = random_r32f(64, 64, 77);
  t.generate_mips();
  const SamplerState s = sampler(Filter::kTrilinear);
  Lcg r(1);
  for (int k = 0; k < 50; ++k) {
    const glm::vec2 uv(r.uniform(0, 1), r.uniform(0, 1));
    const glm::vec2 dx(r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1));
    const glm::vec2 dy(r.uniform(-0.1, 0.1), r.uniform(-0.1, 0.1));
    EXPECT_EQ(sample_grad(t, s, uv, dx, dy).x, sample_lod(t, s, uv, compute_lod(t, dx, dy)).x);
  }
}

TEST(Texture, AnisotropicReducesToTrilinearForIsotropicFootprints) {
  Texture t = random_r32f(64, 64, 13);
  t.generate_mips();
  const SamplerState aniso = sampler(Filter::kAnisotropic);
  const SamplerState tri = sampler(Filter::kTrilinear);
  Lcg r(2);
  for (int k = 0; k < 100; ++k) {
    const glm::vec2 uv(r.uniform(-1, 2), r.uniform(-1, 2));
    const float len = r.uniform(0.001, 0.2);
    const float a = r.uniform(0, 6.283);
    const glm::vec2 dx = len * glm::vec2(std::cos(a), std::sin(a));
    const glm::vec2 dy = len * glm::vec2(-std::sin(a), std::cos(a));
    const glm::vec4 g = sample_grad(t, aniso, uv, dx, dy);
    const glm::vec4 want = sample_grad(t, tri, uv, dx, dy);
    EXPECT_EQ(g.x, want.x) << k;
    EXPECT_EQ(g.w, want.w);
  }
}

TEST(Texture, AnisotropicAveragesProbesAlongTheMajorAxis) {
  Texture t = random_r32f(64, 64, 31);
  t.generate_mips();
  const glm::vec2 uv(0.37f, 0.61f);
  const glm::vec2 dx(8.0f / 64, 0.0f);  // Pmax = 8 texels
  const glm::vec2 dy(0.0f, 1.0f / 64);  // Pmin = 1 texel
  const SamplerState tri = sampler(Filter::kTrilinear);
  auto expected = [&](int n, glm::vec2 major) {
    // EXT_texture_filter_anisotropic: N probes at uv + (i/(N+1) - 1/2) * major, lod log2(Pmax/N).
    const double lod = std::log2(8.0 / n);
    double sum = 0.0;
    for (int i = 1; i <= n; ++i) {
      const glm::vec2 p = uv + static_cast<float>(static_cast<double>(i) / (n + 1) - 0.5) * major;
      sum += sample_lod(t, tri, p, static_cast<float>(lod)).x;
    }
    return sum / n;
  };
  SamplerState s = sampler(Filter::kAnisotropic);
  EXPECT_NEAR(sample_grad(t, s, uv, dx, dy).x, expected(8, dx), 1e-5);
  s.max_aniso = 2;
  EXPECT_NEAR(sample_grad(t, s, uv, dx, dy).x, expected(2, dx), 1e-5);
  // Major axis along y.
  s.max_aniso = 16;
  EXPECT_NEAR(sample_grad(t, s, uv, dy, dx).x, expected(8, dx), 1e-5);
  // Non-integer ratio rounds N up: Pmax/Pmin = 8 / 3 -> 3 probes.
  const glm::vec2 dy3(0.0f, 3.0f / 64);
  EXPECT_NEAR(sample_grad(t, s, uv, dx, dy3).x, expected(3, dx), 1e-5);
  // An anisotropic result differs from the blurrier trilinear one here.
  EXPECT_NE(sample_grad(t, s, uv, dx, dy).x, sample_grad(t, tri, uv, dx, dy).x);
}

TEST(Texture, MipChainPowerOfTwoAverages2x2Blocks) {
  Texture t = random_r32f(8, 4, 41);
  t.generate_mips();
  ASSERT_EQ(t.levels(), 4);
  EXPECT_EQ(t.width(1), 4);
  EXPECT_EQ(t.height(1), 2);
  EXPECT_EQ(t.width(3), 1);
  EXPECT_EQ(t.height(3), 1);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const double want =
          (static_cast<double>(t.fetch_r(0, 2 * x, 2 * y)) + t.fetch_r(0, 2 * x + 1, 2 * y) +
           t.fetch_r(0, 2 * x, 2 * y + 1) + t.fetch_r(0, 2 * x + 1, 2 * y + 1)) /
          4;
      EXPECT_NEAR(t.fetch_r(1, x, y), want, 1e-6);
    }
  // The 4x2 -> 2x1 -> 1x1 levels: the last one is the mean of everything.
  double mean = 0;
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) mean += t.fetch_r(0, x, y);
  EXPECT_NEAR(t.fetch_r(3, 0, 0), mean / 32, 1e-6);
}

// The level-0 bilinear surface's least sample over the square of half-width r texels around
// (u, v), sampled every 1/8 texel (a read below every sample is what the test asks of it).
double min_over_square(const Texture& t, const SamplerState& s, double u, double v, double r) {
  double m = HUGE_VAL;
  const int n = static_cast<int>(std::lround(r * 8.0));
  for (int j = -n; j <= n; ++j)
    for (int i = -n; i <= n; ++i) {
      const glm::vec2 q(static_cast<float>(u + i / 8.0 / t.width()),
                        static_cast<float>(v + j / 8.0 / t.height()));
      m = std::min<double>(m, sample_lod(t, s, q, 0.0f).x);
    }
  return m;
}

// dilate_mips after a min chain: a bilinear read of level k (and a trilinear one between levels)
// never exceeds the level-0 bilinear surface within 2^(k-1) - 1/2 texels of the read point, for
// every wrap and for power-of-two and odd sizes. The plain min chain breaks that (its bilinear
// reads mix a block's minimum with a neighbour's), so the test sees the difference.
TEST(Texture, DilatedMinMipsAreConservativeOverTheFootprint) {
  struct Size {
    int w, h;
  };
  for (Size sz : {Size{32, 32}, Size{24, 20}}) {
    for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
      const std::vector<float> v = random_values(sz.w * sz.h, 29);
      Texture plain = Texture::from_floats(TexFormat::kR32F, sz.w, sz.h, v.data());
      plain.generate_mips(MipReduce::kMin);
      Texture t = plain;
      t.dilate_mips(MipReduce::kMin, wrap, wrap);
      ASSERT_EQ(t.levels(), plain.levels());
      EXPECT_EQ(t.level(0).data, plain.level(0).data);  // level 0 is the surface itself
      SamplerState s;
      s.filter = Filter::kTrilinear;
      s.wrap_u = s.wrap_v = wrap;
      uint32_t rng = 12345;
      const auto next = [&rng] {
        rng = rng * 1664525u + 1013904223u;
        return (rng >> 8) / 16777216.0;
      };
      int plain_violations = 0;
      for (int k = 1; k < std::min(t.levels(), 4); ++k) {
        const double r = std::ldexp(1.0, k - 1) - 0.5;
        for (int i = 0; i < 60; ++i) {
          const double u = next(), w = next();
          const float lod = static_cast<float>(k + (i % 3) * 0.25);  // k, k + 1/4, k + 1/2
          const glm::vec2 p(static_cast<float>(u), static_cast<float>(w));
          const double floor_ = min_over_square(t, s, u, w, r);
          EXPECT_LE(sample_lod(t, s, p, lod).x, floor_ + 1e-6)
              << sz.w << "x" << sz.h << " wrap " << static_cast<int>(wrap) << " lod " << lod;
          plain_violations += sample_lod(plain, s, p, lod).x > floor_ + 1e-6;
        }
      }
      EXPECT_GT(plain_violations, 0) << "the plain min chain should break the bound";
    }
  }
}

TEST(Texture, MipReductionsOnNonPowerOfTwoSizes) {
  const int w = 5, h = 3;
  const std::vector<float> v = random_values(w * h, 17);
  auto at = [&](int x, int y) { return static_cast<double>(v[y * w + x]); };
  double gmin = 1e9, gmax = -1e9, gmean = 0;
  for (float x : v) {
    gmin = std::min<double>(gmin, x);
    gmax = std::max<double>(gmax, x);
    gmean += x / static_cast<double>(w * h);
  }
  for (MipReduce reduce : {MipReduce::kAverage, MipReduce::kMin, MipReduce::kMax}) {
    Texture t = Texture::from_floats(TexFormat::kR32F, w, h, v.data());
    t.generate_mips(reduce);
    ASSERT_EQ(t.levels(), 3);  // 5x3 -> 2x1 -> 1x1
    EXPECT_EQ(t.width(1), 2);
    EXPECT_EQ(t.height(1), 1);
    EXPECT_EQ(t.width(2), 1);
    EXPECT_EQ(t.height(2), 1);
    // Level 1 texel 0 covers source columns [0, 2.5) and rows [0, 3); texel 1 columns [2.5, 5).
    for (int i = 0; i < 2; ++i) {
      double mn = 1e9, mx = -1e9, sum = 0;
      for (int y = 0; y < 3; ++y)
        for (int x = 2 * i; x <= 2 * i + 2; ++x) {
          const double wgt = x == 2 ? 0.5 : 1.0;
          mn = std::min(mn, at(x, y));
          mx = std::max(mx, at(x, y));
          sum += wgt * at(x, y);
        }
      const double want = reduce == MipReduce::kMin   ? mn
                          : reduce == MipReduce::kMax ? mx
                                                      : sum / 7.5;
      EXPECT_NEAR(t.fetch_r(1, i, 0), want, 1e-6) << static_cast<int>(reduce) << " texel " << i;
    }
    const double last = reduce == MipReduce::kMin ? gmin : reduce == MipReduce::kMax ? gmax : gmean;
    EXPECT_NEAR(t.fetch_r(2, 0, 0), last, 1e-6) << static_cast<int>(reduce);
  }
  // Odd sizes down a long chain: 7x1 -> 3x1 -> 1x1, max stays conservative at each level.
  const float row[] = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.9f};
  Texture m = Texture::from_floats(TexFormat::kR32F, 7, 1, row);
  m.generate_mips(MipReduce::kMax);
  ASSERT_EQ(m.levels(), 3);
  EXPECT_EQ(m.width(1), 3);
  EXPECT_FLOAT_EQ(m.fetch_r(1, 0, 0), 0.3f);  // covers [0, 7/3)
  EXPECT_FLOAT_EQ(m.fetch_r(1, 1, 0), 0.5f);  // covers [7/3, 14/3)
  EXPECT_FLOAT_EQ(m.fetch_r(1, 2, 0), 0.9f);  // covers [14/3, 7)
  EXPECT_FLOAT_EQ(m.fetch_r(2, 0, 0), 0.9f);
}

// A level whose sizes halve exactly holds each 2 x 2 block's mean: the block's stored texels,
// decoded, summed in double row by row, divided by 4 and stored as the format stores a float. Bit
// for bit, for floats and for sRGB bytes. 12x6 -> 6x3 halves; 6x3 -> 3x1 does not (the overlap
// reduction of MipReductionsOnNonPowerOfTwoSizes).
TEST(Texture, LevelsThatHalveHoldTheExactMeanOfEachBlock) {
  auto block_mean = [](auto&& at, int x, int y) {
    double acc = 0.0;
    acc += at(2 * x, 2 * y);
    acc += at(2 * x + 1, 2 * y);
    acc += at(2 * x, 2 * y + 1);
    acc += at(2 * x + 1, 2 * y + 1);
    return static_cast<float>(acc / 4.0);
  };
  const std::vector<float> r = random_values(12 * 6, 23);
  Texture f = Texture::from_floats(TexFormat::kR32F, 12, 6, r.data());
  f.generate_mips();
  ASSERT_EQ(f.width(1), 6);
  ASSERT_EQ(f.height(1), 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 6; ++x) {
      auto at = [&](int i, int j) { return static_cast<double>(r[j * 12 + i]); };
      EXPECT_EQ(f.fetch_r(1, x, y), block_mean(at, x, y)) << x << "," << y;
    }

  const std::vector<float> c = random_values(12 * 6 * 4, 29);
  Texture t = Texture::from_floats(TexFormat::kRGBA8, 12, 6, c.data(), ColorSpace::kSRGB);
  t.generate_mips();
  const std::vector<uint8_t>& l0 = t.level(0).data;
  const std::vector<uint8_t>& l1 = t.level(1).data;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 6; ++x)
      for (int ch = 0; ch < 4; ++ch) {
        const float* decode = ch < 3 ? srgb8_table() : unorm8_table();
        auto at = [&](int i, int j) {
          return static_cast<double>(decode[l0[(j * 12 + i) * 4 + ch]]);
        };
        const float mean = block_mean(at, x, y);
        const uint8_t want =
            ch < 3 ? encode_srgb8(mean)
                   : static_cast<uint8_t>(std::lround(static_cast<double>(mean) * 255.0));
        EXPECT_EQ(l1[(y * 6 + x) * 4 + ch], want) << x << "," << y << " channel " << ch;
      }
}

TEST(Texture, SrgbMipsAverageInLinearSpace) {
  const uint8_t px[] = {0, 0, 0, 0, 255, 255, 255, 255};
  Texture t(TexFormat::kRGBA8, 2, 1, px, ColorSpace::kSRGB);
  t.generate_mips();
  ASSERT_EQ(t.levels(), 2);
  EXPECT_EQ(t.level(1).data[0], 188);  // linear 0.5 encoded as sRGB
  EXPECT_NEAR(t.fetch(1, 0, 0).r, 0.5f, 0.003f);
  EXPECT_EQ(t.level(1).data[3], 128);  // alpha averages linearly: 127.5 rounds to 128
}

TEST(Texture, MipsOfEveryFormatStayInRange) {
  for (TexFormat f : kAllFormats) {
    const int ch = format_channels(f);
    const std::vector<float> vals = random_values(6 * 5 * ch, 60 + static_cast<int>(f));
    Texture t = Texture::from_floats(f, 6, 5, vals.data());
    t.generate_mips(MipReduce::kMax);
    ASSERT_EQ(t.levels(), 3) << format_name(f);  // 6x5 -> 3x2 -> 1x1
    // Max of the stored (quantised) level 0: a max reduction re-encodes it without loss.
    float vmax = -1.0f;
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 6; ++x) vmax = std::max(vmax, t.fetch_r(0, x, y));
    EXPECT_EQ(t.fetch_r(2, 0, 0), vmax) << format_name(f);
  }
}

TEST(Texture, OneByOne) {
  const float rgba[] = {0.25f, 0.5f, 0.75f, 1.0f};
  Texture t = Texture::from_floats(TexFormat::kRGBA16F, 1, 1, rgba);
  t.generate_mips();
  EXPECT_EQ(t.levels(), 1);
  for (Filter f : kAllFilters)
    for (Wrap w : kAllWraps) {
      const SamplerState s = sampler(f, w, w);
      for (float lod : {-3.0f, 0.0f, 0.5f, 7.0f}) {
        const glm::vec4 got = sample_lod(t, s, {0.3f, -4.7f}, lod);
        EXPECT_EQ(got, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
        EXPECT_EQ(sample_r_lod(t, s, {12.3f, 0.9f}, lod), 0.25f);
      }
      EXPECT_EQ(sample_grad(t, s, {0.5f, 0.5f}, {3.0f, 0.0f}, {0.0f, 0.01f}).y, 0.5f);
    }
}

TEST(Texture, MissingChannelsReadLikeGl) {
  const uint8_t rg[] = {255, 51};
  const Texture t(TexFormat::kRG8, 1, 1, rg);
  EXPECT_EQ(t.fetch(0, 0, 0), glm::vec4(1.0f, 0.2f, 0.0f, 1.0f));
  const uint16_t r16[] = {65535};
  const Texture u(TexFormat::kR16, 1, 1, r16);
  EXPECT_EQ(u.fetch(0, 0, 0), glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
}

TEST(Texture, NonFiniteInputsGiveFiniteResults) {
  Texture t = random_r32f(8, 8, 9);
  t.generate_mips();
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float bad[] = {nan, inf, -inf, 1e30f, -1e30f, 3e9f};
  for (Filter f : kAllFilters)
    for (Wrap w : kAllWraps) {
      const SamplerState s = sampler(f, w, w);
      for (float a : bad) {
        EXPECT_TRUE(std::isfinite(sample_r_lod(t, s, {a, 0.5f}, 1.0f)));
        EXPECT_TRUE(std::isfinite(sample_r_lod(t, s, {0.5f, a}, a)));
        EXPECT_TRUE(std::isfinite(sample_lod(t, s, {a, a}, a).x));
        EXPECT_TRUE(std::isfinite(sample_grad(t, s, {0.5f, 0.5f}, {a, 0.0f}, {0.0f, 0.01f}).x));
        EXPECT_TRUE(std::isfinite(sample_grad(t, s, {a, 0.5f}, {a, a}, {a, 0.0f}).x));
      }
    }
  // NaN uv reads as uv = 0.
  const SamplerState s = sampler(Filter::kBilinear);
  EXPECT_EQ(sample_r_lod(t, s, {nan, nan}, 0.0f), sample_r_lod(t, s, {0.0f, 0.0f}, 0.0f));
}

// The R8 footprint words (the lane-parallel bilinear read's one gather) hold, for every integer
// corner (ix, iy) a read can have, the four texels ref_wrap gives, in bytes 0..3: on levels of
// power-of-two and other sizes, for repeat and clamp each way, at corners inside the level, on
// its seams and far outside it. Other formats and mirror wraps have none; a copy shares the words
// until its levels change, and then has words of its own levels.
TEST(Texture, R8FootprintsHoldTheFourWrappedTexels) {
  const std::vector<float> values = random_values(37 * 20, 91);
  Texture t = Texture::from_floats(TexFormat::kR8, 37, 20, values.data());
  t.generate_mips();
  Texture p2 = Texture::from_floats(TexFormat::kR8, 16, 8, random_values(16 * 8, 92).data());
  p2.generate_mips();
  const auto texel = [](const Texture& tex, int level, int x, int y) {
    return static_cast<uint32_t>(
        tex.level(level).data[static_cast<size_t>(y) * tex.width(level) + x]);
  };
  int checked = 0;
  for (const Texture* tex : {&t, &p2})
    for (int level = 0; level < tex->levels(); ++level)
      for (Wrap wu : {Wrap::kRepeat, Wrap::kClamp})
        for (Wrap wv : {Wrap::kRepeat, Wrap::kClamp}) {
          const int w = tex->width(level), h = tex->height(level);
          const Texture::Footprints f = tex->r8_footprints(level, wu, wv);
          ASSERT_NE(f.words, nullptr);
          EXPECT_EQ(f.width, w + (wu == Wrap::kClamp ? 1 : 0));
          for (int iy : {-1000003, -2 * h - 1, -h, -2, -1, 0, 1, h / 2, h - 2, h - 1, h, h + 1,
                         3 * h + 2, 999999})
            for (int ix : {-1000003, -2 * w - 1, -w, -2, -1, 0, 1, w / 2, w - 2, w - 1, w, w + 1,
                           3 * w + 2, 999999}) {
              const int col = footprint_cell(ix, w, wu), row = footprint_cell(iy, h, wv);
              ASSERT_GE(col, 0);
              ASSERT_LT(col, f.width);
              ASSERT_GE(row, 0);
              ASSERT_LT(row, h + (wv == Wrap::kClamp ? 1 : 0));
              const int x0 = ref_wrap(ix, w, wu), x1 = ref_wrap(ix + 1LL, w, wu);
              const int y0 = ref_wrap(iy, h, wv), y1 = ref_wrap(iy + 1LL, h, wv);
              const uint32_t want = texel(*tex, level, x0, y0) | texel(*tex, level, x1, y0) << 8 |
                                    texel(*tex, level, x0, y1) << 16 |
                                    texel(*tex, level, x1, y1) << 24;
              ASSERT_EQ(f.words[static_cast<size_t>(row) * f.width + col], want)
                  << w << "x" << h << " level " << level << " corner " << ix << "," << iy;
              ++checked;
            }
        }
  EXPECT_EQ(checked, (t.levels() + p2.levels()) * 4 * 14 * 14);

  EXPECT_EQ(t.r8_footprints(0, Wrap::kMirror, Wrap::kRepeat).words, nullptr);
  EXPECT_EQ(t.r8_footprints(0, Wrap::kRepeat, Wrap::kMirror).words, nullptr);
  EXPECT_EQ(t.r8_footprints(t.levels(), Wrap::kRepeat, Wrap::kRepeat).words, nullptr);
  const Texture rgba = Texture::from_floats(TexFormat::kRGBA8, 4, 4, random_values(64, 93).data());
  EXPECT_EQ(rgba.r8_footprints(0, Wrap::kRepeat, Wrap::kRepeat).words, nullptr);

  // a copy shares them; changed levels get their own
  Texture copy = t;
  EXPECT_EQ(copy.r8_footprints(1, Wrap::kRepeat, Wrap::kRepeat).words,
            t.r8_footprints(1, Wrap::kRepeat, Wrap::kRepeat).words);
  copy.dilate_mips(MipReduce::kMax, Wrap::kRepeat, Wrap::kRepeat);
  const Texture::Footprints dilated = copy.r8_footprints(1, Wrap::kRepeat, Wrap::kRepeat);
  EXPECT_NE(dilated.words, t.r8_footprints(1, Wrap::kRepeat, Wrap::kRepeat).words);
  for (int y = 0; y < copy.height(1); ++y)
    for (int x = 0; x < copy.width(1); ++x)
      ASSERT_EQ(dilated.words[static_cast<size_t>(y) * dilated.width + x] & 0xffu,
                texel(copy, 1, x, y));
}

}  // namespace
}  // namespace relief
