// The lane-parallel sampler of shaders_cpp/sampling.h against the scalar one of
// rasterizer/texture.cpp: textureLod is bit-identical to sample_lod for every format (8-bit and
// R32F), filter and wrap it serves; textureGrad stays within the LOD rounding of sample_grad;
// float and F8 instantiations agree bit for bit; the out-of-line entries (AVX2 clones) agree
// with the inline sampler.
#include <gtest/gtest.h>
#include <algorithm>

#include <cmath>
#include <random>
#include <vector>

#include "shaders_cpp/sampling.h"
#include "shaders_cpp/sampling_simd.h"
#include "tests/shaders_cpp/float_bits.h"
#include "tests/shaders_cpp/random_texture.h"

namespace relief {
namespace {

using testing::float_bits;
using testing::random_texture;

TEST(Sampling, Unorm8DecodeEqualsTheTable) {
  for (int i = 0; i < 256; ++i) {
    const float x = static_cast<float>(i);
    EXPECT_EQ(float_bits(x / 255.0f), float_bits(unorm8_table()[i])) << i;
    EXPECT_EQ(float_bits(HWY_NAMESPACE::detail::unorm8_decode(x)), float_bits(unorm8_table()[i]))
        << i;
    const F8 lanes = HWY_NAMESPACE::detail::unorm8_decode(F8(x));
    for (int k = 0; k < 8; ++k) EXPECT_EQ(float_bits(lanes[k]), float_bits(unorm8_table()[i])) << i;
  }
}

TEST(Sampling, TextureLodMatchesSampleLodBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uvd(-3.0f, 3.0f), lodd(-1.5f, 11.0f);
  int checked = 0;
  for (TexFormat f : {TexFormat::kR8, TexFormat::kRG8, TexFormat::kRGBA8, TexFormat::kR32F})
    for (ColorSpace cs : {ColorSpace::kLinear, ColorSpace::kSRGB})
      for (auto [w, h] : {std::pair{64, 32}, std::pair{37, 20}, std::pair{1, 1}}) {
        const Texture t = random_texture(f, w, h, cs, static_cast<uint32_t>(w * 31 + h));
        for (Filter filter :
             {Filter::kNearest, Filter::kBilinear, Filter::kTrilinear, Filter::kAnisotropic})
          for (Wrap wu : {Wrap::kRepeat, Wrap::kClamp})
            for (Wrap wv : {Wrap::kRepeat, Wrap::kClamp}) {
              const SamplerState s = testing::sampler_state(filter, wu, wv);
              ASSERT_TRUE(HWY_NAMESPACE::detail::vector_sampling_ok(t, s));
              for (int n = 0; n < 16; ++n) {
                F8 u, v, lod;
                for (int i = 0; i < 8; ++i) {
                  u.set(i, uvd(rng));
                  v.set(i, uvd(rng));
                  lod.set(i, i == 7 ? std::floor(lodd(rng)) : lodd(rng));  // whole lods too
                }
                const V4<F8> r8 = texture_lod(t, s, V2<F8>(u, v), lod);
                const F8 red = texture_r_lod(t, s, V2<F8>(u, v), lod);
                // the out-of-line entry: its AVX2 clone (gathers) where the CPU has AVX2
                const F8 red_entry = texture_r_lod_lanes(t, s, V2<F8>(u, v), lod);
                for (int i = 0; i < 8; ++i) {
                  const glm::vec4 ref = sample_lod(t, s, {u[i], v[i]}, lod[i]);
                  const V4<float> r1 = texture_lod(t, s, V2<float>(u[i], v[i]), lod[i]);
                  const float got8[4] = {r8.x[i], r8.y[i], r8.z[i], r8.w[i]};
                  const float got1[4] = {r1.x, r1.y, r1.z, r1.w};
                  for (int c = 0; c < 4; ++c) {
                    ASSERT_EQ(float_bits(got8[c]), float_bits(ref[c]))
                        << format_name(f) << " lane " << i;
                    ASSERT_EQ(float_bits(got1[c]), float_bits(ref[c])) << format_name(f);
                  }
                  ASSERT_EQ(float_bits(red[i]),
                            float_bits(sample_r_lod(t, s, {u[i], v[i]}, lod[i])));
                  ASSERT_EQ(float_bits(red_entry[i]), float_bits(red[i])) << format_name(f);
                  ++checked;
                }
              }
            }
      }
  EXPECT_GT(checked, 10000);
}

TEST(Sampling, TextureGradIsSampleGradUpToLodRounding) {
  const Texture t = random_texture(TexFormat::kRGBA8, 128, 128, ColorSpace::kSRGB, 3);
  SamplerState s;  // trilinear, repeat
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uvd(0.0f, 1.0f), dd(-0.05f, 0.05f);
  float worst = 0.0f;
  for (int n = 0; n < 4000; ++n) {
    const glm::vec2 uv(uvd(rng), uvd(rng)), dx(dd(rng), dd(rng)), dy(dd(rng), dd(rng));
    const glm::vec4 ref = sample_grad(t, s, uv, dx, dy);
    const V4<float> got =
        texture_grad(t, s, V2<float>(uv.x, uv.y), V2<float>(dx.x, dx.y), V2<float>(dy.x, dy.y));
    worst = std::max({worst, std::fabs(got.x - ref.x), std::fabs(got.y - ref.y),
                      std::fabs(got.z - ref.z), std::fabs(got.w - ref.w)});
  }
  EXPECT_LT(worst, 1e-5f);
}

// The out-of-line entry (shaders_cpp/sampling_simd.h: an AVX2 clone with gathers where the CPU
// has AVX2) gives the bits of the inline F8 sampler, for every 8-bit format and filter, sRGB and
// linear, with lanes on one mip level and on different ones.
TEST(Sampling, GradEntryMatchesInlineTextureGrad) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> uvd(-2.0f, 2.0f), dd(-0.2f, 0.2f);
  int checked = 0;
  for (TexFormat f : {TexFormat::kR8, TexFormat::kRG8, TexFormat::kRGBA8, TexFormat::kR32F})
    for (ColorSpace cs : {ColorSpace::kLinear, ColorSpace::kSRGB}) {
      const Texture t = random_texture(f, 64, 64, cs, 17);
      for (Filter filter : {Filter::kNearest, Filter::kBilinear, Filter::kTrilinear}) {
        SamplerState s;
        s.filter = filter;
        for (int n = 0; n < 64; ++n) {
          V2<F8> uv, dx, dy;
          const bool one_lod = n % 2 == 0;
          for (int i = 0; i < 8; ++i) {
            uv.x.set(i, uvd(rng));
            uv.y.set(i, uvd(rng));
            dx.x.set(i, one_lod ? 0.03f : dd(rng));
            dx.y.set(i, one_lod ? 0.0f : dd(rng));
            dy.x.set(i, one_lod ? 0.0f : dd(rng));
            dy.y.set(i, one_lod ? 0.03f : dd(rng));
          }
          const V4<F8> a = texture_grad(t, s, uv, dx, dy);
          const V4<F8> b = texture_grad_lanes(t, s, uv, dx, dy);
          for (int i = 0; i < 8; ++i) {
            ASSERT_EQ(float_bits(a.x[i]), float_bits(b.x[i])) << format_name(f);
            ASSERT_EQ(float_bits(a.y[i]), float_bits(b.y[i])) << format_name(f);
            ASSERT_EQ(float_bits(a.z[i]), float_bits(b.z[i])) << format_name(f);
            ASSERT_EQ(float_bits(a.w[i]), float_bits(b.w[i])) << format_name(f);
            ++checked;
          }
        }
      }
    }
  EXPECT_EQ(checked, 4 * 2 * 3 * 64 * 8);
}

// Reads through a GradLodMemo (the LOD kept between a packet's reads with the same derivatives
// and texture size) give texture_grad's bits: textures of one size and of others, derivatives
// kept, changed in every lane or in one lane only, the anisotropic filter (which never uses the
// memo) between them; float and F8.
template <class F>
void check_memo_reads(const std::vector<const Texture*>& textures, int lanes, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uvd(-2.0f, 2.0f), dd(-0.1f, 0.1f);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(textures.size()) - 1);
  auto random_lanes = [&](F& v, float lo, float hi) {
    std::uniform_real_distribution<float> d(lo, hi);
    for (int i = 0; i < lanes; ++i) HWY_NAMESPACE::set_lane(v, i, d(rng));
  };
  GradLodMemo<F> memo;
  V2<F> dx, dy;
  random_lanes(dx.x, -0.1f, 0.1f);
  random_lanes(dx.y, -0.1f, 0.1f);
  random_lanes(dy.x, -0.1f, 0.1f);
  random_lanes(dy.y, -0.1f, 0.1f);
  int reused = 0;
  for (int n = 0; n < 600; ++n) {
    const int change = n % 5;  // 0: new derivatives, 1: one lane's dy.y changed, else kept
    if (change == 0) {
      random_lanes(dx.x, -0.1f, 0.1f);
      random_lanes(dy.y, -0.1f, 0.1f);
    } else if (change == 1) {
      HWY_NAMESPACE::set_lane(dy.y, n % lanes, dd(rng));
    }
    const Texture& t = *textures[pick(rng)];
    SamplerState s;
    s.filter = n % 7 == 0 ? Filter::kAnisotropic : Filter::kTrilinear;
    V2<F> uv;
    random_lanes(uv.x, -2.0f, 2.0f);
    random_lanes(uv.y, -2.0f, 2.0f);
    const bool kept = memo.width == t.width() && memo.height == t.height();
    const V4<F> a = texture_grad(t, s, uv, dx, dy);
    const V4<F> b = texture_grad_call(t, s, uv, dx, dy, memo);
    reused += kept && change > 1 && s.filter != Filter::kAnisotropic;
    for (int i = 0; i < lanes; ++i) {
      ASSERT_EQ(float_bits(HWY_NAMESPACE::lane(a.x, i)), float_bits(HWY_NAMESPACE::lane(b.x, i)))
          << n;
      ASSERT_EQ(float_bits(HWY_NAMESPACE::lane(a.y, i)), float_bits(HWY_NAMESPACE::lane(b.y, i)))
          << n;
      ASSERT_EQ(float_bits(HWY_NAMESPACE::lane(a.z, i)), float_bits(HWY_NAMESPACE::lane(b.z, i)))
          << n;
      ASSERT_EQ(float_bits(HWY_NAMESPACE::lane(a.w, i)), float_bits(HWY_NAMESPACE::lane(b.w, i)))
          << n;
    }
  }
  EXPECT_GT(reused, 50);  // the memo was used, not only refilled
}

