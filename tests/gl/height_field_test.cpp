// gl/height_field.h: the max-mip packed for the exact twin holds the field
// shaders_cpp/exact_trace.h's HeightField is built from, and each node bounds what lies under it.
#include "gl/height_field.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "shaders_cpp/exact_trace.h"

namespace relief::gl {
namespace {

using P = PackedHeightField;

// A depth map with sharp and smooth parts and no symmetry (odd sizes exercise partial nodes).
Texture test_depth(int w, int h) {
  std::vector<float> d(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      d[static_cast<size_t>(j) * w + i] =
          std::fmod(0.37f * i + 0.11f * j * j + ((i * 7 + j * 3) % 5 == 0 ? 0.5f : 0.0f), 1.0f);
  return Texture::from_floats(TexFormat::kR8, w, h, d.data());
}

// HeightField::depth_at, read from the packed texels.
double packed_depth_at(const P& p, double u, double v) {
  auto locate = [&](int axis, double uv, int& i, double& f) {
    const bool periodic = p.header(P::kPeriodic + axis) != 0;
    const int size = p.header(P::kSize + axis), period = p.header(P::kPeriod + axis);
    double x = uv * size - 0.5;
    if (periodic) {
      x -= std::floor(x / period) * period;
      i = std::min(static_cast<int>(std::floor(x)), period - 1);
    } else {
      x = std::clamp(x, 0.0, static_cast<double>(size - 1));
      i = std::min(static_cast<int>(std::floor(x)), p.header(P::kCells + axis) - 1);
    }
    f = x - i;
  };
  auto corner = [&](int axis, int i) {
    const int size = p.header(P::kSize + axis), period = p.header(P::kPeriod + axis);
    return p.header(P::kPeriodic + axis) ? (i + 1 == period ? 0 : i + 1)
                                         : std::min(i + 1, size - 1);
  };
  int i, j;
  double fx, fy;
  locate(0, u, i, fx);
  locate(1, v, j, fy);
  const int i1 = corner(0, i), j1 = corner(1, j);
  const double a = p.texel(i, j), b = p.texel(i1, j), c = p.texel(i, j1), d = p.texel(i1, j1);
  return (a + (b - a) * fx) * (1.0 - fy) + (c + (d - c) * fx) * fy;
}

class PackedField : public ::testing::TestWithParam<std::tuple<int, int, Wrap, Wrap>> {};

TEST_P(PackedField, TexelsMatchHeightFieldAndNodesBoundTheirChildren) {
  const auto [w, h, wu, wv] = GetParam();
  const Texture t = test_depth(w, h);
  SamplerState s;
  s.wrap_u = wu;
  s.wrap_v = wv;
  Result<P> packed = pack_height_field(t, s);
  ASSERT_TRUE(packed.ok()) << packed.status().message();
  const P& p = *packed;
  const HeightField field = HeightField::from_texture(t, s);
  // the same bilinear field everywhere, wraps included
  for (int k = 0; k < 2000; ++k) {
    const double u = -3.0 + 7.0 * ((k * 7919) % 2000) / 2000.0;
    const double v = -2.5 + 6.0 * ((k * 104729) % 2000) / 2000.0;
    ASSERT_EQ(packed_depth_at(p, u, v), field.depth_at(u, v)) << u << ", " << v;
  }
  // leaves: the minimum of the cell's corners; above: the minimum of the 2x2 children; the top
  // is 1 x 1
  const int levels = p.header(P::kNumLevels);
  ASSERT_GE(levels, 1);
  EXPECT_EQ(p.header(P::kNx + levels - 1), 1);
  EXPECT_EQ(p.header(P::kNy + levels - 1), 1);
  const int nx0 = p.header(P::kNx), ny0 = p.header(P::kNy);
  EXPECT_EQ(nx0, p.header(P::kCells));
  EXPECT_EQ(ny0, p.header(P::kCells + 1));
  for (int j = 0; j < ny0; ++j)
    for (int i = 0; i < nx0; ++i) {
      const double x = (i + 1.0) / w, y = (j + 1.0) / h;  // the cell's centre, uv
      float lo = 2.0f;
      for (double dy : {-0.5, 0.5})
        for (double dx : {-0.5, 0.5})
          lo = std::min(lo, static_cast<float>(field.depth_at(x + dx / w, y + dy / h)));
      ASSERT_EQ(p.node(0, i, j), lo) << i << ", " << j;
    }
  for (int l = 1; l < levels; ++l)
    for (int j = 0; j < p.header(P::kNy + l); ++j)
      for (int i = 0; i < p.header(P::kNx + l); ++i) {
        float lo = 2.0f;
        for (int cj = 2 * j; cj < std::min(2 * j + 2, p.header(P::kNy + l - 1)); ++cj)
          for (int ci = 2 * i; ci < std::min(2 * i + 2, p.header(P::kNx + l - 1)); ++ci)
            lo = std::min(lo, p.node(l - 1, ci, cj));
        ASSERT_EQ(p.node(l, i, j), lo) << l << ": " << i << ", " << j;
      }
}

INSTANTIATE_TEST_SUITE_P(Wraps, PackedField,
                         ::testing::Values(std::make_tuple(16, 16, Wrap::kRepeat, Wrap::kRepeat),
                                           std::make_tuple(13, 7, Wrap::kRepeat, Wrap::kMirror),
                                           std::make_tuple(9, 12, Wrap::kClamp, Wrap::kRepeat),
                                           std::make_tuple(5, 11, Wrap::kMirror, Wrap::kClamp),
                                           std::make_tuple(1, 6, Wrap::kClamp, Wrap::kClamp)));

TEST(PackedField, HeaderIsTheStd430LayoutOfExactGlsl) {
  // int hf_periodic[2], hf_size[2], hf_period[2], hf_cells[2], hf_num_levels,
  // hf_level_offset[16], hf_nx[16], hf_ny[16]; then float hf_data[] (checked against the driver's
  // offsets when the backend links the exact twin).
  EXPECT_EQ(P::kHeaderWords, 9 + 3 * kMaxFieldLevels);
  const Texture t = test_depth(4, 4);
  Result<P> p = pack_height_field(t, SamplerState{});
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p->header(P::kLevelOffset), 16);  // the 4x4 texels come first
  EXPECT_EQ(p->words.size(), P::kHeaderWords + 16u + 16u + 4u + 1u);
}

TEST(PackedField, TooManyLevelsIsAnError) {
  // 40000 texels per axis would need 17 levels.
  const std::vector<float> row(40000, 0.5f);
  const Texture t = Texture::from_floats(TexFormat::kR32F, 40000, 1, row.data());
  Result<P> p = pack_height_field(t, SamplerState{});
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("max-mip levels"), std::string::npos);
}

}  // namespace
}  // namespace relief::gl
