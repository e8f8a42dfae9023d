// Clipping for the rasterizer's setup (rasterizer/clip_internal.h).
#include "rasterizer/clip_internal.h"

namespace relief::raster_detail {
namespace {

// Signed distance to clip plane p (>= 0 inside).
float plane_distance(int p, const glm::vec4& c, float gx, float gy) {
  switch (p) {
    case 0:
      return c.w - c.z;  // near
    case 1:
      return c.z;  // far
    case 2:
      return c.x + gx * c.w;  // guard left
    case 3:
      return gx * c.w - c.x;  // guard right
    case 4:
      return gy * c.w - c.y;  // guard top
    default:
      return c.y + gy * c.w;  // guard bottom
  }
}

}  // namespace

uint32_t clip_outcode(const glm::vec4& c, float gx, float gy) {
  uint32_t o = 0;
  if (c.z > c.w) o |= kOutNear;
  if (c.z < 0.0f) o |= kOutFar;
  if (c.x < -gx * c.w) o |= kOutGuardL;
  if (c.x > gx * c.w) o |= kOutGuardR;
  if (c.y > gy * c.w) o |= kOutGuardT;
  if (c.y < -gy * c.w) o |= kOutGuardB;
  if (c.x < -c.w) o |= kOutViewL;
  if (c.x > c.w) o |= kOutViewR;
  if (c.y > c.w) o |= kOutViewT;
  if (c.y < -c.w) o |= kOutViewB;
  return o;
}

void clip_triangle(const ClipVertex in[3], int nv, uint32_t planes, float gx, float gy,
                   std::vector<float>& clip_arena, ClipPolygon& a) {
  ClipPolygon b;
  for (int i = 0; i < 3; ++i) {
    a.c[i] = in[i].clip;
    a.arena[i] = static_cast<int>(clip_arena.size());
    clip_arena.insert(clip_arena.end(), in[i].vary, in[i].vary + nv);
  }
  a.n = 3;
  for (int p = 0; p < 6 && a.n >= 3; ++p) {
    if (!(planes & (1u << p))) continue;
    b.n = 0;
    for (int i = 0; i < a.n; ++i) {
      const int j = (i + 1) % a.n;
      const float di = plane_distance(p, a.c[i], gx, gy);
      const float dj = plane_distance(p, a.c[j], gx, gy);
      if (di >= 0.0f) {
        b.c[b.n] = a.c[i];
        b.arena[b.n++] = a.arena[i];
      }
      if ((di >= 0.0f) != (dj >= 0.0f)) {
        const float t = di / (di - dj);
        b.c[b.n] = a.c[i] + (a.c[j] - a.c[i]) * t;
        const int off = static_cast<int>(clip_arena.size());
        clip_arena.resize(clip_arena.size() + nv);
        for (int k = 0; k < nv; ++k) {
          const float vi = clip_arena[a.arena[i] + k], vj = clip_arena[a.arena[j] + k];
          clip_arena[off + k] = vi + (vj - vi) * t;
        }
        b.arena[b.n++] = off;
      }
    }
    a = b;
  }
}

}  // namespace relief::raster_detail