TEST(Sampling, GradLodMemoGivesTextureGradBits) {
  const Texture a = random_texture(TexFormat::kRGBA8, 64, 64, ColorSpace::kSRGB, 21);
  const Texture b = random_texture(TexFormat::kRGBA8, 64, 64, ColorSpace::kLinear, 22);
  const Texture c = random_texture(TexFormat::kRGBA8, 32, 128, ColorSpace::kLinear, 23);
  const Texture d = random_texture(TexFormat::kR8, 256, 256, ColorSpace::kLinear, 24);
  const std::vector<const Texture*> textures = {&a, &b, &c, &d};
  check_memo_reads<F8>(textures, 8, 31);
  check_memo_reads<float>(textures, 1, 32);
}

// A prepared read (RLodPlan: levels chosen once for the lanes' LODs, a read entry specialised for
// format and filter; R8 bilinear levels through their footprint words) gives texture_r_lod's bits
// for every format, filter and wrap, power-of-two and other sizes, uv near and far from the
// texture, with the two quads' LODs on one level (the specialised reads) and on
// different ones (the whole sampler per read); a plan is prepared again when its texture,
// sampler or LODs change.
// detail::half_to_float_lanes for all 65536 halves, in F8 and float: every finite half against
// the scalar decode (an R16F texture read at each texel's centre; textures hold finite halves
// only, texture.cpp's sanitize_level), infinities and NaNs as IEEE says.
TEST(Sampling, HalfDecodeOverLanesEqualsTheScalarOneForEveryHalf) {
  std::vector<uint16_t> halves(65536);
  for (size_t i = 0; i < halves.size(); ++i) halves[i] = static_cast<uint16_t>(i);
  const Texture t(TexFormat::kR16F, 256, 256, halves.data(), ColorSpace::kLinear);
  SamplerState s;
  s.filter = Filter::kNearest;
  int finite = 0;
  for (int base = 0; base < 65536; base += 8) {
    I8 h;
    for (int i = 0; i < 8; ++i) set_lane(h, i, base + i);
    const F8 got = detail::half_to_float_lanes<F8>(h);
    for (int i = 0; i < 8; ++i) {
      const int k = base + i;
      const float one = detail::half_to_float_lanes<float>(k);
      ASSERT_EQ(float_bits(got[i]), float_bits(one)) << "half 0x" << std::hex << k;
      if ((k & 0x7c00) == 0x7c00) {  // not in any texture
        if ((k & 0x3ff) == 0)
          EXPECT_EQ(one, (k & 0x8000) ? -INFINITY : INFINITY) << std::hex << k;
        else
          EXPECT_TRUE(std::isnan(one)) << std::hex << k;
        continue;
      }
      ++finite;
      const float want =
          sample_r_lod(t, s, glm::vec2((k % 256 + 0.5f) / 256, (k / 256 + 0.5f) / 256), 0.0f);
      ASSERT_EQ(float_bits(one), float_bits(want)) << "half 0x" << std::hex << k;
    }
  }
  EXPECT_EQ(finite, 65536 - 2 * 1024);
}

