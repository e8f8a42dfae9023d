// Triangle setup for the rasterizer (rasterizer/setup_internal.h) and cpu_triangle_planes
// (rasterizer/pipeline.h), which makes the same decisions for one triangle.
#include <algorithm>
#include <cmath>

#include "base/check.h"
#include "rasterizer/clip_internal.h"
#include "rasterizer/setup_internal.h"

namespace relief {
namespace raster_detail {

bool screen_vertex(const glm::vec4& c, int width, int height, int32_t& x, int32_t& y, float& z,
                   float& iw_out) {
  if (!(c.w > 0.0f)) return false;
  const double iw = 1.0 / static_cast<double>(c.w);
  const double sx = (c.x * iw * 0.5 + 0.5) * width;
  const double sy = (0.5 - c.y * iw * 0.5) * height;
  x = static_cast<int32_t>(std::lround(sx * kSubOne));
  y = static_cast<int32_t>(std::lround(sy * kSubOne));
  z = std::clamp(static_cast<float>(c.z * iw), 0.0f, 1.0f);
  iw_out = static_cast<float>(iw);
  return true;
}

bool pixel_box(int64_t minx, int64_t maxx, int64_t miny, int64_t maxy, int width, int height,
               int& x0, int& y0, int& x1, int& y1) {
  auto ceil_div = [](int64_t a, int64_t b) { return a >= 0 ? (a + b - 1) / b : -((-a) / b); };
  auto floor_div = [](int64_t a, int64_t b) { return a >= 0 ? a / b : -((-a + b - 1) / b); };
  x0 = static_cast<int>(std::max<int64_t>(0, ceil_div(minx - kHalf, kSubOne)));
  y0 = static_cast<int>(std::max<int64_t>(0, ceil_div(miny - kHalf, kSubOne)));
  x1 = static_cast<int>(std::min<int64_t>(width - 1, floor_div(maxx - kHalf, kSubOne)));
  y1 = static_cast<int>(std::min<int64_t>(height - 1, floor_div(maxy - kHalf, kSubOne)));
  return x0 <= x1 && y0 <= y1;
}

void attribute_planes(const int32_t px[3], const int32_t py[3], int x0, int y0,
                      const float* const a[], int n, float* out) {
  const double X0 = px[0] / double(kSubOne), Y0 = py[0] / double(kSubOne);
  const double X1 = px[1] / double(kSubOne) - X0, Y1 = py[1] / double(kSubOne) - Y0;
  const double X2 = px[2] / double(kSubOne) - X0, Y2 = py[2] / double(kSubOne) - Y0;
  const double inv_d = 1.0 / (X1 * Y2 - X2 * Y1);
  const double rx = x0 + 0.5 - X0, ry = y0 + 0.5 - Y0;
  for (int k = 0; k < n; ++k) {
    const double a0 = a[k][0], a1 = a[k][1], a2 = a[k][2];
    const double d1 = a1 - a0, d2 = a2 - a0;
    const double dx = (d1 * Y2 - d2 * Y1) * inv_d;
    const double dy = (d2 * X1 - d1 * X2) * inv_d;
    out[3 * k] = static_cast<float>(a0 + dx * rx + dy * ry);
    out[3 * k + 1] = static_cast<float>(dx);
    out[3 * k + 2] = static_cast<float>(dy);
  }
}

uint32_t FrameSetup::outcode(const glm::vec4& c) const {
  return clip_outcode(c, gx, gy);
}

bool FrameSetup::to_screen(const glm::vec4& c, const float* v, ScreenVertex& s) const {
  if (!screen_vertex(c, width, height, s.x, s.y, s.z, s.iw)) return false;
  s.vary = v;
  return true;
}

void FrameSetup::place_vertices(const DrawCall& dc, DrawVertices& dv, size_t first,
                                size_t last) const {
  const int nv = dc.num_varyings;
  if (dc.transform) {
    const glm::mat4& m = *dc.transform;
    for (size_t i = first; i < last; ++i) dv.clip_storage[i] = m * dc.clip[i];
  }
  for (size_t i = first; i < last; ++i) {
    const glm::vec4& c = dv.clip[i];
    bool valid = finite4(c);
    dv.codes[i] = valid ? outcode(c) : 0;
    if (valid && !(dv.codes[i] & kNeedsClip))
      valid = to_screen(c, dc.varyings.data() + i * nv, dv.screen[i]);
    dv.valid[i] = valid;
  }
}

void FrameSetup::setup(SetupSegment& seg, const DrawCall& dc, ScreenVertex v0, ScreenVertex v1,
                       ScreenVertex v2) const {
  int64_t area = int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v1.y - v0.y) * (v2.x - v0.x);
  if (area == 0) {
    ++seg.stats.triangles_culled;
    return;
  }
  const bool front = area < 0;  // counter-clockwise in NDC (y up) has negative area in y-down
  if ((dc.cull == CullMode::kBack && !front) || (dc.cull == CullMode::kFront && front)) {
    ++seg.stats.triangles_culled;
    return;
  }
  if (area < 0) {  // edge functions below assume positive area
    std::swap(v1, v2);
    area = -area;
  }
  SetupTriangle t;
  t.draw = seg.draw;
  t.front_facing = front;
  const ScreenVertex* v[3] = {&v0, &v1, &v2};
  const int64_t minx = std::min({v0.x, v1.x, v2.x}), maxx = std::max({v0.x, v1.x, v2.x});
  const int64_t miny = std::min({v0.y, v1.y, v2.y}), maxy = std::max({v0.y, v1.y, v2.y});
  // Pixels whose centre (x * 256 + 128) lies in the box.
  if (!pixel_box(minx, maxx, miny, maxy, width, height, t.x0, t.y0, t.x1, t.y1)) {
    ++seg.stats.triangles_culled;
    return;
  }
  for (int e = 0; e < 3; ++e) {
    // Edge e runs from vertex e+1 to e+2 and weighs vertex e.
    const ScreenVertex& a = *v[(e + 1) % 3];
    const ScreenVertex& b = *v[(e + 2) % 3];
    t.a[e] = int64_t(a.y) - b.y;
    t.b[e] = int64_t(b.x) - a.x;
    t.c[e] = -t.a[e] * a.x - t.b[e] * a.y;
    // Top edge: horizontal with the interior below (y grows down); left edge: going up.
    const bool top_left = (a.y == b.y && b.x > a.x) || (b.y < a.y);
    t.bias[e] = top_left ? 0 : -1;
  }
  // Plane equations in double, stored in float relative to the bounding box's first pixel.
  const int nv = dc.num_varyings;
  t.plane = static_cast<uint32_t>(seg.planes.size());
  seg.planes.resize(seg.planes.size() + size_t(kPlaneVary + nv) * 3);
  const int32_t px[3] = {v0.x, v[1]->x, v[2]->x}, py[3] = {v0.y, v[1]->y, v[2]->y};
  float values[kPlaneVary + kMaxVaryings][3];
  const float* rows[kPlaneVary + kMaxVaryings];
  for (int i = 0; i < 3; ++i) {
    values[kPlaneZ][i] = v[i]->z;
    values[kPlaneIw][i] = v[i]->iw;
    for (int k = 0; k < nv; ++k) values[kPlaneVary + k][i] = v[i]->vary[k] * v[i]->iw;
  }
  for (int k = 0; k < kPlaneVary + nv; ++k) rows[k] = values[k];
  attribute_planes(px, py, t.x0, t.y0, rows, kPlaneVary + nv, &seg.planes[t.plane]);
  seg.tris.push_back(t);
}

// Sutherland-Hodgman in homogeneous space against the planes in `planes`, then a fan.
void FrameSetup::clip_and_setup(SetupSegment& seg, const DrawCall& dc, const ClipVertex in[3],
                                uint32_t planes) const {
  const int nv = dc.num_varyings;
  ClipPolygon a;
  seg.clip_arena.clear();
  clip_triangle(in, nv, planes, gx, gy, seg.clip_arena, a);
  if (a.n < 3) {
    ++seg.stats.triangles_culled;
    return;
  }
  ScreenVertex s[9];
  for (int i = 0; i < a.n; ++i)
    if (!to_screen(a.c[i], seg.clip_arena.data() + a.arena[i], s[i])) {
      ++seg.stats.triangles_culled;
      return;
    }
  for (int i = 1; i + 1 < a.n; ++i) setup(seg, dc, s[0], s[i], s[i + 1]);
}

void FrameSetup::setup_segment(const DrawCall& dc, SetupSegment& seg) const {
  const DrawVertices& dv = vertices[seg.draw];
  const size_t nvert = dc.clip.size();
  const int nv = dc.num_varyings;
  seg.tris.clear();
  seg.planes.clear();
  seg.stats = RasterStats{};
  for (size_t t = seg.first; t < seg.first + seg.count; ++t) {
    ++seg.stats.triangles_in;
    const uint32_t i0 = dc.indices[3 * t], i1 = dc.indices[3 * t + 1], i2 = dc.indices[3 * t + 2];
    if (i0 >= nvert || i1 >= nvert || i2 >= nvert || !dv.valid[i0] || !dv.valid[i1] ||
        !dv.valid[i2]) {
      ++seg.stats.triangles_culled;
      continue;
    }
    const uint32_t all = dv.codes[i0] & dv.codes[i1] & dv.codes[i2];
    if (all & (kOutNear | kOutFar | kOutViewL | kOutViewR | kOutViewT | kOutViewB)) {
      ++seg.stats.triangles_culled;  // wholly outside one plane
      continue;
    }
    const uint32_t any = (dv.codes[i0] | dv.codes[i1] | dv.codes[i2]) & kNeedsClip;
    if (!any) {
      setup(seg, dc, dv.screen[i0], dv.screen[i1], dv.screen[i2]);
    } else {
      ++seg.stats.triangles_clipped;
      const ClipVertex in[3] = {{dv.clip[i0], dc.varyings.data() + size_t(i0) * nv},
                                {dv.clip[i1], dc.varyings.data() + size_t(i1) * nv},
                                {dv.clip[i2], dc.varyings.data() + size_t(i2) * nv}};
      clip_and_setup(seg, dc, in, any & 0x3fu);
    }
  }
}

void FrameSetup::bin(SetupSegment& seg, int tile, int tiles_x, int tiles_y) {
  const size_t ntiles = size_t(tiles_x) * tiles_y;
  seg.start.assign(ntiles + 1, 0);
  for (const SetupTriangle& t : seg.tris)
    for (int ty = t.y0 / tile; ty <= t.y1 / tile; ++ty)
      for (int tx = t.x0 / tile; tx <= t.x1 / tile; ++tx)
        ++seg.start[size_t(ty) * tiles_x + tx + 1];
  for (size_t k = 0; k < ntiles; ++k) seg.start[k + 1] += seg.start[k];
  seg.items.resize(seg.start[ntiles]);
  // Fill with a running cursor per tile (start[k] advanced, then shifted back).
  for (uint32_t i = 0; i < seg.tris.size(); ++i) {
    const SetupTriangle& t = seg.tris[i];
    for (int ty = t.y0 / tile; ty <= t.y1 / tile; ++ty)
      for (int tx = t.x0 / tile; tx <= t.x1 / tile; ++tx)
        seg.items[seg.start[size_t(ty) * tiles_x + tx]++] = i;
  }
  for (size_t k = ntiles; k > 0; --k) seg.start[k] = seg.start[k - 1];
  seg.start[0] = 0;
}

void FrameSetup::run(ThreadPool& pool, std::span<const DrawCall> draws, int target_width,
                     int target_height, int tile, int tiles_x, int tiles_y, RasterStats& stats) {
  width = target_width;
  height = target_height;
  gx = guard_band(target_width);
  gy = guard_band(target_height);
  // The draws' vertices, in runs of kVertexRun.
  if (vertices.size() < draws.size()) vertices.resize(draws.size());
  vertex_runs.clear();
  for (size_t d = 0; d < draws.size(); ++d) {
    const DrawCall& dc = draws[d];
    CHECK_LE(dc.num_varyings, kMaxVaryings);
    CHECK(dc.shader != nullptr);
    const size_t nvert = dc.clip.size();
    CHECK_GE(dc.varyings.size(), nvert * dc.num_varyings);
    DrawVertices& dv = vertices[d];
    if (dc.transform) {
      dv.clip_storage.resize(nvert);
      dv.clip = dv.clip_storage.data();
    } else {
      dv.clip = dc.clip.data();
    }
    dv.codes.resize(nvert);
    dv.screen.resize(nvert);
    dv.valid.resize(nvert);
    for (size_t v = 0; v < nvert; v += kVertexRun) vertex_runs.emplace_back(int(d), v);
  }
  pool.run(static_cast<int>(vertex_runs.size()), [&](int r, int) {
    const auto [d, first] = vertex_runs[r];
    const DrawCall& dc = draws[d];
    place_vertices(dc, vertices[d], first, std::min(first + kVertexRun, dc.clip.size()));
  });
  // The draws' triangles in segments of kSegmentTriangles, each set up and binned.
  used = 0;
  for (size_t d = 0; d < draws.size(); ++d) {
    const size_t ntri = draws[d].indices.size() / 3;
    for (size_t t = 0; t < ntri; t += kSegmentTriangles) {
      if (used == segments.size()) segments.push_back(std::make_unique<SetupSegment>());
      SetupSegment& seg = *segments[used++];
      seg.draw = static_cast<int>(d);
      seg.first = t;
      seg.count = std::min(kSegmentTriangles, ntri - t);
    }
  }
  pool.run(static_cast<int>(used), [&](int k, int) {
    SetupSegment& seg = *segments[k];
    setup_segment(draws[seg.draw], seg);
    bin(seg, tile, tiles_x, tiles_y);
  });
  runs.clear();
  for (size_t k = 0; k < used; ++k) {
    const SetupSegment& seg = *segments[k];
    stats.triangles_in += seg.stats.triangles_in;
    stats.triangles_culled += seg.stats.triangles_culled;
    stats.triangles_clipped += seg.stats.triangles_clipped;
    stats.triangles_binned += seg.tris.size();
    if (!seg.tris.empty())
      runs.push_back({seg.tris.data(), seg.planes.data(), seg.start.data(), seg.items.data()});
  }
}

}  // namespace raster_detail

