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

// Channel c's four lanes of quad q of the shader's output, NaN and infinities read as 0 (the
// scalar write-out's std::isfinite test: exponent bits all ones).
vf4 quad_channel(const FragmentOutput& o, int c, int q) {
  vf4 v;
  std::memcpy(&v, &o.color[c][q * 4], sizeof v);
  vi4 bits;
  std::memcpy(&bits, &v, sizeof v);
  const vi4 finite = (bits & 0x7f800000) != 0x7f800000;
  return reinterpret_cast<vf4>(bits & finite);
}

// Writes quad q, every lane covered and kept, of a draw that tests depth before shading and
// writes colour without blending or AOVs: the values of the per-lane loop below (the same
// floats), as two 32-byte rows of colour and two 8-byte rows of depth.
void write_full_quad(const FragmentPacket& p, const FragmentOutput& o, Worker& w, Framebuffer& fb,
                     const DrawCall& dc, int q) {
  const int x = w.qx[q], y = w.qy[q];
  if (dc.depth_write) {
    std::memcpy(&fb.depth.at(x, y), &p.frag_z[q * 4], 2 * sizeof(float));
    std::memcpy(&fb.depth.at(x, y + 1), &p.frag_z[q * 4 + 2], 2 * sizeof(float));
  }
  // Lanes (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1) from channel-major to pixel-major.
  const vf4 r = quad_channel(o, 0, q), g = quad_channel(o, 1, q);
  const vf4 b = quad_channel(o, 2, q), a = quad_channel(o, 3, q);
  const vf4 rg01 = __builtin_shufflevector(r, g, 0, 4, 1, 5);
  const vf4 ba01 = __builtin_shufflevector(b, a, 0, 4, 1, 5);
  const vf4 rg23 = __builtin_shufflevector(r, g, 2, 6, 3, 7);
  const vf4 ba23 = __builtin_shufflevector(b, a, 2, 6, 3, 7);
  const vf4 px[4] = {__builtin_shufflevector(rg01, ba01, 0, 1, 4, 5),
                     __builtin_shufflevector(rg01, ba01, 2, 3, 6, 7),
                     __builtin_shufflevector(rg23, ba23, 0, 1, 4, 5),
                     __builtin_shufflevector(rg23, ba23, 2, 3, 6, 7)};
  std::memcpy(&fb.color.at(x, y), &px[0], 2 * sizeof(vf4));
  std::memcpy(&fb.color.at(x, y + 1), &px[2], 2 * sizeof(vf4));
}

void flush(Worker& w, Framebuffer& fb, const DrawCall& dc) {
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
      write_full_quad(p, o, w, fb, dc, q);
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
      float& stored = fb.depth.at(x, y);
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
        glm::vec4& dst = fb.color.at(x, y);
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
void raster_triangle(const float* planes, Worker& w, Framebuffer& fb, const DrawCall& dc,
                     const SetupTriangle& t, int tx0, int ty0, int tx1, int ty1) {
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
  const int dw = fb.depth.width;
  float* depth = fb.depth.values.data();
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
        const float* r0 = depth + size_t(qy) * dw + qx;
        const float* r1 = r0 + dw;
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
            d[l] = x <= x1 && y <= y1 ? depth[size_t(y) * dw + x] : 1.0f;
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
      if (p.num_quads > kPacketQuads - 2) flush(w, fb, dc);
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
  flush(w, fb, dc);
}

}  // namespace

// Sets n values from dst on to v, in stores as wide as the target's vectors (the clear runs
// ahead of the tile's first reads and is bound by how many stores to lines not yet in the cache
// the core keeps in flight: one wide store a line holds more lines in flight than four narrow
// ones).
template <class T>
void fill_wide(T* dst, size_t n, const T& v) {
  constexpr size_t kBytes = HWY_MAX_BYTES;  // the target's widest vector
  constexpr size_t kPer = kBytes / sizeof(T);
  if constexpr (kPer >= 2 && kBytes % sizeof(T) == 0) {
    T block[kPer];
    std::fill_n(block, kPer, v);
    size_t i = 0;
    for (; i + kPer <= n; i += kPer) std::memcpy(dst + i, block, kBytes);
    std::fill_n(dst + i, n - i, v);
  } else {
    std::fill_n(dst, n, v);
  }
}

// Clears the tile's rows [x0, x1] x [y0, y1] of every plane the target has (a depth-only target
// has no colour).
void clear_rect(Framebuffer& fb, const ClearValues& c, int x0, int y0, int x1, int y1) {
  const size_t n = static_cast<size_t>(x1 - x0 + 1);
  for (int y = y0; y <= y1; ++y) {
    const size_t row = static_cast<size_t>(y) * fb.width + x0;
    if (!fb.color.pixels.empty()) fill_wide(fb.color.pixels.data() + row, n, c.color);
    if (!fb.depth.values.empty()) fill_wide(fb.depth.values.data() + row, n, c.depth);
    if (!fb.aov.empty())
      fill_wide(fb.aov.data() + row * kAovTotalChannels, n * kAovTotalChannels, 0.0f);
  }
}

// flatten: the traversal inlined into one function (speed only; see plugins/shading.h).
RELIEF_LANE_FLATTEN void raster_tile(const TileGrid& g, Worker& w, Framebuffer& fb,
                                     std::span<const DrawCall> draws, int tile,
                                     const ClearValues* clear) {
  int x0, y0, x1, y1;
  tile_rect(g, fb, tile, x0, y0, x1, y1);
  if (clear) clear_rect(fb, *clear, x0, y0, x1, y1);
  for (const TileBins& r : g.runs)
    for (uint32_t i = r.start[tile]; i < r.start[tile + 1]; ++i) {
      const SetupTriangle& t = r.tris[r.items[i]];
      raster_triangle(r.planes, w, fb, draws[t.draw], t, x0, y0, x1, y1);
    }
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
