// Tests for rasterizer/tone_map: the tone curves of `relief render --tonemap`. Reference values are
// worked out by hand from the published formulas (Khronos ToneMapping PBR_Neutral/pbrNeutral.glsl;
// the glTF Sample Viewer's toneMapACES_Hill), in the comments beside them.
#include "rasterizer/tone_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief {
namespace {

// HSV hue of a colour in [0, 6) (undefined for grey: callers pass chromatic colours).
float hue(glm::vec3 c) {
  const float mx = std::max({c.r, c.g, c.b}), mn = std::min({c.r, c.g, c.b});
  const float d = mx - mn;
  if (mx == c.r) return std::fmod((c.g - c.b) / d + 6.0f, 6.0f);
  if (mx == c.g) return (c.b - c.r) / d + 2.0f;
  return (c.r - c.g) / d + 4.0f;
}
float saturation(glm::vec3 c) {
  const float mx = std::max({c.r, c.g, c.b});
  return (mx - std::min({c.r, c.g, c.b})) / mx;
}

void expect_near(glm::vec3 got, glm::vec3 want, float tol) {
  EXPECT_NEAR(got.r, want.r, tol);
  EXPECT_NEAR(got.g, want.g, tol);
  EXPECT_NEAR(got.b, want.b, tol);
}

TEST(ToneMap, NamesRoundTrip) {
  for (ToneCurve c : {ToneCurve::kNone, ToneCurve::kAcesHill, ToneCurve::kPbrNeutral}) {
    ToneCurve back = c == ToneCurve::kNone ? ToneCurve::kAcesHill : ToneCurve::kNone;
    ASSERT_TRUE(parse_tone_curve(tone_curve_name(c), back)) << tone_curve_name(c);
    EXPECT_EQ(back, c);
  }
  ToneCurve c = ToneCurve::kNone;
  for (const char* bad : {"", "ACES", "pbr_neutral", "aces ", "reinhard", "filmic"})
    EXPECT_FALSE(parse_tone_curve(bad, c)) << bad;
}

TEST(ToneMap, NoneIsAClamp) {
  expect_near(tone_map(ToneCurve::kNone, {0.25f, 1.5f, -0.5f}), {0.25f, 1.0f, 0.0f}, 0.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  expect_near(tone_map(ToneCurve::kNone, {nan, inf, 0.5f}), {0.0f, 1.0f, 0.5f}, 0.0f);
}

TEST(ToneMap, PbrNeutralIsTheIdentityMinusTheOffsetBelowCompression) {
  // min >= 0.08: the offset is 0.04; max - 0.04 < startCompression = 0.76 (max < 0.8): no
  // compression, the colour comes out minus 0.04.
  for (glm::vec3 c :
       {glm::vec3(0.5f, 0.3f, 0.2f), glm::vec3(0.79f, 0.08f, 0.4f), glm::vec3(0.1f, 0.1f, 0.1f)})
    expect_near(tone_map_pbr_neutral(c), c - 0.04f, 1e-7f);
  // The toe: min x < 0.08 subtracts x - 6.25 x^2, so grey 0.05 gives 6.25 * 0.0025 = 0.015625;
  // (0.5, 0.05, 0.2) minus 0.034375 = (0.465625, 0.015625, 0.165625).
  expect_near(tone_map_pbr_neutral(glm::vec3(0.05f)), glm::vec3(0.015625f), 1e-7f);
  expect_near(tone_map_pbr_neutral({0.5f, 0.05f, 0.2f}), {0.465625f, 0.015625f, 0.165625f}, 1e-7f);
  // The toe meets the constant at 0.08 (0.08 - 6.25 * 0.0064 = 0.04): continuous there.
  EXPECT_NEAR(tone_map_pbr_neutral(glm::vec3(0.0799999f)).r,
              tone_map_pbr_neutral(glm::vec3(0.08f)).r, 1e-6f);
  expect_near(tone_map_pbr_neutral(glm::vec3(0.0f)), glm::vec3(0.0f), 0.0f);
}

TEST(ToneMap, PbrNeutralReferenceValues) {
  // Grey 1: 1 - 0.04 = 0.96 = peak; d = 0.24; new peak = 1 - 0.0576 / (0.96 + 0.24 - 0.76)
  // = 1 - 0.0576 / 0.44 = 0.8690909; grey stays grey.
  expect_near(tone_map_pbr_neutral(glm::vec3(1.0f)), glm::vec3(0.8690909f), 1e-6f);
  // (2, 1, 0.5) - 0.04 = (1.96, 0.96, 0.46); new peak = 1 - 0.0576 / 1.44 = 0.96; scaled by
  // 0.96 / 1.96: (0.96, 0.4702041, 0.2253061); g = 1 - 1 / (0.15 * (1.96 - 0.96) + 1) =
  // 0.1304348; mixed towards 0.96: (0.96, 0.5340905, 0.3211358).
  expect_near(tone_map_pbr_neutral({2.0f, 1.0f, 0.5f}), {0.96f, 0.5340905f, 0.3211358f}, 1e-6f);
}

TEST(ToneMap, PbrNeutralIsMonotoneBoundedAndKeepsHue) {
  // Monotone up to float rounding: near 1 the scale-and-mix of a grey can come out one ulp
  // (6e-8) below its neighbour's (grey 318.6 after 318.5), as the reference GLSL does in float.
  constexpr float kUlps = 3e-7f;
  float last = -1.0f;
  for (int i = 0; i <= 4000; ++i) {  // grey 0 .. 400
    const float v = tone_map_pbr_neutral(glm::vec3(i * 0.1f)).r;
    EXPECT_GE(v, last - kUlps) << i;
    EXPECT_LT(v, 1.0f) << i;
    last = v;
  }
  EXPECT_GT(last, 0.999f);  // 1 - 0.0576 / (399.96 - 0.52)
  const glm::vec3 chroma(1.0f, 0.45f, 0.1f);
  float last_peak = -1.0f;
  for (int i = 1; i <= 1000; ++i) {  // a chromatic colour from 0.05 to 50 times itself
    const glm::vec3 in = chroma * (i * 0.05f);
    const glm::vec3 out = tone_map_pbr_neutral(in);
    const float peak = std::max({out.r, out.g, out.b});
    EXPECT_GE(peak, last_peak - kUlps) << i;
    EXPECT_LT(peak, 1.0f) << i;
    EXPECT_GE(std::min({out.r, out.g, out.b}), 0.0f) << i;
    last_peak = peak;
    // Subtracting one offset from every channel, scaling and mixing towards grey keep the HSV
    // hue; saturation falls only by the documented desaturation factor 1 / (0.15 (p - p') + 1).
    EXPECT_NEAR(hue(out), hue(in), 2e-4f) << i;
    const glm::vec3 shifted = in - (in.b < 0.08f ? in.b - 6.25f * in.b * in.b : 0.04f);
    const float p = std::max({shifted.r, shifted.g, shifted.b});
    if (p >= 0.76f) {
      const float p2 = 1.0f - 0.0576f / (p + 0.24f - 0.76f);
      EXPECT_NEAR(saturation(out), saturation(shifted) / (0.15f * (p - p2) + 1.0f), 1e-5f) << i;
    }
  }
}

TEST(ToneMap, AcesHillReferenceValues) {
  // Both matrices have rows summing to 1 (the output's blue row to 0.99999), so grey stays grey
  // and only the fit acts: f(1) = (1.0245786 - 0.000090537) / (0.983729 + 0.4329510 + 0.238081)
  // = 1.0244881 / 1.654761 = 0.6191154 (blue 0.99999 of it: 0.6191092).
  expect_near(tone_map_aces_hill(glm::vec3(1.0f)), {0.6191154f, 0.6191154f, 0.6191092f}, 2e-6f);
  // f(0.18) = (0.18 * 0.2045786 - 0.000090537) / (0.18 * 0.6100222 + 0.238081)
  // = 0.0367336 / 0.3478850 = 0.1055912.
  EXPECT_NEAR(tone_map_aces_hill(glm::vec3(0.18f)).r, 0.1055912f, 2e-6f);
  // f(0) = -0.000090537 / 0.238081 < 0, clamped: black stays black.
  expect_near(tone_map_aces_hill(glm::vec3(0.0f)), glm::vec3(0.0f), 0.0f);
}

TEST(ToneMap, AcesHillIsMonotoneOnGreyAndClipsAtOne) {
  float last = -1.0f;
  for (int i = 0; i <= 3000; ++i) {  // grey 0 .. 30
    const float v = tone_map_aces_hill(glm::vec3(i * 0.01f)).g;
    EXPECT_GE(v, last) << i;
    EXPECT_LE(v, 1.0f) << i;
    last = v;
  }
  // The fit tends to 1 / 0.983729 = 1.0165 and crosses 1 at grey 25.67, so the curve does not
  // saturate below 1: grey 20 is 0.9952851 (still below), grey 26 and 1000 clip to 1.
  EXPECT_NEAR(tone_map_aces_hill(glm::vec3(20.0f)).r, 0.9952851f, 2e-6f);
  EXPECT_EQ(tone_map_aces_hill(glm::vec3(26.0f)).r, 1.0f);
  EXPECT_EQ(tone_map_aces_hill(glm::vec3(1000.0f)), glm::vec3(1.0f));
  // Non-finite input is made finite first: no NaN out.
  const glm::vec3 inf = tone_map_aces_hill(glm::vec3(std::numeric_limits<float>::infinity()));
  EXPECT_EQ(inf, glm::vec3(1.0f));
}

TEST(ToneMap, ImageMapsStraightColourAndKeepsCoverage) {
  Image im(3, 1);
  im.at(0, 0) = {2.0f, 1.0f, 0.5f, 1.0f};                 // opaque
  im.at(1, 0) = {1.0f, 0.5f, 0.25f, 0.5f};                // (2, 1, 0.5) at half coverage
  im.at(2, 0) = {0.0f, 0.0f, 0.0f, 0.0f};                 // background
  const glm::vec3 mapped(0.96f, 0.5340905f, 0.3211358f);  // PbrNeutralReferenceValues
  Image none = im;
  apply_tone_curve(none, ToneCurve::kNone);
  EXPECT_EQ(none.pixels, im.pixels);  // untouched: the encoder clamps, as it always did
  apply_tone_curve(im, ToneCurve::kPbrNeutral);
  expect_near(glm::vec3(im.at(0, 0)), mapped, 1e-6f);
  expect_near(glm::vec3(im.at(1, 0)), mapped * 0.5f, 1e-6f);
  EXPECT_EQ(im.at(1, 0).a, 0.5f);
  EXPECT_EQ(im.at(2, 0), glm::vec4(0.0f));
}

}  // namespace
}  // namespace relief