using namespace raster_detail;

bool cpu_triangle_planes(const glm::vec4 clip[3], const float* const varyings[3], int num_varyings,
                         int width, int height, CpuTrianglePlanes& out) {
  CHECK_LE(num_varyings, kMaxVaryings);
  out.parts.clear();
  const int nv = num_varyings;
  const float gx = guard_band(width), gy = guard_band(height);
  uint32_t codes[3];
  for (int i = 0; i < 3; ++i) {
    if (!finite4(clip[i])) return false;
    codes[i] = clip_outcode(clip[i], gx, gy);
  }
  // setup_draw's decisions: wholly outside one plane, drawn as is, or clipped into a fan
  if (codes[0] & codes[1] & codes[2] &
      (kOutNear | kOutFar | kOutViewL | kOutViewR | kOutViewT | kOutViewB))
    return false;
  const uint32_t any = (codes[0] | codes[1] | codes[2]) & kNeedsClip;
  std::vector<float> arena;
  ClipPolygon poly;
  if (!any) {
    poly.n = 3;
    for (int i = 0; i < 3; ++i) {
      poly.c[i] = clip[i];
      poly.arena[i] = static_cast<int>(arena.size());
      arena.insert(arena.end(), varyings[i], varyings[i] + nv);
    }
  } else {
    const ClipVertex in[3] = {
        {clip[0], varyings[0]}, {clip[1], varyings[1]}, {clip[2], varyings[2]}};
    clip_triangle(in, nv, any & 0x3fu, gx, gy, arena, poly);
    if (poly.n < 3) return false;
  }
  int32_t sx[9], sy[9];
  float sz[9], siw[9];
  for (int i = 0; i < poly.n; ++i)
    if (!screen_vertex(poly.c[i], width, height, sx[i], sy[i], sz[i], siw[i])) return false;
  for (int f = 1; f + 1 < poly.n; ++f) {
    const int id[3] = {0, f, f + 1};
    int32_t px[3], py[3];
    float values[2 + kMaxVaryings][3];
    for (int i = 0; i < 3; ++i) {
      const int v = id[i];
      px[i] = sx[v];
      py[i] = sy[v];
      values[kPlaneZ][i] = sz[v];
      values[kPlaneIw][i] = siw[v];
      for (int k = 0; k < nv; ++k) values[kPlaneVary + k][i] = arena[poly.arena[v] + k] * siw[v];
    }
    const int64_t area =
        int64_t(px[1] - px[0]) * (py[2] - py[0]) - int64_t(py[1] - py[0]) * (px[2] - px[0]);
    if (area == 0) continue;
    if (area < 0) {  // setup's orientation swap of vertices 1 and 2
      std::swap(px[1], px[2]);
      std::swap(py[1], py[2]);
      for (auto& v : values) std::swap(v[1], v[2]);
    }
    CpuTrianglePlanes::Part part;
    int x1, y1;
    if (!pixel_box(std::min({px[0], px[1], px[2]}), std::max({px[0], px[1], px[2]}),
                   std::min({py[0], py[1], py[2]}), std::max({py[0], py[1], py[2]}), width, height,
                   part.x0, part.y0, x1, y1))
      continue;
    for (int i = 0; i < 3; ++i) {
      part.corner[2 * i] = static_cast<float>(px[i]) / kSubOne;
      part.corner[2 * i + 1] = static_cast<float>(py[i]) / kSubOne;
    }
    const float* rows[2 + kMaxVaryings];
    for (int k = 0; k < 2 + nv; ++k) rows[k] = values[k];
    part.planes.resize(static_cast<size_t>(2 + nv) * 3);
    attribute_planes(px, py, part.x0, part.y0, rows, 2 + nv, part.planes.data());
    out.parts.push_back(std::move(part));
  }
  return !out.parts.empty();
}

}  // namespace relief