TEST(Sampling, PlannedReadMatchesTextureRLodBitForBit) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> uvd(-3.0f, 3.0f), lodd(-1.5f, 8.0f);
  int checked = 0, shared = 0, straddling = 0, mixed = 0;
  for (TexFormat f : {TexFormat::kR8, TexFormat::kRG8, TexFormat::kRGBA8, TexFormat::kR32F})
    for (auto [w, h] : {std::pair{64, 32}, std::pair{37, 20}, std::pair{1, 1}}) {
      const Texture t = random_texture(f, w, h, ColorSpace::kLinear, static_cast<uint32_t>(w + h));
      for (Filter filter : {Filter::kNearest, Filter::kBilinear, Filter::kTrilinear})
        for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
          SamplerState s;
          s.filter = filter;
          s.wrap_u = wrap;
          s.wrap_v = wrap == Wrap::kRepeat ? Wrap::kClamp : Wrap::kRepeat;
          RLodPlan plan;
          for (int n = 0; n < 24; ++n) {
            float lod[8];
            const float a = lodd(rng), b = n % 3 == 0 ? lodd(rng) : a + 0.01f;
            for (int i = 0; i < 8; ++i) lod[i] = i < 4 ? a : b;  // one LOD per quad
            for (int r = 0; r < 4; ++r) {                        // several reads through one plan
              V2<F8> uv;
              for (int i = 0; i < 8; ++i) {
                uv.x.set(i, uvd(rng));
                uv.y.set(i, uvd(rng));
              }
              if (r == 3) {  // far from the texture, and on its edges: the wraps' extremes
                constexpr float kFar[8] = {-3e9f, 3e9f, -1e5f, 1e5f, 0.0f, 1.0f, -0.0f, 2.0f};
                for (int i = 0; i < 8; ++i) {
                  uv.x.set(i, kFar[(i + n) % 8]);
                  uv.y.set(i, kFar[(i + 3 * n + 1) % 8]);
                }
              }
              const F8 got = texture_r_lod_planned(t, s, lod, uv, plan);
              const F8 want = texture_r_lod(t, s, uv, F8::load(lod));
              for (int i = 0; i < 8; ++i) {
                ASSERT_EQ(float_bits(got[i]), float_bits(want[i]))
                    << format_name(f) << " " << w << "x" << h << " lane " << i;
                ++checked;
              }
            }
            ASSERT_TRUE(plan.prepared_for(t, s, lod));
            (plan.straddles ? straddling : plan.shared_levels ? shared : mixed) += 1;
          }
        }
    }
  EXPECT_EQ(checked, 4 * 3 * 3 * 2 * 24 * 4 * 8);
  EXPECT_GT(shared, 500);     // mostly one level: the specialised reads are what was checked
  EXPECT_GT(straddling, 20);  // quads on neighbouring pairs of levels: three levels read
  EXPECT_GT(mixed, 20);       // and quads further apart: the whole sampler per read

  // a plan made for one texture, sampler or LOD set is not used for another
  const Texture a = random_texture(TexFormat::kR8, 64, 64, ColorSpace::kLinear, 1);
  const Texture b = random_texture(TexFormat::kR8, 64, 64, ColorSpace::kLinear, 2);
  SamplerState s;
  float lod[8] = {1.25f, 1.25f, 1.25f, 1.25f, 1.25f, 1.25f, 1.25f, 1.25f};
  RLodPlan plan;
  const V2<F8> uv(F8(0.3f), F8(0.7f));
  texture_r_lod_planned(a, s, lod, uv, plan);
  EXPECT_TRUE(plan.prepared_for(a, s, lod));
  EXPECT_FALSE(plan.prepared_for(b, s, lod));
  const F8 from_b = texture_r_lod_planned(b, s, lod, uv, plan);
  EXPECT_EQ(float_bits(from_b[0]), float_bits(texture_r_lod(b, s, uv, F8::load(lod))[0]));
  SamplerState nearest = s;
  nearest.filter = Filter::kNearest;
  EXPECT_FALSE(plan.prepared_for(b, nearest, lod));
  lod[5] = 2.0f;
  EXPECT_FALSE(plan.prepared_for(b, s, lod));
}

}  // namespace
}  // namespace relief
