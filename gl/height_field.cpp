// Packs the max-mip of shaders_cpp/exact.cpp (Tevs, Ihrke and Seidel, "Maximum Mipmaps for Fast,
// Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008) for gl/shaders/exact.glsl.
#include "gl/height_field.h"

#include <algorithm>
#include <cstring>

namespace relief::gl {
namespace {

uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}

// exact.cpp make_axis: periodic unless clamped; mirror doubles the period.
struct AxisSpec {
  bool periodic;
  int size, period, cells;
};
AxisSpec make_axis(int size, Wrap wrap) {
  AxisSpec a;
  a.size = size;
  a.periodic = wrap != Wrap::kClamp;
  a.period = wrap == Wrap::kMirror ? 2 * size : size;
  a.cells = a.periodic ? a.period : std::max(size - 1, 1);
  return a;
}
int corner(const AxisSpec& a, int i) {
  return a.periodic ? (i + 1 == a.period ? 0 : i + 1) : std::min(i + 1, a.size - 1);
}

}  // namespace

float PackedHeightField::data(size_t i) const {
  float f;
  std::memcpy(&f, &words[kHeaderWords + i], sizeof(f));
  return f;
}
float PackedHeightField::texel(int i, int j) const {
  return data(static_cast<size_t>(j) * header(kPeriod) + i);
}
float PackedHeightField::node(int level, int i, int j) const {
  return data(static_cast<size_t>(header(kLevelOffset + level)) +
              static_cast<size_t>(j) * header(kNx + level) + i);
}

Result<PackedHeightField> pack_height_field(const Texture& depth, const SamplerState& sampler) {
  if (depth.empty()) return Status::error("exact: the depth texture is empty");
  const int w = depth.width(0), h = depth.height(0);
  const AxisSpec ax = make_axis(w, sampler.wrap_u), ay = make_axis(h, sampler.wrap_v);
  // levels: cells, then (n + 1) / 2 per axis down to 1 x 1
  std::vector<int> nx{ax.cells}, ny{ay.cells};
  while (nx.back() > 1 || ny.back() > 1) {
    nx.push_back((nx.back() + 1) / 2);
    ny.push_back((ny.back() + 1) / 2);
  }
  const int levels = static_cast<int>(nx.size());
  if (levels > kMaxFieldLevels)
    return Status::error("exact: a " + std::to_string(w) + "x" + std::to_string(h) +
                         " depth map needs " + std::to_string(levels) +
                         " max-mip levels, the GL twin holds " + std::to_string(kMaxFieldLevels));
  PackedHeightField p;
  std::vector<uint32_t>& out = p.words;
  out.assign(PackedHeightField::kHeaderWords, 0u);
  out[PackedHeightField::kPeriodic] = ax.periodic;
  out[PackedHeightField::kPeriodic + 1] = ay.periodic;
  out[PackedHeightField::kSize] = ax.size;
  out[PackedHeightField::kSize + 1] = ay.size;
  out[PackedHeightField::kPeriod] = ax.period;
  out[PackedHeightField::kPeriod + 1] = ay.period;
  out[PackedHeightField::kCells] = ax.cells;
  out[PackedHeightField::kCells + 1] = ay.cells;
  out[PackedHeightField::kNumLevels] = levels;
  // the expanded texels: mirror reads the source backwards in its second half
  auto src = [](int i, int size, int period) { return i < size ? i : period - 1 - i; };
  std::vector<float> tex(static_cast<size_t>(ax.period) * ay.period);
  for (int j = 0; j < ay.period; ++j)
    for (int i = 0; i < ax.period; ++i)
      tex[static_cast<size_t>(j) * ax.period + i] =
          depth.fetch_r(0, src(i, w, ax.period), src(j, h, ay.period));
  // leaves: min of each cell's four corners; above: min of 2x2 nodes
  std::vector<std::vector<float>> lv(levels);
  lv[0].resize(static_cast<size_t>(nx[0]) * ny[0]);
  auto texel = [&](int i, int j) { return tex[static_cast<size_t>(j) * ax.period + i]; };
  for (int j = 0; j < ny[0]; ++j)
    for (int i = 0; i < nx[0]; ++i) {
      const int i1 = corner(ax, i), j1 = corner(ay, j);
      lv[0][static_cast<size_t>(j) * nx[0] + i] =
          std::min(std::min(texel(i, j), texel(i1, j)), std::min(texel(i, j1), texel(i1, j1)));
    }
  for (int l = 1; l < levels; ++l) {
    lv[l].resize(static_cast<size_t>(nx[l]) * ny[l]);
    const std::vector<float>& fine = lv[l - 1];
    for (int j = 0; j < ny[l]; ++j)
      for (int i = 0; i < nx[l]; ++i) {
        float m = fine[static_cast<size_t>(2 * j) * nx[l - 1] + 2 * i];
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di) {
            const int fi = 2 * i + di, fj = 2 * j + dj;
            if (fi < nx[l - 1] && fj < ny[l - 1])
              m = std::min(m, fine[static_cast<size_t>(fj) * nx[l - 1] + fi]);
          }
        lv[l][static_cast<size_t>(j) * nx[l] + i] = m;
      }
  }
  size_t offset = tex.size();
  for (int l = 0; l < levels; ++l) {
    out[PackedHeightField::kLevelOffset + l] = static_cast<uint32_t>(offset);
    out[PackedHeightField::kNx + l] = nx[l];
    out[PackedHeightField::kNy + l] = ny[l];
    offset += lv[l].size();
  }
  out.reserve(out.size() + offset);
  for (float v : tex) out.push_back(float_bits(v));
  for (const std::vector<float>& level : lv)
    for (float v : level) out.push_back(float_bits(v));
  return p;
}

}  // namespace relief::gl
