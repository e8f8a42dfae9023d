// srgb_byte (tables) against encode_srgb8 (the definition): every float in [0, 1] (all 2^30
// bit patterns, about 7 s in a Release build), and the values outside it.
#include "rasterizer/srgb_bytes.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>

#include "rasterizer/texture.h"

namespace relief {
namespace {

TEST(SrgbBytes, EveryFloatInZeroOneGivesTheExactByte) {
  long bad = 0;
  int seen[256] = {};
  for (uint32_t b = 0; b <= 0x3f800000u; ++b) {  // 0 to 1.0f
    const float c = std::bit_cast<float>(b);
    const uint8_t got = srgb_byte(c);
    ++seen[got];
    if (got != encode_srgb8(c) && ++bad <= 5)
      ADD_FAILURE() << "bits 0x" << std::hex << b << " (" << c << "): table " << std::dec
                    << int(got) << ", exact " << int(encode_srgb8(c));
  }
  EXPECT_EQ(bad, 0);
  for (int k = 0; k < 256; ++k) EXPECT_GT(seen[k], 0) << k;  // every byte is reached
}

TEST(SrgbBytes, ValuesOutsideZeroOneClamp) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float c : {-0.0f, -std::numeric_limits<float>::denorm_min(), -1.0f, -inf, nan, 1.0000001f,
                  1.5f, 3e38f, inf})
    EXPECT_EQ(srgb_byte(c), encode_srgb8(c)) << c;
  EXPECT_EQ(srgb_byte(nan), 0);
  EXPECT_EQ(srgb_byte(-1.0f), 0);
  EXPECT_EQ(srgb_byte(1.5f), 255);
  EXPECT_EQ(srgb_byte(0.5f), 188);  // 255 * (1.055 * 0.5^(1/2.4) - 0.055) = 187.52
  EXPECT_EQ(srgb_byte(0.001f), 3);  // 255 * 12.92 * 0.001 = 3.29
}

}  // namespace
}  // namespace relief
