// Self-shadow rays (shaders_cpp/shadow.h) and the exact shadow query, on a wall scene.
#include "shaders_cpp/shadow.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shaders_cpp/exact_trace.h"
#include "shaders_cpp/ray.h"
#include "tests/bake/field_fixture.h"

namespace relief {
namespace {

using testing::FloatField;

// Depth-1 floor with a full-height wall (depth 0) on texel columns 15 and 16 of 32.
FloatField wall_field() {
  FloatField f;
  f.w = f.h = 32;
  f.wrap_u = f.wrap_v = Wrap::kClamp;
  f.d.assign(32 * 32, 1.0f);
  for (int j = 0; j < 32; ++j) f.d[j * 32 + 15] = f.d[j * 32 + 16] = 0.0f;
  return f;
}

struct Case {
  V3<float> light;
  bool shadowed;
};

TEST(Shadow, WallShadowsFloorBehindIt) {
  FloatField f = wall_field();
  HeightField hf = f.exact();
  const float scale = 0.5f;
  const V2<float> uv(20.5f / 32.0f, 0.5f);  // floor texel 4 right of the wall
  const float t = f(0, uv.x, uv.y);
  ASSERT_EQ(t, 1.0f);
  const float s2 = std::sqrt(0.5f);
  const Case cases[] = {
      {V3<float>(-s2, 0.0f, s2), true},          // light behind the wall
      {V3<float>(0.0f, 0.0f, 1.0f), false},      // overhead
      {V3<float>(s2, 0.0f, s2), false},          // from the open side
      {V3<float>(0.0f, s2, s2), false},          // along the wall
      {V3<float>(-0.99f, 0.0f, -0.141f), true},  // below the horizon
  };
  for (const Case& c : cases) {
    V2<float> dl = light_step(c.light, scale);
    for (int n : {8, 32, 128}) {
      ShadowResult<float> r = self_shadow(f, uv, t, dl, c.light.z, n, 1e-3f, true);
      EXPECT_EQ(r.visibility, c.shadowed ? 0.0f : 1.0f) << c.light.x << " n=" << n;
      ShadowResult<float> soft = self_shadow<true>(f, uv, t, dl, c.light.z, n, 1e-3f, true);
      if (c.shadowed) {
        EXPECT_LT(soft.visibility, 0.5f);
      } else {
        EXPECT_EQ(soft.visibility, 1.0f);
      }
    }
    EXPECT_EQ(exact_shadow(hf, uv, t, dl, c.light.z, 1e-4f, true), c.shadowed ? 0.0f : 1.0f);
  }
}

TEST(Shadow, StopsAtFirstBlockerAndCountsSteps) {
  FloatField f = wall_field();
  const V2<float> uv(20.5f / 32.0f, 0.5f);
  const float s2 = std::sqrt(0.5f);
  V2<float> dl = light_step(V3<float>(-s2, 0.0f, s2), 0.5f);  // (-0.5, 0)
  ShadowResult<float> hard = self_shadow(f, uv, 1.0f, dl, s2, 64, 1e-3f, true);
  // the wall's slope starts 3.5 texels (0.109 uv, s = 0.219) away: blocked within ~16 steps
  EXPECT_GT(hard.steps, 10.0f);
  EXPECT_LT(hard.steps, 20.0f);
  EXPECT_EQ(hard.fetches, hard.steps);
  ShadowResult<float> lit = self_shadow(f, uv, 1.0f, V2<float>(0.0f, 0.0f), 1.0f, 64, 1e-3f, true);
  EXPECT_EQ(lit.steps, 63.0f);  // s = 1/64 ... 63/64 below t = 1
  ShadowResult<float> top = self_shadow(f, uv, 0.0f, dl, s2, 64, 1e-3f, true);
  EXPECT_EQ(top.steps, 0.0f);
  EXPECT_EQ(top.visibility, 1.0f);
}

}  // namespace
}  // namespace relief
