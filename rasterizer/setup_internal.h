// Triangle setup for the rasterizer (internal to rasterizer/, not installed): the draws'
// triangles culled, clipped where they leave the guard band (rasterizer/clip_internal.h), snapped
// to fixed point and turned into edge functions and attribute planes (rasterizer/raster_tile.h's
// SetupTriangle) for the tile traversal. Plain scalar code: rasterizer/pipeline.cpp runs it once
// per frame before binning; cpu_triangle_planes (pipeline.h) makes the same decisions for one
// triangle.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "rasterizer/clip_internal.h"
#include "rasterizer/pipeline.h"
#include "rasterizer/raster_tile.h"

namespace relief::raster_detail {

// A vertex after the perspective divide and viewport: what setup needs.
struct ScreenVertex {
  int32_t x, y;   // fixed point, 8 sub-pixel bits
  float z;        // NDC depth, reversed-Z
  float iw;       // 1 / w
  uint32_t vary;  // offset of the premultiplied (v / w) varyings in the frame's arena
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

// One frame's triangle setup: what the tiles read (the setup triangles and their attribute
// planes) and the scratch that makes them, reused between frames so steady state does not
// allocate.
struct FrameSetup {
  std::vector<SetupTriangle> tris;
  std::vector<float> vary;        // premultiplied varyings of every screen vertex
  std::vector<float> clip_arena;  // varyings of vertices made by the clipper
  std::vector<float> planes;      // attribute planes of every setup triangle
  std::vector<uint32_t> codes;    // per-vertex scratch of setup_draw
  std::vector<ScreenVertex> screen;
  std::vector<uint8_t> valid;
  int width = 0, height = 0;
  float gx = 1.0f, gy = 1.0f;  // guard band in NDC units

  // Starts a frame on a width x height target: no triangles yet.
  void begin(int target_width, int target_height);
  // Sets up the triangles of draw `draw` in order, appending to `tris`; counts them in `stats`
  // (in, culled, clipped).
  void setup_draw(int draw, const DrawCall& dc, RasterStats& stats);

 private:
  uint32_t outcode(const glm::vec4& c) const;
  bool to_screen(const glm::vec4& c, const float* v, int nv, ScreenVertex& s);
  void setup(int draw, const DrawCall& dc, ScreenVertex v0, ScreenVertex v1, ScreenVertex v2,
             RasterStats& stats);
  void clip_and_setup(int draw, const DrawCall& dc, const ClipVertex in[3], uint32_t planes,
                      RasterStats& stats);
};

}  // namespace relief::raster_detail
