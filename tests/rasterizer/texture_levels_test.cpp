// Texture::from_levels: explicit mip chains (the prefiltered environment, bake/environment_bake.h)
// keep their levels and read through sample_lod like generated ones.
#include <gtest/gtest.h>

#include <vector>

#include "rasterizer/texture.h"

namespace relief {
namespace {

MipLevel float_level(int w, int h, float value) {
  std::vector<float> v(static_cast<size_t>(w) * h * 4, value);
  return Texture::from_floats(TexFormat::kRGBA16F, w, h, v.data()).level(0);
}

TEST(TextureLevels, ExplicitLevelsAreKeptAndSampledAtTheirLod) {
  std::vector<MipLevel> levels;
  for (int k = 0; k < 3; ++k) levels.push_back(float_level(8 >> k, 4 >> k, 1.0f + k));
  const Texture t = Texture::from_levels(TexFormat::kRGBA16F, levels);
  ASSERT_EQ(t.levels(), 3);
  EXPECT_EQ(t.width(2), 2);
  EXPECT_EQ(t.height(2), 1);
  const SamplerState s{Filter::kTrilinear, Wrap::kClamp, Wrap::kClamp, 1};
  EXPECT_FLOAT_EQ(sample_lod(t, s, {0.3f, 0.6f}, 0.0f).x, 1.0f);
  EXPECT_FLOAT_EQ(sample_lod(t, s, {0.3f, 0.6f}, 1.5f).x, 2.5f);  // halfway between 1 and 2
  EXPECT_FLOAT_EQ(sample_lod(t, s, {0.3f, 0.6f}, 7.0f).x, 3.0f);  // clamped to the last level
}

TEST(TextureLevelsDeathTest, WrongLevelSizeIsRefused) {
  std::vector<MipLevel> levels{float_level(8, 8, 1.0f), float_level(3, 4, 1.0f)};
  EXPECT_DEATH(Texture::from_levels(TexFormat::kRGBA16F, levels), "");
}

}  // namespace
}  // namespace relief
