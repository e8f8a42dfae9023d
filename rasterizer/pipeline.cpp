#include "rasterizer/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "base/check.h"
#include "base/simd.h"
#include "rasterizer/raster_tile.h"

namespace relief {
namespace {

using namespace raster_detail;

// A vertex after clipping: clip position and varyings, stored by the draw's vertex arena.
struct ClipVertex {
  glm::vec4 clip;
  const float* vary;
};

// A vertex after the perspective divide and viewport: what setup needs.
struct ScreenVertex {
  int32_t x, y;   // fixed point, 8 sub-pixel bits
  float z;        // NDC depth, reversed-Z
  float iw;       // 1 / w
  uint32_t vary;  // offset of the premultiplied (v / w) varyings in the frame's arena
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

bool finite4(const glm::vec4& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && std::isfinite(v.w);
}

// A clip-space vertex on a width x height target: window position in 1/kSubOne pixel fixed
// point (rows top to bottom), depth and 1/w. False behind the eye.
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

// The first pixel (x0, y0) of the box of pixels whose centre lies in the box [minx, maxx] x
// [miny, maxy] (fixed point), clamped to the target; false when no pixel centre is inside.
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

// Plane equations in double, stored in float relative to the box's first pixel (x0, y0): for
// vertices p[0..2] (fixed point, after the orientation swap) and per-vertex values a[k][i], k in
// 0..n-1, writes (c, dx, dy) of plane k to out[3 k].
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

// A clipped polygon: clip positions and the offsets of their varyings in the clip arena.
struct ClipPolygon {
  glm::vec4 c[9];
  int arena[9];
  int n = 0;
};

// Sutherland-Hodgman in homogeneous space: triangle `in` against the planes in `planes` (bits of
// plane_distance), with the guard band gx, gy; new vertices' varyings are appended to `arena`.
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

}  // namespace

struct Rasterizer::Impl {
  // Frame state, reused between frames so steady state does not allocate.
  std::vector<SetupTriangle> tris;
  std::vector<float> vary;                  // premultiplied varyings of every screen vertex
  std::vector<std::vector<uint32_t>> bins;  // triangle indices per tile, submission order
  std::vector<float> clip_arena;            // varyings of vertices made by the clipper
  std::vector<float> planes;                // attribute planes of every setup triangle
  std::vector<uint32_t> codes;              // per-vertex scratch of setup_draw
  std::vector<ScreenVertex> screen;
  std::vector<uint8_t> valid;
  std::vector<std::unique_ptr<Worker>> workers;
  RasterStats stats;
  int width = 0, height = 0, tiles_x = 0, tiles_y = 0, tile = 64;
  float gx = 1.0f, gy = 1.0f;  // guard band in NDC units

  TileGrid grid() const { return {tris, bins, planes.data(), tile, tiles_x}; }

  uint32_t outcode(const glm::vec4& c) const { return clip_outcode(c, gx, gy); }

  bool to_screen(const glm::vec4& c, const float* v, int nv, ScreenVertex& s) {
    if (!screen_vertex(c, width, height, s.x, s.y, s.z, s.iw)) return false;
    s.vary = static_cast<uint32_t>(vary.size());
    for (int k = 0; k < nv; ++k) vary.push_back(v[k] * s.iw);
    return true;
  }

