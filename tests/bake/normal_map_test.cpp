#include "bake/normal_map.h"

#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace relief {
namespace {

constexpr float kPi = 3.14159265358979f;

// R32F depth map from d(u, v) sampled at texel centres.
Texture depth_from(int w, int h, const std::function<float(float, float)>& d) {
  std::vector<float> v(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) v[y * w + x] = d((x + 0.5f) / w, (y + 0.5f) / h);
  return Texture::from_floats(TexFormat::kR32F, w, h, v.data());
}

glm::vec3 decode8(const Texture& t, int x, int y) {
  glm::vec4 c = t.fetch(0, x, y);
  return glm::vec3(c) * 2.0f - 1.0f;
}

TEST(NormalMap, RampIsConstantEverywhereWithClamp) {
  // d = 0.3 u + 0.6 v: a plane tilting down along +u and +v; with clamp the one-sided border
  // differences are exact too, so every texel has the same normal. glTF convention: green is the
  // component toward the image top (-v).
  const float s = 0.25f;
  Texture depth = depth_from(40, 24, [](float u, float v) { return 0.3f * u + 0.6f * v; });
  const glm::vec3 want = glm::normalize(glm::vec3(s * 0.3f, -s * 0.6f, 1.0f));
  Texture nf = normal_map_from_depth_float(depth, s, /*wrap=*/false);
  Texture n8 = normal_map_from_depth(depth, s, /*wrap=*/false);
  ASSERT_EQ(n8.format(), TexFormat::kRGBA8);
  ASSERT_EQ(nf.format(), TexFormat::kRGBA16F);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 40; ++x) {
      glm::vec4 f = nf.fetch(0, x, y);
      EXPECT_NEAR(f.x, want.x, 2e-3f) << x << "," << y;
      EXPECT_NEAR(f.y, want.y, 2e-3f) << x << "," << y;
      EXPECT_NEAR(f.z, want.z, 2e-3f) << x << "," << y;
      EXPECT_EQ(f.w, 1.0f);
      glm::vec3 e = decode8(n8, x, y);
      EXPECT_NEAR(e.x, want.x, 1.5f / 255.0f);
      EXPECT_NEAR(e.y, want.y, 1.5f / 255.0f);
      EXPECT_NEAR(e.z, want.z, 1.5f / 255.0f);
      EXPECT_EQ(n8.fetch(0, x, y).w, 1.0f);
    }
}

TEST(NormalMap, SignsFollowTangentFrame) {
  // Depth growing along +u means the surface falls away along +u: the normal leans towards +u.
  Texture du = depth_from(16, 16, [](float u, float) { return u; });
  Texture dv = depth_from(16, 16, [](float, float v) { return 1.0f - v; });
  glm::vec4 a = normal_map_from_depth_float(du, 1.0f, false).fetch(0, 8, 8);
  glm::vec4 b = normal_map_from_depth_float(dv, 1.0f, false).fetch(0, 8, 8);
  EXPECT_GT(a.x, 0.5f);
  EXPECT_NEAR(a.y, 0.0f, 1e-6f);
  EXPECT_NEAR(b.x, 0.0f, 1e-6f);
  EXPECT_GT(b.y, 0.5f);  // leans towards -v, the image top: glTF's green is +
  EXPECT_LT(
      normal_map_from_depth_float(dv, 1.0f, false, NormalConvention::kDirectX).fetch(0, 8, 8).y,
      -0.5f);
  EXPECT_GT(a.z, 0.0f);
  EXPECT_GT(b.z, 0.0f);
}

TEST(NormalMap, ParaboloidMatchesAnalyticGradient) {
  // d = c ((u - 0.5)^2 + (v - 0.5)^2): central differences are exact for a quadratic, so interior
  // texels match the analytic gradient 2c (u - 0.5), 2c (v - 0.5).
  const int w = 64, h = 48;
  const float c = 1.6f, s = 0.1f;
  auto d = [c](float u, float v) {
    return c * ((u - 0.5f) * (u - 0.5f) + (v - 0.5f) * (v - 0.5f));
  };
  Texture nf = normal_map_from_depth_float(depth_from(w, h, d), s, false);
  for (int y = 1; y < h - 1; ++y)
    for (int x = 1; x < w - 1; ++x) {
      const float u = (x + 0.5f) / w, v = (y + 0.5f) / h;
      glm::vec3 want =
          glm::normalize(glm::vec3(s * 2 * c * (u - 0.5f), -s * 2 * c * (v - 0.5f), 1));
      glm::vec4 f = nf.fetch(0, x, y);
      EXPECT_NEAR(f.x, want.x, 2e-3f) << x << "," << y;
      EXPECT_NEAR(f.y, want.y, 2e-3f) << x << "," << y;
      EXPECT_NEAR(f.z, want.z, 2e-3f) << x << "," << y;
    }
  // Symmetry: mirrored texels have mirrored x.
  EXPECT_NEAR(nf.fetch(0, 3, 20).x, -nf.fetch(0, w - 4, 20).x, 1e-3f);
}

