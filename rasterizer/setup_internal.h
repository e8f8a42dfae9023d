// Triangle setup for the rasterizer (internal to rasterizer/, not installed): the draws'
// triangles culled, clipped where they leave the guard band (rasterizer/clip_internal.h), snapped
// to fixed point and turned into edge functions and attribute planes (rasterizer/raster_tile.h's
// SetupTriangle) for the tile traversal, and binned by tile. rasterizer/pipeline.cpp runs it once
// per frame, spread over the pool; cpu_triangle_planes (pipeline.h) makes the same decisions for
// one triangle.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "base/thread_pool.h"
#include "rasterizer/clip_internal.h"
#include "rasterizer/pipeline.h"
#include "rasterizer/raster_tile.h"

namespace relief::raster_detail {

// A vertex after the perspective divide and viewport: what setup needs.
struct ScreenVertex {
  int32_t x, y;       // fixed point, 8 sub-pixel bits
  float z;            // NDC depth, reversed-Z
  float iw;           // 1 / w
  const float* vary;  // its varyings (the draw's, or the clipper's), times iw in the planes
};

// A clip-space vertex on a width x height target: window position in 1/kSubOne pixel fixed
// point (rows top to bottom), depth and 1/w. False behind the eye.
bool screen_vertex(const glm::vec4& c, int width, int height, int32_t& x, int32_t& y, float& z,
                   float& iw_out);

// The first pixel (x0, y0) of the box of pixels whose centre lies in the box [minx, maxx] x
// [miny, maxy] (fixed point), clamped to the target; false when no pixel centre is inside.
bool pixel_box(int64_t minx, int64_t maxx, int64_t miny, int64_t maxy, int width, int height,
               int& x0, int& y0, int& x1, int& y1);

// Plane equations in double, stored in float relative to the box's first pixel (x0, y0): for
// vertices p[0..2] (fixed point, after the orientation swap) and per-vertex values a[k][i], k in
// 0..n-1, writes (c, dx, dy) of plane k to out[3 k].
void attribute_planes(const int32_t px[3], const int32_t py[3], int x0, int y0,
                      const float* const a[], int n, float* out);

// The guard band of a target `size` pixels wide (or high), in NDC units: 1 plus kGuardBand
// pixels on either side.
inline float guard_band(int size) {
  return 1.0f + 2.0f * kGuardBand / size;
}

// One draw's vertices on screen: made once per vertex (in parallel over runs of vertices) and
// read by every segment of the draw.
struct DrawVertices {
  const glm::vec4* clip = nullptr;      // the draw's clip positions, or clip_storage's
  std::vector<glm::vec4> clip_storage;  // DrawCall::transform times each position
  std::vector<uint32_t> codes;          // outcodes
  std::vector<ScreenVertex> screen;
  std::vector<uint8_t> valid;  // finite, in front of the eye where drawn unclipped
};

// A run of one draw's triangles, set up by one thread and binned by tile: its setup triangles,
// their attribute planes, and per tile the indices of the triangles that touch it (a counting
// sort: tile k's are items[start[k] .. start[k + 1])). Reused between frames.
struct SetupSegment {
  int draw = 0;
  size_t first = 0, count = 0;  // the draw's triangles [first, first + count)
  std::vector<SetupTriangle> tris;
  std::vector<float> planes;      // attribute planes of every setup triangle
  std::vector<float> clip_arena;  // varyings of vertices made by the clipper
  std::vector<uint32_t> start, items;
  RasterStats stats;  // triangles in, culled, clipped
};

// One frame's triangle setup, in three steps that each run in parallel and give the same result
// for any thread count: the draws' vertices on screen (runs of kVertexRun vertices), the draws'
// triangles set up in segments of kSegmentTriangles (culled, clipped where they leave the guard
// band, edge functions and planes), and each segment binned by tile. Tiles read the segments in
// order, so every tile sees its triangles in submission order. The buffers are kept between
// frames, so steady state does not allocate.
struct FrameSetup {
  static constexpr size_t kVertexRun = 32768;
  static constexpr size_t kSegmentTriangles = 32768;
  std::vector<DrawVertices> vertices;                   // per draw
  std::vector<std::unique_ptr<SetupSegment>> segments;  // the first `used` are this frame's
  size_t used = 0;
  std::vector<TileBins> runs;  // one per segment with triangles, for the TileGrid
  std::vector<std::pair<int, size_t>> vertex_runs;  // (draw, first vertex) of each vertex run
  int width = 0, height = 0;
  float gx = 1.0f, gy = 1.0f;  // guard band in NDC units

  // Sets up `draws` on a width x height target with tiles of `tile` pixels (tiles_x x tiles_y),
  // the steps spread over `pool`; sums the segments' counters into `stats`.
  void run(ThreadPool& pool, std::span<const DrawCall> draws, int target_width, int target_height,
           int tile, int tiles_x, int tiles_y, RasterStats& stats);

 private:
  uint32_t outcode(const glm::vec4& c) const;
  bool to_screen(const glm::vec4& c, const float* v, ScreenVertex& s) const;
  void place_vertices(const DrawCall& dc, DrawVertices& dv, size_t first, size_t last) const;
  void setup_segment(const DrawCall& dc, SetupSegment& seg) const;
  void setup(SetupSegment& seg, const DrawCall& dc, ScreenVertex v0, ScreenVertex v1,
             ScreenVertex v2) const;
  void clip_and_setup(SetupSegment& seg, const DrawCall& dc, const ClipVertex in[3],
                      uint32_t planes) const;
  static void bin(SetupSegment& seg, int tile, int tiles_x, int tiles_y);
};

}  // namespace relief::raster_detail
