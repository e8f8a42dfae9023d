// Coverage masks of rendered frames and their comparison near the outline, shared by the
// silhouette tests (tests/frames/silhouette_test.cpp, impostor_test.cpp).
#pragma once

#include <algorithm>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/render.h"
#include "tests/frames/cpu_frame.h"

namespace relief::test {

// One flag per pixel, row by row.
struct Mask {
  int width = 0, height = 0;
  std::vector<char> on;
  bool at(int x, int y) const { return on[static_cast<size_t>(y) * width + x] != 0; }
  int count() const { return static_cast<int>(std::count(on.begin(), on.end(), 1)); }
};

// Covered pixels: the reversed-z depth buffer was written (the clear value is 0).
inline Mask coverage(const Framebuffer& fb) {
  Mask m{fb.depth.width, fb.depth.height, {}};
  m.on.resize(fb.depth.values.size());
  for (size_t i = 0; i < m.on.size(); ++i) m.on[i] = fb.depth.values[i] != 0.0f ? 1 : 0;
  return m;
}

// Pixels whose 4-neighbourhood (inside the image) is not all of one value in `m`.
inline bool boundary_pixel(const Mask& m, int x, int y) {
  const bool v = m.at(x, y);
  const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (int k = 0; k < 4; ++k) {
    const int nx = x + dx[k], ny = y + dy[k];
    if (nx >= 0 && ny >= 0 && nx < m.width && ny < m.height && m.at(nx, ny) != v) return true;
  }
  return false;
}

// The silhouette band: pixels within `radius` pixels (Chebyshev distance) of a boundary pixel of
// either mask.
inline Mask silhouette_band(const Mask& a, const Mask& b, int radius) {
  Mask band;
  band.width = a.width;
  band.height = a.height;
  band.on.assign(a.on.size(), 0);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      if (!boundary_pixel(a, x, y) && !boundary_pixel(b, x, y)) continue;
      for (int j = std::max(0, y - radius); j <= std::min(a.height - 1, y + radius); ++j)
        for (int i = std::max(0, x - radius); i <= std::min(a.width - 1, x + radius); ++i)
          band.on[static_cast<size_t>(j) * a.width + i] = 1;
    }
  return band;
}

// How two coverage masks differ: every differing pixel (wherever it lies) over the number of
// silhouette-band pixels.
struct MaskDiff {
  int differing = 0;  // pixels covered in one mask only
  int band = 0;       // silhouette band size
  double ratio() const { return band > 0 ? static_cast<double>(differing) / band : 0.0; }
};

// The coverage of `scene` rendered on the CPU at width x height with `technique` (empty: the
// scene's own), shadow maps off; an empty mask (and a test failure) when planning or rendering
// fails.
inline Mask render_coverage(const Scene& scene, const std::string& technique, int width,
                            int height) {
  RenderOptions opt = cpu_options(width, height, technique);
  opt.shadows = false;
  const std::optional<Framebuffer> fb = render_frame(scene, opt);
  return fb ? coverage(*fb) : Mask{};
}

inline MaskDiff compare_masks(const Mask& a, const Mask& b, int radius = 2) {
  MaskDiff d;
  d.band = silhouette_band(a, b, radius).count();
  for (size_t i = 0; i < a.on.size(); ++i) d.differing += a.on[i] != b.on[i] ? 1 : 0;
  return d;
}

}  // namespace relief::test
