// vlog2, vexp2 and vpow_fast (shaders_cpp/lanes.h) against libm, and their float and F8
// instantiations bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "shaders_cpp/lanes.h"
#include "tests/shaders_cpp/float_bits.h"

namespace relief {
namespace {

using testing::float_bits;

TEST(LanesMath, Log2AndExp2AreAccurate) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> e(-120.0f, 120.0f), y(-125.0f, 126.0f);
  double worst_log = 0, worst_exp = 0;
  for (int i = 0; i < 200000; ++i) {
    const float x = std::exp2(e(rng));
    const double ref_log = std::log2(double(x));
    // float's own rounding of the result dominates far from 1
    worst_log = std::max(worst_log,
                         std::fabs(double(vlog2(x)) - ref_log) / std::max(1.0, std::fabs(ref_log)));
    const float v = y(rng);
    const double ref = std::exp2(double(v));
    worst_exp = std::max(worst_exp, std::fabs(double(vexp2(v)) - ref) / ref);
  }
  EXPECT_LT(worst_log, 1.5e-7);  // absolute below 1, relative above
  EXPECT_LT(worst_exp, 3e-7);
  EXPECT_EQ(vexp2(5.0f), 32.0f);
  EXPECT_EQ(vexp2(-3.0f), 0.125f);
  EXPECT_EQ(vlog2(1.0f), 0.0f);
  EXPECT_EQ(vexp2(0.0f), 1.0f);
  EXPECT_EQ(vexp2(-200.0f), 0.0f);
  EXPECT_TRUE(std::isfinite(vexp2(1000.0f)));
  EXPECT_TRUE(std::isfinite(vexp2(NAN)));
}

TEST(LanesMath, PowMatchesLibmOnTheSpecularDomain) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> x01(0.0f, 1.0f);
  double worst = 0;
  for (float e : {1.0f, 8.0f, 32.0f, 128.0f}) {
    for (int i = 0; i < 100000; ++i) {
      const float x = x01(rng);
      const double ref = std::pow(double(x), double(e));
      if (ref < 1e-30) continue;
      // the float exponent e * log2(x) carries a relative rounding error of its own
      const double y = std::max(1.0, std::fabs(double(e) * std::log2(double(x))));
      worst = std::max(worst, std::fabs(double(vpow_fast(x, e)) - ref) / ref / y);
    }
  }
  EXPECT_LT(worst, 3e-7);
  EXPECT_EQ(vpow_fast(0.0f, 32.0f), 0.0f);
  EXPECT_EQ(vpow_fast(0.0f, 0.0f), 1.0f);
  EXPECT_EQ(vpow_fast(1.0f, 32.0f), 1.0f);
}

// vfloor(F8) is written without a round instruction; it must still be std::floor bit for bit.
TEST(LanesMath, F8FloorIsStdFloorBitForBit) {
  std::vector<float> xs = {0.0f,
                           -0.0f,
                           0.5f,
                           -0.5f,
                           1.0f,
                           -1.0f,
                           1.5f,
                           -1.5f,
                           2.0f - 1e-7f,
                           -2.0f + 1e-7f,
                           8388607.5f,
                           -8388607.5f,
                           8388608.0f,
                           -8388608.0f,
                           16777217.0f,
                           1e30f,
                           -1e30f,
                           1e-45f,
                           -1e-45f,
                           1.17549435e-38f,
                           -1.17549435e-38f,
                           INFINITY,
                           -INFINITY,
                           NAN,
                           -NAN,
                           2147483648.0f,
                           -2147483904.0f,
                           0.99999994f,
                           -0.99999994f};
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> wide(-1e7f, 1e7f), narrow(-4.0f, 4.0f);
  std::uniform_int_distribution<uint32_t> any_bits;
  for (int i = 0; i < 20000; ++i) {
    xs.push_back(wide(rng));
    xs.push_back(narrow(rng));
    const uint32_t b = any_bits(rng);
    float x;
    std::memcpy(&x, &b, 4);
    xs.push_back(x);
  }
  while (xs.size() % 8) xs.push_back(0.25f);
  for (size_t i = 0; i < xs.size(); i += 8) {
    const F8 r = vfloor(F8::load(&xs[i]));
    for (int k = 0; k < 8; ++k) {
      const float want = std::floor(xs[i + k]);
      if (std::isnan(want)) {
        EXPECT_TRUE(std::isnan(r[k])) << xs[i + k];
      } else {
        EXPECT_EQ(float_bits(r[k]), float_bits(want)) << xs[i + k];
      }
    }
  }
}

TEST(LanesMath, FloatAndF8AreBitIdentical) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<float> d(-40.0f, 40.0f);
  for (int n = 0; n < 20000; ++n) {
    F8 x;
    for (int i = 0; i < 8; ++i) x.set(i, n % 5 == 0 ? d(rng) : std::exp2(d(rng)));
    const F8 l = vlog2(x), e = vexp2(x), p = vpow_fast(x, 17.0f);
    for (int i = 0; i < 8; ++i) {
      ASSERT_EQ(float_bits(l[i]), float_bits(vlog2(x[i])));
      ASSERT_EQ(float_bits(e[i]), float_bits(vexp2(x[i])));
      ASSERT_EQ(float_bits(p[i]), float_bits(vpow_fast(x[i], 17.0f)));
    }
  }
}

}  // namespace
}  // namespace relief
