// Tangent-space normal maps from depth maps by central differences (Policarpo, Oliveira, Comba
// 2005). Conventions in bake/normal_map.h.
#include "bake/normal_map.h"

#include <cmath>
#include <vector>

#include "base/check.h"

namespace relief {
namespace {

// Unit normals (x, y, z) per texel of level 0, row-major.
std::vector<float> depth_normals(const Texture& depth, float depth_scale, bool wrap,
                                 NormalConvention convention) {
  const float green = convention == NormalConvention::kGltf ? -1.0f : 1.0f;  // n_v to green
  CHECK(!depth.empty());
  const int w = depth.width(0);
  const int h = depth.height(0);
  std::vector<float> d(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) d[static_cast<size_t>(y) * w + x] = depth.fetch_r(0, x, y);
  auto at = [&](int x, int y) { return d[static_cast<size_t>(y) * w + x]; };
  // Neighbour index along one axis and the distance in texels it spans (0 for a 1-texel axis).
  auto neighbours = [wrap](int i, int n, int& lo, int& hi, float& span) {
    if (n == 1) {
      lo = hi = i;
      span = 0.0f;
      return;
    }
    if (wrap) {
      lo = (i + n - 1) % n;
      hi = (i + 1) % n;
      span = 2.0f;
      return;
    }
    lo = i > 0 ? i - 1 : i;
    hi = i < n - 1 ? i + 1 : i;
    span = static_cast<float>(hi - lo);
  };
  std::vector<float> out(static_cast<size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y) {
    int y0, y1;
    float sy;
    neighbours(y, h, y0, y1, sy);
    for (int x = 0; x < w; ++x) {
      int x0, x1;
      float sx;
      neighbours(x, w, x0, x1, sx);
      // Slopes in uv units: texel spacing is 1/w along u, 1/h along v.
      const float ddu = sx > 0.0f ? (at(x1, y) - at(x0, y)) * static_cast<float>(w) / sx : 0.0f;
      const float ddv = sy > 0.0f ? (at(x, y1) - at(x, y0)) * static_cast<float>(h) / sy : 0.0f;
      float nx = depth_scale * ddu, ny = depth_scale * ddv, nz = 1.0f;
      const float inv = 1.0f / std::sqrt(nx * nx + ny * ny + nz * nz);
      float* o = &out[(static_cast<size_t>(y) * w + x) * 3];
      o[0] = nx * inv;
      o[1] = green * ny * inv;
      o[2] = nz * inv;
    }
  }
  return out;
}

Texture pack(const Texture& depth, const std::vector<float>& n, TexFormat format, bool encode) {
  const int w = depth.width(0);
  const int h = depth.height(0);
  std::vector<float> rgba(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < static_cast<size_t>(w) * h; ++i) {
    for (int c = 0; c < 3; ++c)
      rgba[i * 4 + c] = encode ? n[i * 3 + c] * 0.5f + 0.5f : n[i * 3 + c];
    rgba[i * 4 + 3] = 1.0f;
  }
  Texture t = Texture::from_floats(format, w, h, rgba.data(), ColorSpace::kLinear);
  t.generate_mips(MipReduce::kAverage);
  return t;
}

}  // namespace

Texture normal_map_from_depth(const Texture& depth, float depth_scale, bool wrap,
                              NormalConvention convention) {
  return pack(depth, depth_normals(depth, depth_scale, wrap, convention), TexFormat::kRGBA8, true);
}

Texture normal_map_from_depth_float(const Texture& depth, float depth_scale, bool wrap,
                                    NormalConvention convention) {
  return pack(depth, depth_normals(depth, depth_scale, wrap, convention), TexFormat::kRGBA16F,
              false);
}

}  // namespace relief
