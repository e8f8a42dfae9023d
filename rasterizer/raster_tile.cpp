// The rasterizer's tile traversal (rasterizer/raster_tile.h), compiled once per SIMD target
// (base/simd.h): coverage from the exact edge functions, depth and varyings from the float
// planes eight lanes (two quads) at a time, the early depth test, packets to the draw's shader,
// and the per-fragment depth test, blend and writes of what the shader returns. Every target does
// the same IEEE operations, so the frame is the same bits on each.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "rasterizer/raster_tile.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rasterizer/raster_tile.h"

#include <hwy/highway.h>
#if HWY_ARCH_X86
#include <immintrin.h>  // _mm_stream_ps, _mm_sfence (SSE: every x86-64 target)
#endif

#include "base/simd_flatten.h"

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace raster_detail {
namespace HWY_NAMESPACE {
namespace {

typedef float vf __attribute__((vector_size(32)));
typedef int32_t vi __attribute__((vector_size(32)));
typedef float vf4 __attribute__((vector_size(16)));
typedef int32_t vi4 __attribute__((vector_size(16)));

// Where a tile's fragments land: pixel (x, y) is element (y - y0) * stride + (x - x0) of each
// plane. Either the framebuffer's own planes (origin 0, 0, stride its width) or the worker's
// tile-sized copies, which raster_tile fills before the tile's triangles (cleared, or copied from
// the framebuffer) and streams back after them: drawn there, a tile's pixels stay in the core's
// cache from clear to last write, and the framebuffer's lines are written once without being
// read first.
struct TilePixels {
  glm::vec4* color = nullptr;  // null: the target has no colour
  float* depth = nullptr;
  size_t stride = 0;
  int x0 = 0, y0 = 0;
  size_t index(int x, int y) const {
    return static_cast<size_t>(y - y0) * stride + static_cast<size_t>(x - x0);
  }
  float& depth_at(int x, int y) const { return depth[index(x, y)]; }
  glm::vec4& color_at(int x, int y) const { return color[index(x, y)]; }
};

// Channel c's four lanes of quad q of the shader's output, NaN and infinities read as 0 (the
// scalar write-out's std::isfinite test: exponent bits all ones).
vf4 quad_channel(const FragmentOutput& o, int c, int q) {
  vi4 bits;
  std::memcpy(&bits, &o.color[c][q * 4], sizeof bits);
  const vi4 finite = (bits & 0x7f800000) != 0x7f800000;
  return reinterpret_cast<vf4>(bits & finite);
}

// Writes quad q, every lane covered and kept, of a draw that tests depth before shading and
// writes colour without blending or AOVs: the values of the per-lane loop below (the same
// floats), as two 32-byte rows of colour and two 8-byte rows of depth.
void write_full_quad(const FragmentPacket& p, const FragmentOutput& o, const Worker& w,
                     const TilePixels& px, const DrawCall& dc, int q) {
  const int x = w.qx[q], y = w.qy[q];
  if (dc.depth_write) {
    std::memcpy(&px.depth_at(x, y), &p.frag_z[q * 4], 2 * sizeof(float));
    std::memcpy(&px.depth_at(x, y + 1), &p.frag_z[q * 4 + 2], 2 * sizeof(float));
  }
  // Lanes (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1) from channel-major to pixel-major.
  const vf4 r = quad_channel(o, 0, q), g = quad_channel(o, 1, q);
  const vf4 b = quad_channel(o, 2, q), a = quad_channel(o, 3, q);
  const vf4 rg01 = __builtin_shufflevector(r, g, 0, 4, 1, 5);
  const vf4 ba01 = __builtin_shufflevector(b, a, 0, 4, 1, 5);
  const vf4 rg23 = __builtin_shufflevector(r, g, 2, 6, 3, 7);
  const vf4 ba23 = __builtin_shufflevector(b, a, 2, 6, 3, 7);
  // Each row's two pixels joined in registers: stored to a stack array as 16-byte halves and
  // reloaded as one 32-byte row, they stalled on store forwarding (measured: the write-out's
  // hottest instructions).
  const vf4 p0 = __builtin_shufflevector(rg01, ba01, 0, 1, 4, 5);
  const vf4 p1 = __builtin_shufflevector(rg01, ba01, 2, 3, 6, 7);
  const vf4 p2 = __builtin_shufflevector(rg23, ba23, 0, 1, 4, 5);
  const vf4 p3 = __builtin_shufflevector(rg23, ba23, 2, 3, 6, 7);
  const vf top = __builtin_shufflevector(p0, p1, 0, 1, 2, 3, 4, 5, 6, 7);
  const vf bottom = __builtin_shufflevector(p2, p3, 0, 1, 2, 3, 4, 5, 6, 7);
  std::memcpy(&px.color_at(x, y), &top, sizeof(vf));
  std::memcpy(&px.color_at(x, y + 1), &bottom, sizeof(vf));
}

void flush(Worker& w, const TilePixels& px, Framebuffer& fb, const DrawCall& dc) {
  FragmentPacket& p = w.packet;
  if (p.num_quads == 0) return;
  FragmentOutput& o = w.out;
  std::memset(o.discard, 0, sizeof(o.discard));
  dc.shader(dc.user, p, o, w.counters);
  w.quads += p.num_quads;
  const bool write_aov = dc.aov_write && fb.aov_mask != 0;
  const bool plain =
      dc.depth_test == DepthTest::kEarly && dc.color_write && !dc.blend && !write_aov;
  for (int q = 0; q < p.num_quads; ++q) {
    const uint8_t live = p.coverage[q] & ~o.discard[q];
    if (plain && live == 0xf) {
      w.counters.fragments += 4;
      write_full_quad(p, o, w, px, dc, q);
      continue;
    }
    for (int l = 0; l < 4; ++l) {
      if (!((p.coverage[q] >> l) & 1)) continue;
      ++w.counters.fragments;
      if (!((live >> l) & 1)) {
        ++w.counters.discarded;
        continue;
      }
      const int lane = q * 4 + l;
      const int x = w.qx[q] + (l & 1), y = w.qy[q] + (l >> 1);
      float& stored = px.depth_at(x, y);
      float z = p.frag_z[lane];
      if (dc.depth_test != DepthTest::kEarly) {
        z = o.depth[lane];
        if (!(z == z)) {  // NaN depth: the fragment is dropped
          ++w.counters.discarded;
          continue;
        }
        z = std::clamp(z, 0.0f, 1.0f);
        if (!(z > stored)) continue;
      }
      if (dc.depth_write) stored = z;
      if (dc.color_write) {
        glm::vec4 c(o.color[0][lane], o.color[1][lane], o.color[2][lane], o.color[3][lane]);
        for (int k = 0; k < 4; ++k)
          if (!std::isfinite(c[k])) c[k] = 0.0f;
        glm::vec4& dst = px.color_at(x, y);
        if (dc.blend) {
          const float a = std::clamp(c.a, 0.0f, 1.0f), keep = 1.0f - a;
          dst = glm::vec4(c.r * a + dst.r * keep, c.g * a + dst.g * keep, c.b * a + dst.b * keep,
                          a + dst.a * keep);
        } else {
          dst = c;
        }
      }
      if (write_aov) {
        float* a = fb.aov_at(x, y);
        for (int k = 0; k < kAovTotalChannels; ++k) {
          const float v = o.aov[k][lane];
          a[k] = std::isfinite(v) ? v : 0.0f;
        }
      }
    }
  }
  p.num_quads = 0;
}

// Bit l set where lane l of the comparison result m (all ones or zero) is set.
unsigned lane_bits(vi m) {
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  return static_cast<unsigned>(_mm256_movemask_ps(reinterpret_cast<__m256>(m)));
#else
  unsigned bits = 0;
  for (int l = 0; l < 8; ++l) bits |= static_cast<unsigned>(m[l] & 1) << l;
  return bits;
#endif
}

// Coverage of the quad whose top-left pixel has edge values e[k]: bit l set when lane l is
// inside all three edges (top-left rule through the bias).
uint8_t quad_mask(const SetupTriangle& t, const int64_t e[3]) {
  uint32_t out = 0;
  for (int k = 0; k < 3; ++k) {
    const int64_t v = e[k] + t.bias[k], da = t.a[k] * kSubOne, db = t.b[k] * kSubOne;
    out |= uint32_t(v < 0) | uint32_t(v + da < 0) << 1 | uint32_t(v + db < 0) << 2 |
           uint32_t(v + da + db < 0) << 3;
  }
  return static_cast<uint8_t>(~out & 0xf);
}

// Walks the part of triangle t inside the tile [tx0, tx1] x [ty0, ty1], two quads (8 lanes) at
// a time: coverage from the exact edge functions (skipped when the whole rectangle is inside),
// depth and varyings from the float planes, early depth test, packets of up to 16 quads.
void raster_triangle(const float* planes, Worker& w, const TilePixels& px, Framebuffer& fb,
                     const DrawCall& dc, const SetupTriangle& t, int tx0, int ty0, int tx1,
                     int ty1) {
  const int nv = dc.num_varyings;
  FragmentPacket& p = w.packet;
  p.num_quads = 0;
  p.num_varyings = nv;
  p.front_facing = t.front_facing;
  const int x0 = std::max(t.x0, tx0) & ~1, y0 = std::max(t.y0, ty0) & ~1;
  const int x1 = std::min(t.x1, tx1), y1 = std::min(t.y1, ty1);
  if (x0 > x1 || y0 > y1) return;
  // The pixel rectangle is inside every edge when its four corner pixels are; outside when all
  // four are outside one edge.
  bool inside = true;
  for (int k = 0; k < 3; ++k) {
    int outside = 0;
    for (int c = 0; c < 4; ++c) {
      const int64_t px = int64_t(c & 1 ? x1 : x0) * kSubOne + kHalf;
      const int64_t py = int64_t(c & 2 ? y1 : y0) * kSubOne + kHalf;
      outside += t.a[k] * px + t.b[k] * py + t.c[k] + t.bias[k] < 0;
    }
    if (outside == 4) return;
    inside &= outside == 0;
  }
  const bool early = dc.depth_test != DepthTest::kLate;
  const float* pl = planes + t.plane;
  const vf kDx = {0, 1, 0, 1, 2, 3, 2, 3}, kDy = {0, 0, 1, 1, 0, 0, 1, 1};
  const vi kHigh = {4, 5, 6, 7, 4, 5, 6, 7};
  for (int qy = y0; qy <= y1; qy += 2) {
    const uint8_t rowm = qy + 1 <= y1 ? 0xf : 0x3;
    int64_t erow[3];
    for (int k = 0; k < 3; ++k)
      erow[k] = t.a[k] * (int64_t(x0) * kSubOne + kHalf) +
                t.b[k] * (int64_t(qy) * kSubOne + kHalf) + t.c[k];
    const vf fy = static_cast<float>(qy - t.y0) + kDy;
    for (int qx = x0; qx <= x1; qx += 4) {
      const bool has_b = qx + 2 <= x1;
      uint8_t m0 = rowm & (qx + 1 <= x1 ? 0xf : 0x5);
      uint8_t m1 = has_b ? rowm & (qx + 3 <= x1 ? 0xf : 0x5) : 0;
      if (!inside) {
        int64_t e[3];
        for (int k = 0; k < 3; ++k) e[k] = erow[k] + t.a[k] * int64_t(qx - x0) * kSubOne;
        m0 &= quad_mask(t, e);
        if (has_b) {
          for (int k = 0; k < 3; ++k) e[k] += t.a[k] * 2 * kSubOne;
          m1 &= quad_mask(t, e);
        }
        if (!(m0 | m1)) continue;
      }
      const vf fx = static_cast<float>(qx - t.x0) + kDx;
      vf z = (pl[0] + pl[1] * fx) + pl[2] * fy;
      z = z < 0.0f ? 0.0f : z;
      z = z > 1.0f ? 1.0f : z;
      if (early) {
        const float* r0 = &px.depth_at(qx, qy);
        const float* r1 = r0 + px.stride;
        vf d;
        // Only pixels of this tile (x1, y1 are clipped to it): a quad pair may reach past the
        // tile's edge into pixels another thread is clearing or writing (ThreadSanitizer found
        // it); those lanes are masked off, so what they read does not matter.
        if (qx + 3 <= x1 && qy + 1 <= y1) {
          vf4 top, bottom;
          std::memcpy(&top, r0, sizeof top);
          std::memcpy(&bottom, r1, sizeof bottom);
          d = __builtin_shufflevector(top, bottom, 0, 1, 4, 5, 2, 3, 6, 7);
        } else {
          for (int l = 0; l < 8; ++l) {
            const int x = qx + (l & 1) + (l >> 2) * 2, y = qy + ((l >> 1) & 1);
            d[l] = x <= x1 && y <= y1 ? px.depth_at(x, y) : 1.0f;
          }
        }
        const unsigned bits = lane_bits(z > d);
        m0 &= bits & 0xf;
        m1 &= bits >> 4;
        if (!(m0 | m1)) continue;
      }
      vf iw = (pl[3] + pl[4] * fx) + pl[5] * fy;
      iw = iw < 1e-30f ? 1e-30f : iw;  // helper lanes far outside may pass the horizon
      const vf wv = 1.0f / iw;
      if (p.num_quads > kPacketQuads - 2) flush(w, px, fb, dc);
      const int q = p.num_quads;
      const bool shift = m0 == 0;  // only the right quad: move lanes 4..7 down
      const size_t lane0 = size_t(q) * 4;
      auto put = [&](float* dst, vf v) {
        if (shift) v = __builtin_shuffle(v, kHigh);
        std::memcpy(dst + lane0, &v, sizeof v);
      };
      put(p.frag_x, static_cast<float>(qx) + 0.5f + kDx);
      put(p.frag_y, static_cast<float>(qy) + 0.5f + kDy);
      put(p.frag_z, z);
      put(p.inv_w, iw);
      for (int k = 0; k < nv; ++k) {
        const float* c = pl + 3 * (kPlaneVary + k);
        put(p.varyings[k], ((c[0] + c[1] * fx) + c[2] * fy) * wv);
      }
      if (m0) {
        p.coverage[q] = m0;
        w.qx[q] = static_cast<int16_t>(qx);
        w.qy[q] = static_cast<int16_t>(qy);
      }
      if (m1) {
        const int q1 = m0 ? q + 1 : q;
        p.coverage[q1] = m1;
        w.qx[q1] = static_cast<int16_t>(qx + 2);
        w.qy[q1] = static_cast<int16_t>(qy);
      }
      p.num_quads += (m0 != 0) + (m1 != 0);
    }
  }
  flush(w, px, fb, dc);
}

// Copies n floats from src to dst through non-temporal stores where the target has them: the
// lines go to memory without being read into the cache first (a write-back of a finished tile,
// which nothing reads again in this draw).
void stream_floats(float* dst, const float* src, size_t n) {
#if HWY_ARCH_X86
  size_t i = 0;
  for (; i < n && (reinterpret_cast<uintptr_t>(dst + i) & 15) != 0; ++i) dst[i] = src[i];
  for (; i + 4 <= n; i += 4) _mm_stream_ps(dst + i, _mm_loadu_ps(src + i));
  for (; i < n; ++i) dst[i] = src[i];
#else
  std::memcpy(dst, src, n * sizeof(float));
#endif
}

// The tile [x0, x1] x [y0, y1] of fb drawn in w's tile-sized planes (TilePixels), which this
// fills: cleared to `clear`, or else copied from fb. A target with AOVs (or without depth) is
// drawn in place and only cleared.
TilePixels tile_pixels(Worker& w, Framebuffer& fb, int tile, const ClearValues* clear, int x0,
                       int y0, int x1, int y1) {
  const bool in_place = !fb.aov.empty() || fb.depth.values.empty();
  const bool color = !fb.color.pixels.empty();
  TilePixels px;
  if (in_place) {
    px = {color ? fb.color.pixels.data() : nullptr, fb.depth.values.data(),
          static_cast<size_t>(fb.width), 0, 0};
  } else {
    const size_t area = static_cast<size_t>(tile) * tile;
    if (w.tile_depth.size() < area) w.tile_depth.resize(area);
    if (color && w.tile_color.size() < area) w.tile_color.resize(area);
    px = {color ? w.tile_color.data() : nullptr, w.tile_depth.data(), static_cast<size_t>(tile), x0,
          y0};
  }
  if (in_place && !clear) return px;
  const size_t n = static_cast<size_t>(x1 - x0 + 1);
  for (int y = y0; y <= y1; ++y) {
    float* d = px.depth ? &px.depth_at(x0, y) : nullptr;
    glm::vec4* c = px.color ? &px.color_at(x0, y) : nullptr;
    if (clear) {
      if (d) std::fill_n(d, n, clear->depth);
      if (c) std::fill_n(c, n, clear->color);
      if (!fb.aov.empty()) std::fill_n(fb.aov_at(x0, y), n * kAovTotalChannels, 0.0f);
    } else {
      std::memcpy(d, &fb.depth.at(x0, y), n * sizeof(float));
      if (c) std::memcpy(c, &fb.color.at(x0, y), n * sizeof(glm::vec4));
    }
  }
  return px;
}

// Writes tile_pixels' copies back into fb.
void write_back(const TilePixels& px, Framebuffer& fb, int x0, int y0, int x1, int y1) {
  if (px.depth == fb.depth.values.data()) return;  // drawn in place
  const size_t n = static_cast<size_t>(x1 - x0 + 1);
  for (int y = y0; y <= y1; ++y) {
    stream_floats(&fb.depth.at(x0, y), &px.depth_at(x0, y), n);
    if (px.color) stream_floats(&fb.color.at(x0, y).x, &px.color_at(x0, y).x, 4 * n);
  }
#if HWY_ARCH_X86
  _mm_sfence();  // the streamed stores are ordered before the pool reports the tile done
#endif
}

}  // namespace

// flatten: the traversal inlined into one function (speed only; see plugins/shading.h).
RELIEF_LANE_FLATTEN void raster_tile(const TileGrid& g, Worker& w, Framebuffer& fb,
                                     std::span<const DrawCall> draws, int tile,
                                     const ClearValues* clear) {
  int x0, y0, x1, y1;
  tile_rect(g, fb, tile, x0, y0, x1, y1);
  const TilePixels px = tile_pixels(w, fb, g.tile, clear, x0, y0, x1, y1);
  for (const TileBins& r : g.runs)
    for (uint32_t i = r.start[tile]; i < r.start[tile + 1]; ++i) {
      const SetupTriangle& t = r.tris[r.items[i]];
      raster_triangle(r.planes, w, px, fb, draws[t.draw], t, x0, y0, x1, y1);
    }
  write_back(px, fb, x0, y0, x1, y1);
}

}  // namespace HWY_NAMESPACE
}  // namespace raster_detail
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief::raster_detail {

HWY_EXPORT(raster_tile);

void raster_tile(const TileGrid& g, Worker& w, Framebuffer& fb, std::span<const DrawCall> draws,
                 int tile, const ClearValues* clear) {
  HWY_DYNAMIC_DISPATCH(raster_tile)(g, w, fb, draws, tile, clear);
}

}  // namespace relief::raster_detail
#endif  // HWY_ONCE
