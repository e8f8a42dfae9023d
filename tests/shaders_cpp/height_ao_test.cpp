// Ambient occlusion from the height field (shaders_cpp/height_ao.h): a flat map is unoccluded
// exactly, the bottom of a deep narrow pit strongly occluded and its rim not, the factor falls
// with strength, every input stays finite, and float and F8 lanes agree bit for bit.
#include "shaders_cpp/height_ao.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tests/shaders_cpp/float_bits.h"

namespace relief {
namespace {

// A depth source: `floor` everywhere but a square pit of half-width `half` at (0.5, 0.5),
// `bottom` deep.
struct Pit {
  float floor = 0.0f, bottom = 1.0f, half = 0.01f;
  float operator()(int, float u, float v) const {
    return std::fabs(u - 0.5f) < half && std::fabs(v - 0.5f) < half ? bottom : floor;
  }
};

// A smooth height field with slopes in every direction.
struct Waves {
  float operator()(int, float u, float v) const {
    return 0.5f + 0.25f * std::sin(40.0f * u) * std::cos(31.0f * v);
  }
};

HeightAoResult<float> ao_at(const auto& depth, float u, float v, int rays = 8, float radius = 0.05f,
                            float depth_scale = 0.05f) {
  return height_field_ao(depth, V2<float>(u, v), rays, radius, depth_scale, true);
}

TEST(HeightAo, FlatMapIsUnoccludedExactly) {
  for (float level : {0.0f, 0.3f, 1.0f}) {
    const HeightAoResult<float> r = ao_at(Pit{level, level}, 0.5f, 0.5f);
    EXPECT_EQ(r.ao, 1.0f) << level;
    EXPECT_EQ(height_ao_factor(r.ao, 1.0f), 1.0f);
    EXPECT_EQ(r.fetches, 1.0f + 8.0f * kHeightAoSteps);
  }
}

TEST(HeightAo, PitBottomIsOccludedAndItsRimIsNot) {
  const Pit pit;
  const float bottom = ao_at(pit, 0.5f, 0.5f).ao;
  EXPECT_LT(bottom, 0.5f);
  EXPECT_GE(bottom, 0.0f);
  // on the floor just outside the pit: nothing rises above it
  EXPECT_EQ(ao_at(pit, 0.5f + 1.5f * pit.half, 0.5f).ao, 1.0f);
  // a shallower pit occludes less
  EXPECT_GT(ao_at(Pit{0.0f, 0.2f}, 0.5f, 0.5f).ao, bottom);
  // a wider radius sees the same walls at a lower angle
  EXPECT_GT(ao_at(pit, 0.5f, 0.5f, 8, 0.2f).ao, bottom);
}

TEST(HeightAo, FactorFallsMonotonicallyWithStrength) {
  const float ao = ao_at(Pit{}, 0.5f, 0.5f).ao;
  float last = 2.0f;
  for (int i = 0; i <= 10; ++i) {
    const float f = height_ao_factor(ao, 0.1f * static_cast<float>(i));
    EXPECT_LT(f, last) << i;
    last = f;
  }
  EXPECT_EQ(height_ao_factor(ao, 0.0f), 1.0f);
  EXPECT_FLOAT_EQ(height_ao_factor(ao, 1.0f), ao);  // 1 - (1 - ao): rounded
}

TEST(HeightAo, DegenerateInputsStayFinite) {
  const Pit pit;
  // off: no fetch, AO 1
  for (const HeightAoResult<float>& r :
       {ao_at(pit, 0.5f, 0.5f, 0), ao_at(pit, 0.5f, 0.5f, 8, 0.0f), ao_at(pit, 0.5f, 0.5f, -3)}) {
    EXPECT_EQ(r.ao, 1.0f);
    EXPECT_EQ(r.fetches, 0.0f);
  }
  const HeightAoResult<float> inactive =
      height_field_ao(pit, V2<float>(0.5f, 0.5f), 8, 0.05f, 0.05f, false);
  EXPECT_EQ(inactive.ao, 1.0f);
  EXPECT_EQ(inactive.fetches, 0.0f);
  // one ray, a tiny radius, a full-height relief: finite and in [0, 1]
  for (float radius : {1e-38f, 1e-30f, 1e-8f, 1.0f})
    for (int rays : {1, 16})
      for (float scale : {0.0f, 1.0f}) {
        const float ao = ao_at(pit, 0.5f, 0.5f, rays, radius, scale).ao;
        EXPECT_TRUE(std::isfinite(ao)) << radius << " " << rays << " " << scale;
        EXPECT_GE(ao, 0.0f);
        EXPECT_LE(ao, 1.0f);
      }
}

TEST(HeightAo, FloatAndF8AreBitIdentical) {
  std::mt19937 rng(24);
  std::uniform_real_distribution<float> c(0.0f, 1.0f);
  const Waves waves;
  for (int n = 0; n < 500; ++n) {
    V2<F8> uv;
    for (int i = 0; i < 8; ++i) {
      uv.x.set(i, c(rng));
      uv.y.set(i, c(rng));
    }
    const int rays = 1 + n % 16;
    const float radius = 0.002f + 0.1f * c(rng), scale = 0.2f * c(rng);
    const HeightAoResult<F8> r = height_field_ao(waves, uv, rays, radius, scale, true_mask<F8>());
    for (int i = 0; i < 8; ++i) {
      const HeightAoResult<float> s = ao_at(waves, uv.x[i], uv.y[i], rays, radius, scale);
      ASSERT_EQ(testing::float_bits(r.ao[i]), testing::float_bits(s.ao)) << n << " " << i;
      ASSERT_EQ(r.fetches[i], s.fetches);
    }
  }
}

}  // namespace
}  // namespace relief
