// Images and the framebuffer. Pixel (0, 0) is the top-left pixel of the output file; rows run
// top to bottom. Colour is linear float RGBA. Depth is float32 reversed-Z: 1 at the near plane,
// 0 at the far plane and for the cleared background; a larger value is closer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

namespace relief {

struct Image {
  int width = 0;
  int height = 0;
  std::vector<glm::vec4> pixels;  // row-major, width * height

  Image() = default;
  Image(int w, int h, glm::vec4 fill = glm::vec4(0.0f))
      : width(w), height(h), pixels(static_cast<size_t>(w) * h, fill) {}
  glm::vec4& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  const glm::vec4& at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
};

// A single-channel float plane (depth, steps, ...).
struct Plane {
  int width = 0;
  int height = 0;
  std::vector<float> values;

  Plane() = default;
  Plane(int w, int h, float fill = 0.0f)
      : width(w), height(h), values(static_cast<size_t>(w) * h, fill) {}
  float& at(int x, int y) { return values[static_cast<size_t>(y) * width + x]; }
  float at(int x, int y) const { return values[static_cast<size_t>(y) * width + x]; }
};

// Arbitrary output variables a fragment shader can write beside colour.
enum class Aov : uint8_t { kHitUv = 0, kHitDepth, kSteps, kNormal, kCount };
inline constexpr int kAovCount = static_cast<int>(Aov::kCount);
// Channels per AOV: uv 2, hit depth 1, steps 1, normal 3.
inline constexpr int kAovChannels[kAovCount] = {2, 1, 1, 3};
inline constexpr int kAovOffset[kAovCount] = {0, 2, 3, 4};
inline constexpr int kAovTotalChannels = 7;
inline constexpr const char* kAovNames[kAovCount] = {"uv", "hit_depth", "steps", "normal"};

using AovMask = uint32_t;
inline constexpr AovMask aov_bit(Aov a) {
  return 1u << static_cast<int>(a);
}

// The render target of one pass: colour, depth and the requested AOVs (stored as channels in
// `aov`, kAovTotalChannels per pixel, only when aov_mask is non-zero).
struct Framebuffer {
  int width = 0;
  int height = 0;
  Image color;
  Plane depth;
  AovMask aov_mask = 0;
  std::vector<float> aov;  // width * height * kAovTotalChannels, when aov_mask != 0

  Framebuffer() = default;
  Framebuffer(int w, int h, AovMask aovs = 0);
  void clear(glm::vec4 color_value, float depth_value = 0.0f);
  float* aov_at(int x, int y) {
    return &aov[(static_cast<size_t>(y) * width + x) * kAovTotalChannels];
  }
  const float* aov_at(int x, int y) const {
    return &aov[(static_cast<size_t>(y) * width + x) * kAovTotalChannels];
  }
  // Extracts one AOV as an image (channels beyond those of the AOV are 0, alpha 1).
  Image aov_image(Aov which) const;
};

}  // namespace relief
