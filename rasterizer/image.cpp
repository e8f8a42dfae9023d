#include "rasterizer/image.h"

#include <algorithm>

namespace relief {

Framebuffer::Framebuffer(int w, int h, AovMask aovs)
    : width(w), height(h), color(w, h), depth(w, h), aov_mask(aovs) {
  if (aov_mask != 0) aov.assign(static_cast<size_t>(w) * h * kAovTotalChannels, 0.0f);
}

void Framebuffer::clear(glm::vec4 color_value, float depth_value) {
  std::fill(color.pixels.begin(), color.pixels.end(), color_value);
  std::fill(depth.values.begin(), depth.values.end(), depth_value);
  std::fill(aov.begin(), aov.end(), 0.0f);
}

Image Framebuffer::aov_image(Aov which) const {
  Image out(width, height, glm::vec4(0, 0, 0, 1));
  if (aov.empty()) return out;
  const int idx = static_cast<int>(which);
  const int off = kAovOffset[idx];
  const int n = kAovChannels[idx];
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float* a = aov_at(x, y);
      glm::vec4& p = out.at(x, y);
      for (int c = 0; c < n; ++c) p[c] = a[off + c];
    }
  return out;
}

}  // namespace relief