TEST(NormalMap, WrapUsesOppositeBorder) {
  // A periodic sinusoid along u: with wrap, the border texels use the same central difference as
  // the interior; with clamp they are one-sided.
  const int w = 32, h = 4;
  auto d = [](float u, float) { return 0.5f + 0.5f * std::sin(2 * kPi * u); };
  Texture depth = depth_from(w, h, d);
  Texture wrap = normal_map_from_depth_float(depth, 0.2f, true);
  Texture clamp = normal_map_from_depth_float(depth, 0.2f, false);
  for (int x = 0; x < w; ++x) {
    const float up = d((((x + 1) % w) + 0.5f) / w, 0), dn = d((((x + w - 1) % w) + 0.5f) / w, 0);
    const float ddu = (up - dn) * w / 2.0f;
    glm::vec3 want = glm::normalize(glm::vec3(0.2f * ddu, 0.0f, 1.0f));
    EXPECT_NEAR(wrap.fetch(0, x, 0).x, want.x, 2e-3f) << x;
    EXPECT_NEAR(wrap.fetch(0, x, 0).z, want.z, 2e-3f) << x;
    EXPECT_NEAR(wrap.fetch(0, x, 0).y, 0.0f, 1e-6f);
  }
  const float one_sided = (d(1.5f / w, 0) - d(0.5f / w, 0)) * w;
  EXPECT_NEAR(clamp.fetch(0, 0, 0).x, glm::normalize(glm::vec3(0.2f * one_sided, 0, 1)).x, 2e-3f);
}

TEST(NormalMap, FullMipChainAveraged) {
  Texture depth = depth_from(64, 16, [](float u, float v) { return 0.5f * u * v; });
  Texture n8 = normal_map_from_depth(depth, 0.3f, false);
  ASSERT_EQ(n8.levels(), 7);  // 64x16 ... 1x1
  EXPECT_EQ(n8.width(6), 1);
  EXPECT_EQ(n8.height(6), 1);
  // Level 1 texel is the average of its 2x2 block (within 8-bit rounding).
  glm::vec4 avg =
      (n8.fetch(0, 10, 6) + n8.fetch(0, 11, 6) + n8.fetch(0, 10, 7) + n8.fetch(0, 11, 7)) / 4.0f;
  glm::vec4 m = n8.fetch(1, 5, 3);
  for (int c = 0; c < 4; ++c) EXPECT_NEAR(m[c], avg[c], 1.01f / 255.0f);
}

TEST(NormalMap, FlatAndOneTexelMaps) {
  Texture flat = depth_from(8, 8, [](float, float) { return 0.7f; });
  glm::vec3 n = decode8(normal_map_from_depth(flat, 5.0f, true), 3, 3);
  // 8-bit quantisation: half a step of 2/255 in decoded units.
  EXPECT_NEAR(n.x, 0, 1.001f / 255);
  EXPECT_NEAR(n.y, 0, 1.001f / 255);
  EXPECT_NEAR(n.z, 1, 1.001f / 255);
  Texture line = depth_from(1, 5, [](float, float v) { return v; });
  glm::vec4 f = normal_map_from_depth_float(line, 1.0f, false).fetch(0, 0, 2);
  EXPECT_EQ(f.x, 0.0f);  // one texel wide: no slope along u
  // d = v over 5 texels: dd/dv = 1, n = normalize(0, 1, 1) in (u, v, n); green is -n_v (glTF).
  EXPECT_NEAR(f.y, -std::sqrt(0.5f), 2e-3f);
  EXPECT_NEAR(f.z, std::sqrt(0.5f), 2e-3f);
}

TEST(NormalMap, DirectXConventionFlipsGreenOnly) {
  Texture depth = depth_from(12, 10, [](float u, float v) { return 0.5f * u * u + 0.7f * v * u; });
  const Texture gl = normal_map_from_depth(depth, 0.3f, true);
  const Texture dx = normal_map_from_depth(depth, 0.3f, true, NormalConvention::kDirectX);
  const Texture glf = normal_map_from_depth_float(depth, 0.3f, true);
  const Texture dxf = normal_map_from_depth_float(depth, 0.3f, true, NormalConvention::kDirectX);
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 12; ++x) {
      const glm::vec3 a = decode8(gl, x, y), b = decode8(dx, x, y);
      EXPECT_NEAR(a.x, b.x, 1e-6f);
      EXPECT_NEAR(a.y, -b.y, 1.5f / 255.0f);
      EXPECT_NEAR(a.z, b.z, 1e-6f);
      EXPECT_EQ(glf.fetch(0, x, y).y, -dxf.fetch(0, x, y).y);
    }
}

}  // namespace
}  // namespace relief
