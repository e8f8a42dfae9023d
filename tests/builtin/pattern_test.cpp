// The `pattern` depth map (builtin/builtin.h make_pattern_depth) as a height field: it has the
// one-texel walls it promises, and the exact reference (shaders_cpp/exact_trace.h, Tevs et al. 2008
// max-mip traversal) never reports a hit later than a dense brute-force march on it.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "builtin/builtin.h"
#include "shaders_cpp/exact_trace.h"
#include "tests/bake/field_fixture.h"

namespace relief {
namespace {

TEST(Pattern, DepthHasOneTexelWallsAndIsInRange) {
  for (int size : {64, 256}) {
    const Texture t = make_pattern_depth(size);
    ASSERT_EQ(t.width(0), size);
    ASSERT_GT(t.levels(), 1);
    int walls = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float d = t.fetch_r(0, x, y);
        ASSERT_GE(d, 0.0f);
        ASSERT_LE(d, 1.0f);
      }
    // the thin quadrant (x < size / 2 <= y): walls every 8 texels over a floor at depth 1, each
    // one texel wide (both side neighbours on the floor)
    const int h = size / 2;
    for (int y = h + 1; y < size; ++y)
      for (int x = 8; x < h; x += 8) {
        if ((y - h) % 8 == 0) continue;
        EXPECT_EQ(t.fetch_r(0, x, y), 0.0f) << x << " " << y;
        EXPECT_EQ(t.fetch_r(0, x - 1, y), 1.0f) << x << " " << y;
        EXPECT_EQ(t.fetch_r(0, x + 1, y), 1.0f) << x << " " << y;
        ++walls;
      }
    EXPECT_GT(walls, size * size / 64);
    // quadrant walls at x = 0 and x = size / 2, one texel wide as well
    for (int y = 1; y < size; ++y) {
      if (y == h) continue;
      EXPECT_EQ(t.fetch_r(0, 0, y), 0.0f);
      EXPECT_EQ(t.fetch_r(0, h, y), 0.0f);
      if (y < h || (y - h) % 8 != 0) {  // not a crossing wall
        EXPECT_GT(t.fetch_r(0, 1, y), 0.0f);
      }
      EXPECT_GT(t.fetch_r(0, h + 1, y), 0.0f);
    }
  }
}

// 200 random rays (up to 85 degrees from the normal, 2 to 15 % of the texture deep, so they cross
// up to 440 texels) on the 256 x 256 pattern with repeat wrap: the exact hit is on the surface
// and never after the first inside sample of a 1e5-step march.
TEST(Pattern, ExactNeverLaterThanDenseMarch) {
  const Texture t = make_pattern_depth(kPatternSize);
  const HeightField hf = HeightField::from_texture(t, SamplerState{});
  const int kMarch = 100000;
  std::mt19937 rng(31);
  int earlier = 0;
  for (int k = 0; k < 200; ++k) {
    const testing::RandomRay r = testing::random_ray(rng, 85.0f, 0.02f, 0.15f);
    const ExactHit h = hf.intersect(r.u, r.v, r.dsx, r.dsy);
    ASSERT_LE(hf.depth_at(h.u, h.v) - h.t, 1e-9) << k;
    double march = 1.0;
    for (int i = 0; i <= kMarch; ++i) {
      const double s = static_cast<double>(i) / kMarch;
      if (hf.depth_at(r.u + s * r.dsx, r.v + s * r.dsy) <= s) {
        march = s;
        break;
      }
    }
    ASSERT_LE(h.t, march + 1e-12) << k;
    earlier += march - h.t > 2.0 / kMarch;  // a crossing too thin for the march
  }
  RecordProperty("exact_earlier_than_march", earlier);
}

}  // namespace
}  // namespace relief
