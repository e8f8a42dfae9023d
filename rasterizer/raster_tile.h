// What the rasterizer's setup hands its tile traversal (internal to rasterizer/): setup
// triangles, their attribute planes and tile bins, and the per-thread packet state. The traversal
// (rasterizer/raster_tile.cpp) is compiled once per SIMD target (base/simd.h); raster_tile picks
// the level in use.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rasterizer/fragment.h"
#include "rasterizer/image.h"
#include "rasterizer/pipeline.h"

namespace relief::raster_detail {

constexpr int kSubBits = 8;
constexpr int64_t kSubOne = 1 << kSubBits;
constexpr int64_t kHalf = kSubOne / 2;

struct SetupTriangle {
  int draw;
  bool front_facing;
  int x0, y0, x1, y1;        // pixel bounding box, inclusive, inside the viewport
  int64_t a[3], b[3], c[3];  // edge functions E = a*px + b*py + c in fixed point
  int64_t bias[3];           // 0 for top-left edges, -1 otherwise
  uint32_t plane;            // offset in the frame's plane arena: (2 + nv) x {c, dx, dy}
};

// Attribute planes are evaluated as (c + dx * fx) + dy * fy with fx = px - x0, fy = py - y0 (whole
// pixel offsets from the triangle's bounding-box origin): a pure function of the pixel, so the
// image does not depend on tiles or threads. Plane 0 is depth, plane 1 is 1/w, then the varyings
// premultiplied by 1/w.
inline constexpr int kPlaneZ = 0, kPlaneIw = 1, kPlaneVary = 2;

// One thread's packet, shader output and counters, reused between tiles.
struct Worker {
  FragmentPacket packet;
  FragmentOutput out;
  int16_t qx[kPacketQuads], qy[kPacketQuads];
  WorkCounters counters;
  uint64_t quads = 0;
  // The pixels of the tile being drawn (raster_tile.cpp, TilePixels): tile x tile, kept between
  // tiles and frames.
  std::vector<glm::vec4> tile_color;
  std::vector<float> tile_depth;
};

// One segment of the frame's setup (rasterizer/setup_internal.h SetupSegment) as the tiles read
// it: its triangles, their planes, and per tile the indices of those that touch it
// (items[start[tile] .. start[tile + 1])), in submission order.
struct TileBins {
  const SetupTriangle* tris;
  const float* planes;
  const uint32_t* start;
  const uint32_t* items;
};

// The frame's setup output that every tile reads: the segments in submission order.
struct TileGrid {
  std::span<const TileBins> runs;
  int tile, tiles_x;  // tile size in pixels, tiles per row
};

// Tile `tile`'s pixels in [x0, x1] x [y0, y1] (inclusive), clipped to the target.
inline void tile_rect(const TileGrid& g, const Framebuffer& fb, int tile, int& x0, int& y0, int& x1,
                      int& y1) {
  const int tx = tile % g.tiles_x, ty = tile / g.tiles_x;
  x0 = tx * g.tile;
  y0 = ty * g.tile;
  x1 = std::min(x0 + g.tile, fb.width) - 1;
  y1 = std::min(y0 + g.tile, fb.height) - 1;
}

// Rasterizes tile `tile`: its pixels cleared to `clear` (when given), then its triangles in
// submission order, through the draws' shaders, at the SIMD level in use.
void raster_tile(const TileGrid& g, Worker& w, Framebuffer& fb, std::span<const DrawCall> draws,
                 int tile, const ClearValues* clear);

}  // namespace relief::raster_detail