  void setup(int draw, const DrawCall& dc, ScreenVertex v0, ScreenVertex v1, ScreenVertex v2) {
    int64_t area = int64_t(v1.x - v0.x) * (v2.y - v0.y) - int64_t(v1.y - v0.y) * (v2.x - v0.x);
    if (area == 0) {
      ++stats.triangles_culled;
      return;
    }
    const bool front = area < 0;  // counter-clockwise in NDC (y up) has negative area in y-down
    if ((dc.cull == CullMode::kBack && !front) || (dc.cull == CullMode::kFront && front)) {
      ++stats.triangles_culled;
      return;
    }
    if (area < 0) {  // edge functions below assume positive area
      std::swap(v1, v2);
      area = -area;
    }
    SetupTriangle t;
    t.draw = draw;
    t.front_facing = front;
    const ScreenVertex* v[3] = {&v0, &v1, &v2};
    const int64_t minx = std::min({v0.x, v1.x, v2.x}), maxx = std::max({v0.x, v1.x, v2.x});
    const int64_t miny = std::min({v0.y, v1.y, v2.y}), maxy = std::max({v0.y, v1.y, v2.y});
    // Pixels whose centre (x * 256 + 128) lies in the box.
    if (!pixel_box(minx, maxx, miny, maxy, width, height, t.x0, t.y0, t.x1, t.y1)) {
      ++stats.triangles_culled;
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
    t.plane = static_cast<uint32_t>(planes.size());
    planes.resize(planes.size() + size_t(kPlaneVary + nv) * 3);
    const int32_t px[3] = {v0.x, v[1]->x, v[2]->x}, py[3] = {v0.y, v[1]->y, v[2]->y};
    float values[kPlaneVary + kMaxVaryings][3];
    const float* rows[kPlaneVary + kMaxVaryings];
    for (int i = 0; i < 3; ++i) {
      values[kPlaneZ][i] = v[i]->z;
      values[kPlaneIw][i] = v[i]->iw;
      for (int k = 0; k < nv; ++k) values[kPlaneVary + k][i] = vary[v[i]->vary + k];
    }
    for (int k = 0; k < kPlaneVary + nv; ++k) rows[k] = values[k];
    attribute_planes(px, py, t.x0, t.y0, rows, kPlaneVary + nv, &planes[t.plane]);
    tris.push_back(t);
  }

  // Sutherland-Hodgman in homogeneous space against the planes in `mask`, then a fan.
  void clip_and_setup(int draw, const DrawCall& dc, const ClipVertex in[3], uint32_t planes) {
    const int nv = dc.num_varyings;
    ClipPolygon a;
    clip_triangle(in, nv, planes, gx, gy, clip_arena, a);
    if (a.n < 3) {
      ++stats.triangles_culled;
      return;
    }
    ScreenVertex s[9];
    for (int i = 0; i < a.n; ++i)
      if (!to_screen(a.c[i], clip_arena.data() + a.arena[i], nv, s[i])) {
        ++stats.triangles_culled;
        return;
      }
    for (int i = 1; i + 1 < a.n; ++i) setup(draw, dc, s[0], s[i], s[i + 1]);
  }

  void setup_draw(int draw, const DrawCall& dc) {
    CHECK_LE(dc.num_varyings, kMaxVaryings);
    CHECK(dc.shader != nullptr);
    const size_t nvert = dc.clip.size();
    const int nv = dc.num_varyings;
    CHECK_GE(dc.varyings.size(), nvert * nv);
    // Per-vertex outcodes and screen vertices, computed once per vertex.
    codes.resize(nvert);
    screen.resize(nvert);
    valid.resize(nvert);
    for (size_t i = 0; i < nvert; ++i) {
      const glm::vec4& c = dc.clip[i];
      valid[i] = finite4(c);
      codes[i] = valid[i] ? outcode(c) : 0;
      if (valid[i] && !(codes[i] & kNeedsClip))
        valid[i] = to_screen(c, dc.varyings.data() + i * nv, nv, screen[i]);
    }
    const size_t ntri = dc.indices.size() / 3;
    for (size_t t = 0; t < ntri; ++t) {
      ++stats.triangles_in;
      const uint32_t i0 = dc.indices[3 * t], i1 = dc.indices[3 * t + 1], i2 = dc.indices[3 * t + 2];
      if (i0 >= nvert || i1 >= nvert || i2 >= nvert || !valid[i0] || !valid[i1] || !valid[i2]) {
        ++stats.triangles_culled;
        continue;
      }
      const uint32_t all = codes[i0] & codes[i1] & codes[i2];
      if (all & (kOutNear | kOutFar | kOutViewL | kOutViewR | kOutViewT | kOutViewB)) {
        ++stats.triangles_culled;  // wholly outside one plane
        continue;
      }
      const uint32_t any = (codes[i0] | codes[i1] | codes[i2]) & kNeedsClip;
      if (!any) {
        setup(draw, dc, screen[i0], screen[i1], screen[i2]);
      } else {
        ++stats.triangles_clipped;
        const ClipVertex in[3] = {{dc.clip[i0], dc.varyings.data() + size_t(i0) * nv},
                                  {dc.clip[i1], dc.varyings.data() + size_t(i1) * nv},
                                  {dc.clip[i2], dc.varyings.data() + size_t(i2) * nv}};
        uint32_t planes = 0;
        for (int p = 0; p < 6; ++p)
          if (any & (1u << p)) planes |= 1u << p;
        clip_and_setup(draw, dc, in, planes);
      }
    }
  }

  void bin() {
    for (auto& b : bins) b.clear();
    for (uint32_t i = 0; i < tris.size(); ++i) {
      const SetupTriangle& t = tris[i];
      const int tx0 = t.x0 / tile, tx1 = t.x1 / tile, ty0 = t.y0 / tile, ty1 = t.y1 / tile;
      for (int ty = ty0; ty <= ty1; ++ty)
        for (int tx = tx0; tx <= tx1; ++tx) bins[size_t(ty) * tiles_x + tx].push_back(i);
    }
    stats.triangles_binned = tris.size();
  }

  // Clears one tile's rows of every plane the target has (a depth-only target has no colour).
  void clear_tile(Framebuffer& fb, const ClearValues& c, int tile) const {
    int x0, y0, x1, y1;
    tile_rect(grid(), fb, tile, x0, y0, x1, y1);
    const size_t n = static_cast<size_t>(x1 - x0 + 1);
    for (int y = y0; y <= y1; ++y) {
      const size_t row = static_cast<size_t>(y) * fb.width + x0;
      if (!fb.color.pixels.empty()) std::fill_n(fb.color.pixels.begin() + row, n, c.color);
      if (!fb.depth.values.empty()) std::fill_n(fb.depth.values.begin() + row, n, c.depth);
      if (!fb.aov.empty())
        std::fill_n(fb.aov.begin() + row * kAovTotalChannels, n * kAovTotalChannels, 0.0f);
    }
  }
};

Rasterizer::Rasterizer(ThreadPool& pool, RasterConfig config)
    : pool_(pool), config_(config), impl_(std::make_unique<Impl>()) {
  // Links base/simd.cpp, whose start-up code applies RELIEF_SIMD, into every program that draws:
  // the draws dispatch on the level it sets.
  (void)simd_level();
  CHECK(config_.tile_size >= 8 && config_.tile_size <= 512 && config_.tile_size % 2 == 0);
}

Rasterizer::~Rasterizer() = default;

RasterStats Rasterizer::draw(Framebuffer& fb, std::span<const DrawCall> draws,
                             const ClearValues* clear) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  Impl& im = *impl_;
  im.stats = RasterStats{};
  im.width = fb.width;
  im.height = fb.height;
  CHECK(fb.width > 0 && fb.height > 0 && fb.width <= kMaxTargetSize && fb.height <= kMaxTargetSize);
  im.tile = config_.tile_size;
  im.tiles_x = (fb.width + im.tile - 1) / im.tile;
  im.tiles_y = (fb.height + im.tile - 1) / im.tile;
  im.gx = 1.0f + 2.0f * kGuardBand / fb.width;
  im.gy = 1.0f + 2.0f * kGuardBand / fb.height;
  im.tris.clear();
  im.vary.clear();
  im.clip_arena.clear();
  im.planes.clear();
  im.bins.resize(size_t(im.tiles_x) * im.tiles_y);
  for (size_t d = 0; d < draws.size(); ++d) im.setup_draw(static_cast<int>(d), draws[d]);
  im.bin();
  const auto t1 = Clock::now();

