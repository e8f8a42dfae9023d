// Clipping for the rasterizer's setup (internal to rasterizer/, not installed): outcodes against
// the clip volume and the guard band, and Sutherland-Hodgman in homogeneous space. Plain scalar
// code; rasterizer/setup.cpp calls it.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

namespace relief::raster_detail {

// A vertex after clipping: clip position and varyings, stored by the draw's vertex arena.
struct ClipVertex {
  glm::vec4 clip;
  const float* vary;
};

// Outcode bits against the clip volume (near, far) and the guard band.
enum : uint32_t {
  kOutNear = 1,
  kOutFar = 2,
  kOutGuardL = 4,
  kOutGuardR = 8,
  kOutGuardT = 16,
  kOutGuardB = 32,
  kOutViewL = 64,
  kOutViewR = 128,
  kOutViewT = 256,
  kOutViewB = 512,
};
constexpr uint32_t kNeedsClip =
    kOutNear | kOutFar | kOutGuardL | kOutGuardR | kOutGuardT | kOutGuardB;

inline bool finite4(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// The outcode of clip position `c` with the guard band gx, gy (NDC units).
uint32_t clip_outcode(const glm::vec4& c, float gx, float gy);

// A clipped polygon: clip positions and the offsets of their varyings in the clip arena.
struct ClipPolygon {
  glm::vec4 c[9];
  int arena[9];
  int n = 0;
};

// Sutherland-Hodgman in homogeneous space: triangle `in` against the planes in `planes` (bit p:
// near, far, guard left, right, top, bottom for p = 0..5), with the guard band gx, gy; the
// vertices' varyings (nv each) are appended to `clip_arena`, new ones interpolated there.
void clip_triangle(const ClipVertex in[3], int nv, uint32_t planes, float gx, float gy,
                   std::vector<float>& clip_arena, ClipPolygon& a);

}  // namespace relief::raster_detail