  while (static_cast<int>(im.workers.size()) < pool_.size())
    im.workers.push_back(std::make_unique<Worker>());
  for (auto& w : im.workers) {
    w->counters = WorkCounters{};
    w->quads = 0;
  }
  const TileGrid grid = im.grid();
  pool_.run(im.tiles_x * im.tiles_y, [&](int tile, int worker) {
    Worker& w = *im.workers[worker];
    if (clear) im.clear_tile(fb, *clear, tile);
    raster_tile(grid, w, fb, draws, tile);
  });
  for (auto& w : im.workers) {
    im.stats.work += w->counters;
    im.stats.quads += w->quads;
  }
  const auto t2 = Clock::now();
  im.stats.setup_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  im.stats.raster_ms = std::chrono::duration<double, std::milli>(t2 - t1).count();
  return im.stats;
}

void transform_positions(const glm::mat4& mvp, std::span<const glm::vec3> positions,
                         std::vector<glm::vec4>& clip) {
  clip.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) clip[i] = mvp * glm::vec4(positions[i], 1.0f);
}

bool cpu_triangle_planes(const glm::vec4 clip[3], const float* const varyings[3], int num_varyings,
                         int width, int height, CpuTrianglePlanes& out) {
  CHECK_LE(num_varyings, kMaxVaryings);
  out.parts.clear();
  const int nv = num_varyings;
  const float gx = 1.0f + 2.0f * kGuardBand / width, gy = 1.0f + 2.0f * kGuardBand / height;
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
