#include "rasterizer/pipeline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace relief {
namespace {

constexpr int kW = 160, kH = 120;

// Counts covered fragments per pixel; never writes depth.
struct Counter {
  std::vector<int> count = std::vector<int>(kW * kH, 0);
};
void count_shader(const void* user, const FragmentPacket& p, FragmentOutput& out, WorkCounters&) {
  auto* c = static_cast<Counter*>(const_cast<void*>(user));
  for (int lane = 0; lane < p.num_quads * 4; ++lane) {
    out.depth[lane] = 0.0f;
    if (!p.lane_covered(lane)) continue;
    const int x = static_cast<int>(p.frag_x[lane]), y = static_cast<int>(p.frag_y[lane]);
    c->count[y * kW + x]++;
  }
}

// Screen position (pixels, y down) -> clip position with depth 0.5 and the given w.
glm::vec4 to_clip(glm::dvec2 s, double w) {
  const double x = s.x / kW * 2.0 - 1.0, y = 1.0 - s.y / kH * 2.0;
  return glm::vec4(static_cast<float>(x * w), static_cast<float>(y * w),
                   static_cast<float>(0.5 * w), static_cast<float>(w));
}

// A draw that shades every covered fragment (no culling, no depth write, no colour) with a
// shader that records what it sees in `user`; returns the pass's counters.
RasterStats draw_recording(ThreadPool& pool, int tile, const std::vector<glm::vec4>& clip,
                           const std::vector<float>& vary, int num_varyings,
                           const std::vector<uint32_t>& idx, PacketShader shader, void* user) {
  DrawCall dc;
  dc.clip = clip;
  dc.varyings = vary;
  dc.num_varyings = num_varyings;
  dc.indices = idx;
  dc.cull = CullMode::kNone;
  dc.depth_test = DepthTest::kLate;
  dc.depth_write = false;
  dc.color_write = false;
  dc.shader = shader;
  dc.user = user;
  Framebuffer fb(kW, kH);
  Rasterizer r(pool, RasterConfig{tile});
  return r.draw(fb, std::span<const DrawCall>(&dc, 1));
}

std::vector<int> rasterize_count(ThreadPool& pool, const std::vector<glm::vec4>& clip,
                                 const std::vector<uint32_t>& idx, int tile = 64) {
  Counter c;
  draw_recording(pool, tile, clip, {}, 0, idx, &count_shader, &c);
  return c.count;
}

// Inside test for a convex polygon (counter-clockwise or clockwise), with a tolerance band.
int classify(const std::vector<glm::dvec2>& poly, glm::dvec2 p) {
  double mn = 1e30, mx = -1e30;
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
    const glm::dvec2 e = b - a;
    const double d = (e.x * (p.y - a.y) - e.y * (p.x - a.x)) / glm::length(e);
    mn = std::min(mn, d);
    mx = std::max(mx, d);
  }
  if (mn > 1e-6 || mx < -1e-6) return (mn > 1e-6 || mx < -1e-6) && (mn > 0 || mx < 0) ? 1 : 0;
  return (mn < -1e-6 && mx > 1e-6) ? 0 : -1;  // outside, or on the boundary
}

double snap(double v) {
  return std::round(v * 256.0) / 256.0;
}

TEST(Pipeline, WatertightRotatedGridsWithRandomW) {
  ThreadPool pool(2);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3), wdist(0.1, 4.0);
  for (int rot = 0; rot <= 90; rot += 15) {
    const double a = rot * M_PI / 180.0;
    const glm::dvec2 c(80.3, 60.7);
    const int n = 7;  // n x n cells
    const double half = 45.0;
    std::vector<glm::dvec2> screen;
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        glm::dvec2 p(-half + 2 * half * i / n, -half + 2 * half * j / n);
        const bool border = i == 0 || j == 0 || i == n || j == n;
        if (!border) p += glm::dvec2(jitter(rng), jitter(rng)) * (2 * half / n);
        const glm::dvec2 r(p.x * std::cos(a) - p.y * std::sin(a),
                           p.x * std::sin(a) + p.y * std::cos(a));
        screen.push_back({snap(c.x + r.x), snap(c.y + r.y)});
      }
    std::vector<glm::vec4> clip;
    for (auto& s : screen) clip.push_back(to_clip(s, wdist(rng)));
    std::vector<uint32_t> idx;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const uint32_t v = j * (n + 1) + i;
        // alternate diagonals and windings
        if ((i + j) & 1)
          idx.insert(idx.end(), {v, v + 1, v + n + 2, v, v + n + 2, v + n + 1});
        else
          idx.insert(idx.end(), {v, v + n + 1, v + 1, v + 1, v + n + 1, v + n + 2});
      }
    const std::vector<glm::dvec2> outline = {screen[0], screen[n], screen[(n + 1) * (n + 1) - 1],
                                             screen[n * (n + 1)]};
    for (int tile : {16, 64}) {
      const auto count = rasterize_count(pool, clip, idx, tile);
      int inside = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const int k = classify(outline, {x + 0.5, y + 0.5});
          const int got = count[y * kW + x];
          ASSERT_LE(got, 1) << "pixel (" << x << "," << y << ") covered twice, rotation " << rot;
          if (k == 1) {
            ASSERT_EQ(got, 1) << "hole at (" << x << "," << y << "), rotation " << rot;
            ++inside;
          } else if (k == 0) {
            ASSERT_EQ(got, 0) << "pixel (" << x << "," << y << ") outside covered";
          }
        }
      EXPECT_GT(inside, 1000);
    }
  }
}

TEST(Pipeline, WatertightFans) {
  ThreadPool pool(2);
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> jitter(-8.0, 8.0), wdist(0.1, 4.0);
  for (int trial = 0; trial < 10; ++trial) {
    const int k = 5 + trial;
    std::vector<glm::dvec2> ring;
    for (int i = 0; i < k; ++i) {
      const double a = 2 * M_PI * i / k + trial * 0.1;
      ring.push_back({snap(80 + 50 * std::cos(a)), snap(60 + 50 * std::sin(a))});
    }
    const glm::dvec2 centre(snap(80 + jitter(rng)), snap(60 + jitter(rng)));
    std::vector<glm::vec4> clip = {to_clip(centre, wdist(rng))};
    for (auto& r : ring) clip.push_back(to_clip(r, wdist(rng)));
    std::vector<uint32_t> idx;
    for (int i = 0; i < k; ++i) idx.insert(idx.end(), {0u, 1u + i, 1u + (i + 1) % k});
    const auto count = rasterize_count(pool, clip, idx);
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const int c = classify(ring, {x + 0.5, y + 0.5});
        const int got = count[y * kW + x];
        ASSERT_LE(got, 1);
        if (c == 1) {
          ASSERT_EQ(got, 1) << "hole at " << x << "," << y << " trial " << trial;
        }
        if (c == 0) {
          ASSERT_EQ(got, 0);
        }
      }
  }
}

TEST(Pipeline, WatertightAcrossTheNearPlane) {
  ThreadPool pool(2);
  // A ground grid seen by a low perspective camera: the rows nearest the eye cross the near plane.
  const glm::mat4 proj = [] {
    const float f = 1.0f / std::tan(0.5f), n = 0.5f, fa = 50.0f;
    glm::mat4 m(0.0f);
    m[0][0] = f * kH / kW;
    m[1][1] = f;
    m[2][2] = n / (fa - n);
    m[2][3] = -1.0f;
    m[3][2] = n * fa / (fa - n);
    return m;
  }();
  const glm::mat4 vp =
      proj * glm::lookAt(glm::vec3(0, 1, 0), glm::vec3(0, 0.2f, -3), glm::vec3(0, 1, 0));
  const int n = 12;
  std::vector<glm::vec4> clip;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      clip.push_back(vp * glm::vec4(-4 + 8.0f * i / n, 0, 1 - 9.0f * j / n, 1));
  std::vector<uint32_t> idx;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t v = j * (n + 1) + i;
      idx.insert(idx.end(), {v, v + 1, v + n + 2, v, v + n + 2, v + n + 1});
    }
  int crossing = 0;
  for (auto& c : clip) crossing += c.z > c.w;
  ASSERT_GT(crossing, 0);  // the test really clips
  const auto count = rasterize_count(pool, clip, idx);
  // The same surface as two big triangles.
  std::vector<glm::vec4> big = {clip[0], clip[n], clip[(n + 1) * (n + 1) - 1], clip[n * (n + 1)]};
  const auto ref = rasterize_count(pool, big, {0, 1, 2, 0, 2, 3});
  int interior = 0;
  for (int y = 1; y + 1 < kH; ++y)
    for (int x = 1; x + 1 < kW; ++x) {
      ASSERT_LE(count[y * kW + x], 1);
      bool all = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) all &= ref[(y + dy) * kW + x + dx] == 1;
      if (all) {
        ASSERT_EQ(count[y * kW + x], 1) << "hole at " << x << "," << y;
        ++interior;
      }
    }
  EXPECT_GT(interior, kW * kH / 4);
}

TEST(Pipeline, TopLeftRuleOnPixelCentres) {
  ThreadPool pool(1);
  // Square with corners on the centres of pixels (2,2) and (6,6): the top and left edges are in,
  // the bottom and right edges out, so exactly pixels 2..5 x 2..5 are covered, once.
  const glm::dvec2 p[4] = {{2.5, 2.5}, {6.5, 2.5}, {6.5, 6.5}, {2.5, 6.5}};
  std::vector<glm::vec4> clip;
  for (auto& s : p) clip.push_back(to_clip(s, 1.0));
  for (const std::vector<uint32_t>& idx :
       {std::vector<uint32_t>{0, 1, 2, 0, 2, 3}, std::vector<uint32_t>{0, 2, 1, 0, 3, 2},
        std::vector<uint32_t>{0, 1, 3, 1, 2, 3}}) {
    const auto count = rasterize_count(pool, clip, idx);
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x) {
        const int expect = (x >= 2 && x <= 5 && y >= 2 && y <= 5) ? 1 : 0;
        EXPECT_EQ(count[y * kW + x], expect) << x << "," << y;
      }
  }
}

TEST(Pipeline, DegenerateTrianglesAreDroppedWithoutCrash) {
  ThreadPool pool(2);
  const float nan = std::nanf("");
  const float inf = INFINITY;
  std::vector<glm::vec4> clip = {
      {0, 0, 0.5f, 1},         {0.5f, 0, 0.5f, 1},     {1, 0, 0.5f, 1},     // collinear: zero area
      {nan, 0, 0.5f, 1},       {0.5f, 0.5f, 0.5f, 1},  {0, 0.5f, 0.5f, 1},  // NaN
      {inf, 0, 0.5f, 1},       {0, 0, 0.5f, 1},        {0, 0.3f, 0.5f, 1},  // Inf
      {-1e7f, -1e7f, 0.5f, 1}, {1e7f, -1e7f, 0.5f, 1}, {0, 1e7f, 0.5f, 1},  // huge: covers all
  };
  std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 0, 1, 99};
  const auto count = rasterize_count(pool, clip, idx);
  for (int v : count) ASSERT_EQ(v, 1);  // only the huge one, clipped to the guard band
}

// Varying 0 = u of a plane seen in perspective; compare with a ray-plane intersection.
void write_u(const void*, const FragmentPacket& p, FragmentOutput& out, WorkCounters&) {
  for (int l = 0; l < p.num_quads * 4; ++l) {
    out.color[0][l] = p.varyings[0][l];
    out.color[1][l] = p.varyings[1][l];
    out.color[2][l] = 0;
    out.color[3][l] = 1;
  }
}

TEST(Pipeline, PerspectiveCorrectInterpolation) {
  ThreadPool pool(2);
  // One triangle given by snapped screen positions and very different w; the exact answer is the
  // barycentric coordinate of the hit of the pixel's ray with the triangle in (x, y, w) space.
  const glm::dvec2 s[3] = {
      {snap(5.3), snap(7.1)}, {snap(151.7), snap(20.2)}, {snap(40.4), snap(113.9)}};
  const double w[3] = {0.2, 3.7, 1.1};
  const float U[3] = {0.0f, 1.0f, 0.25f}, V[3] = {0.1f, 0.0f, 1.0f};
  std::vector<glm::vec4> clip;
  std::vector<float> vary;
  glm::dvec3 q[3];
  for (int i = 0; i < 3; ++i) {
    clip.push_back(to_clip(s[i], w[i]));
    q[i] = glm::dvec3(double(clip[i].x), double(clip[i].y), double(clip[i].w));
    vary.push_back(U[i]);
    vary.push_back(V[i]);
  }
  std::vector<uint32_t> idx = {0, 1, 2};
  DrawCall dc;
  dc.clip = clip;
  dc.varyings = vary;
  dc.num_varyings = 2;
  dc.indices = idx;
  dc.cull = CullMode::kNone;
  dc.shader = &write_u;
  Framebuffer fb(kW, kH);
  Rasterizer r(pool);
  r.draw(fb, std::span<const DrawCall>(&dc, 1));
  const glm::dvec3 nrm = glm::cross(q[1] - q[0], q[2] - q[0]);
  double worst = 0;
  int checked = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (fb.depth.at(x, y) == 0.0f) continue;
      const glm::dvec3 dir((x + 0.5) / kW * 2 - 1, 1 - (y + 0.5) / kH * 2, 1.0);
      const glm::dvec3 hit = dir * (glm::dot(q[0], nrm) / glm::dot(dir, nrm));
      const double area = glm::dot(glm::cross(q[1] - q[0], q[2] - q[0]), nrm);
      const double l1 = glm::dot(glm::cross(hit - q[0], q[2] - q[0]), nrm) / area;
      const double l2 = glm::dot(glm::cross(q[1] - q[0], hit - q[0]), nrm) / area;
      const double l0 = 1 - l1 - l2;
      const double u = l0 * U[0] + l1 * U[1] + l2 * U[2], v = l0 * V[0] + l1 * V[1] + l2 * V[2];
      const glm::vec4 c = fb.color.at(x, y);
      worst = std::max({worst, std::fabs(c.x - u) / std::max(std::fabs(u), 1e-2),
                        std::fabs(c.y - v) / std::max(std::fabs(v), 1e-2)});
      ++checked;
    }
  EXPECT_GT(checked, 2000);
  EXPECT_LT(worst, 1e-4);
}

// Solid colour from user data; depth = polygon depth (for the late path).
struct Solid {
  glm::vec4 color;
  bool farther = false;  // conservative path: push depth slightly farther
};
void solid_shader(const void* user, const FragmentPacket& p, FragmentOutput& out, WorkCounters&) {
  const auto* s = static_cast<const Solid*>(user);
  for (int l = 0; l < p.num_quads * 4; ++l) {
    for (int k = 0; k < 4; ++k) out.color[k][l] = s->color[k];
    out.depth[l] = s->farther ? p.frag_z[l] * 0.999f : p.frag_z[l];
  }
}

// Three overlapping triangles at reversed-Z depths 0.3, 0.7 and 0.5, in that order.
void overlapping_triangles(std::vector<glm::vec4>& clip, std::vector<uint32_t>& idx) {
  const float depth[3] = {0.3f, 0.7f, 0.5f};
  for (int t = 0; t < 3; ++t) {
    const float ox = -0.5f + 0.4f * t;
    clip.push_back({ox - 0.6f, -0.7f, depth[t], 1});
    clip.push_back({ox + 0.7f, -0.6f, depth[t], 1});
    clip.push_back({ox, 0.8f, depth[t], 1});
    idx.insert(idx.end(), {uint32_t(3 * t), uint32_t(3 * t + 1), uint32_t(3 * t + 2)});
  }
}

Framebuffer overlap_scene(ThreadPool& pool, DepthTest mode, bool farther) {
  std::vector<glm::vec4> clip;
  std::vector<uint32_t> idx;
  overlapping_triangles(clip, idx);
  std::vector<float> vary;
  static Solid colors[3] = {{{1, 0, 0, 1}}, {{0, 1, 0, 1}}, {{0, 0, 1, 1}}};
  std::vector<DrawCall> draws;
  for (int t = 0; t < 3; ++t) {
    colors[t].farther = farther;
    DrawCall dc;
    dc.clip = clip;
    dc.varyings = vary;
    dc.indices = std::span<const uint32_t>(idx).subspan(3 * t, 3);
    dc.depth_test = mode;
    dc.shader = &solid_shader;
    dc.user = &colors[t];
    draws.push_back(dc);
  }
  Framebuffer fb(kW, kH);
  Rasterizer r(pool, RasterConfig{32});
  r.draw(fb, draws);
  return fb;
}

TEST(Pipeline, EarlyAndLateDepthAgreeAndReversedZOrders) {
  ThreadPool pool(2);
  const Framebuffer early = overlap_scene(pool, DepthTest::kEarly, false);
  const Framebuffer late = overlap_scene(pool, DepthTest::kLate, false);
  int green = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      ASSERT_EQ(early.color.at(x, y), late.color.at(x, y));
      ASSERT_EQ(early.depth.at(x, y), late.depth.at(x, y));
      // Green (depth 0.7, nearest in reversed-Z) is never overdrawn by red or blue.
      if (early.depth.at(x, y) > 0.69f) {
        ASSERT_EQ(early.color.at(x, y), glm::vec4(0, 1, 0, 1));
        ++green;
      }
    }
  EXPECT_GT(green, 100);
  // Conservative (depth only moves farther) agrees with the late path on the same shader.
  const Framebuffer cons = overlap_scene(pool, DepthTest::kConservative, true);
  const Framebuffer late2 = overlap_scene(pool, DepthTest::kLate, true);
  for (size_t i = 0; i < cons.color.pixels.size(); ++i) {
    ASSERT_EQ(cons.color.pixels[i], late2.color.pixels[i]);
    ASSERT_EQ(cons.depth.values[i], late2.depth.values[i]);
  }
}

// A colour per pixel and channel from the pixel's position, with NaN, infinities and -0 in some
// channels; depth the polygon's.
void pattern_shader(const void*, const FragmentPacket& p, FragmentOutput& out, WorkCounters&) {
  const float inf = std::numeric_limits<float>::infinity();
  const float special[4] = {std::numeric_limits<float>::quiet_NaN(), inf, -inf, -0.0f};
  for (int l = 0; l < p.num_quads * 4; ++l) {
    const int x = static_cast<int>(p.frag_x[l]), y = static_cast<int>(p.frag_y[l]);
    for (int k = 0; k < 4; ++k) {
      const int pick = (x + 2 * y + 3 * k) % 11;
      out.color[k][l] = pick < 4 ? special[pick] : static_cast<float>((x * 7 + y * 13) * 4 + k);
    }
    out.depth[l] = p.frag_z[l];
  }
}

// The three overlapping triangles as one draw through pattern_shader, and the clear it is drawn
// over.
struct PatternDraw {
  std::vector<glm::vec4> clip;
  std::vector<uint32_t> idx;
  std::vector<float> vary;
  PatternDraw() { overlapping_triangles(clip, idx); }
  DrawCall draw(DepthTest mode) const {
    DrawCall dc;
    dc.clip = clip;
    dc.varyings = vary;
    dc.indices = idx;
    dc.depth_test = mode;
    dc.shader = &pattern_shader;
    return dc;
  }
};
const ClearValues kPatternClear{glm::vec4(0.25f, 0.5f, 0.75f, 1.0f), 0.0f};

// Fully covered quads of a draw that tests depth early and writes colour without blending are
// written four lanes at a time (raster_tile.cpp write_full_quad); every other fragment lane by
// lane. Both must store each lane's colour at its own pixel, non-finite channels as 0, and the
// same depth: the early draw against the same triangles through the per-lane path (a
// conservative depth test, the shader's depth being the polygon's), bit for bit.
TEST(Pipeline, QuadWritesEqualLaneWrites) {
  ThreadPool pool(2);
  const PatternDraw pattern;
  auto render = [&](DepthTest mode, RasterStats* stats) {
    const DrawCall dc = pattern.draw(mode);
    Framebuffer fb(kW, kH);
    Rasterizer r(pool, RasterConfig{32});
    *stats = r.draw(fb, std::span<const DrawCall>(&dc, 1), &kPatternClear);
    return fb;
  };
  RasterStats quads, lanes;
  const Framebuffer a = render(DepthTest::kEarly, &quads);
  const Framebuffer b = render(DepthTest::kConservative, &lanes);
  EXPECT_EQ(quads.work.fragments, lanes.work.fragments);
  ASSERT_EQ(a.color.pixels.size(), b.color.pixels.size());
  EXPECT_EQ(std::memcmp(a.color.pixels.data(), b.color.pixels.data(),
                        a.color.pixels.size() * sizeof(glm::vec4)),
            0);
  EXPECT_EQ(std::memcmp(a.depth.values.data(), b.depth.values.data(),
                        a.depth.values.size() * sizeof(float)),
            0);
  // What was drawn: each covered pixel holds its own pattern, NaN and infinities as 0.
  int drawn = 0, zeroed = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (a.depth.at(x, y) == 0.0f) {
        ASSERT_EQ(a.color.at(x, y), glm::vec4(0.25f, 0.5f, 0.75f, 1.0f));
        continue;
      }
      ++drawn;
      for (int k = 0; k < 4; ++k) {
        const int pick = (x + 2 * y + 3 * k) % 11;
        const float want =
            pick < 3 ? 0.0f : (pick == 3 ? -0.0f : static_cast<float>((x * 7 + y * 13) * 4 + k));
        const float got = a.color.at(x, y)[k];
        ASSERT_EQ(std::signbit(got), std::signbit(want)) << x << "," << y;
        ASSERT_EQ(got, want) << x << "," << y << " channel " << k;
        zeroed += pick < 3;
      }
    }
  EXPECT_GT(drawn, 5000);
  EXPECT_GT(zeroed, 1000);
}

// Drawing on demand (Rasterizer::prepare, draw_tile, finish): tiles asked for from several
// threads at once, each tile by several of them, come out as draw() draws them, each drawn once
// (the counters are draw()'s), and the tiles never asked for keep what the target held.
TEST(Pipeline, TilesDrawnOnDemandEqualTheWholeDrawAndAreDrawnOnce) {
  ThreadPool pool(4);
  const PatternDraw pattern;
  const DrawCall dc = pattern.draw(DepthTest::kConservative);
  const std::span<const DrawCall> draws(&dc, 1);
  const ClearValues& clear = kPatternClear;
  for (int tile : {8, 32, 48}) {
    Framebuffer whole(kW, kH);
    const RasterStats ref = Rasterizer(pool, RasterConfig{tile}).draw(whole, draws, &clear);
    Rasterizer r(pool, RasterConfig{tile});
    for (int round = 0; round < 2; ++round) {  // the second reuses the first's state
      Framebuffer fb(kW, kH);
      for (glm::vec4& c : fb.color.pixels) c = glm::vec4(9.0f);
      std::fill(fb.depth.values.begin(), fb.depth.values.end(), 0.125f);
      r.prepare(fb, draws, &clear);
      const int tiles = r.tiles_x() * r.tiles_y();
      ASSERT_EQ(r.tiles_x(), (kW + tile - 1) / tile);
      // round 0: every tile, each asked for by 4 tasks; round 1: the even tiles only
      const int step = round == 0 ? 1 : 2;
      pool.run(4 * tiles, [&](int task, int) {
        const int t = task % tiles;
        if (t % step == 0) r.draw_tile(t);
      });
      const RasterStats got = r.finish();
      if (round == 0) {
        EXPECT_EQ(got.work.fragments, ref.work.fragments) << "tile " << tile;
        EXPECT_EQ(got.quads, ref.quads);
        EXPECT_EQ(got.triangles_binned, ref.triangles_binned);
      } else {
        EXPECT_LT(got.work.fragments, ref.work.fragments);
      }
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const int t = (y / tile) * r.tiles_x() + x / tile;
          const bool drawn = t % step == 0;
          ASSERT_EQ(r.drawn()[t].load(), drawn ? 1 : 0);
          const glm::vec4 want_c = drawn ? whole.color.at(x, y) : glm::vec4(9.0f);
          const float want_z = drawn ? whole.depth.at(x, y) : 0.125f;
          ASSERT_EQ(std::memcmp(&fb.color.at(x, y), &want_c, sizeof want_c), 0) << x << "," << y;
          ASSERT_EQ(fb.depth.at(x, y), want_z) << x << "," << y;
        }
    }
  }
}

// Tiles are drawn in a copy of their pixels (raster_tile.cpp TilePixels) and written back: a draw
// without a clear starts from what the target held, keeps every pixel no fragment reaches, and
// with a clear replaces all of them; for every tile size, including ones that leave partial tiles.
TEST(Pipeline, TilesStartFromTheTargetOrTheClearAndWriteBackEveryPixel) {
  ThreadPool pool(2);
  std::vector<glm::vec4> clip = {
      {-0.5f, -0.5f, 0.5f, 1}, {0.6f, -0.4f, 0.5f, 1}, {0, 0.7f, 0.5f, 1}};
  std::vector<uint32_t> idx = {0, 1, 2};
  std::vector<float> vary;
  Solid s{{0.5f, 0.25f, 1.0f, 1.0f}};
  for (int tile : {8, 26, 64, 512}) {
    for (bool clear : {false, true}) {
      Framebuffer fb(kW, kH);
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          fb.color.at(x, y) = glm::vec4(float(x), float(y), 0.0f, 1.0f);
          fb.depth.at(x, y) = x == 3 * y ? 0.9f : 0.1f;  // a line the triangle cannot pass
        }
      DrawCall dc;
      dc.clip = clip;
      dc.varyings = vary;
      dc.indices = idx;
      dc.cull = CullMode::kNone;
      dc.shader = &solid_shader;
      dc.user = &s;
      Rasterizer r(pool, RasterConfig{tile});
      const ClearValues cv{glm::vec4(0.0f, 0.0f, 0.0f, 0.5f), 0.0f};
      const RasterStats st = r.draw(fb, std::span<const DrawCall>(&dc, 1), clear ? &cv : nullptr);
      const std::vector<int> covered = rasterize_count(pool, clip, idx, tile);
      int drawn = 0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const bool blocked = !clear && x == 3 * y;
          const bool hit = covered[y * kW + x] > 0 && !blocked;
          const glm::vec4 before = clear ? cv.color : glm::vec4(float(x), float(y), 0.0f, 1.0f);
          const float depth_before = clear ? cv.depth : (x == 3 * y ? 0.9f : 0.1f);
          ASSERT_EQ(fb.color.at(x, y), hit ? s.color : before) << tile << " " << x << "," << y;
          ASSERT_EQ(fb.depth.at(x, y), hit ? 0.5f : depth_before) << tile << " " << x << "," << y;
          drawn += hit;
        }
      EXPECT_GT(drawn, 3000);
      EXPECT_GE(st.work.fragments, static_cast<uint64_t>(drawn));
    }
  }
}

TEST(Pipeline, BackFaceCulling) {
  ThreadPool pool(1);
  std::vector<glm::vec4> clip = {
      {-0.5f, -0.5f, 0.5f, 1}, {0.5f, -0.5f, 0.5f, 1}, {0, 0.5f, 0.5f, 1}};
  std::vector<uint32_t> ccw = {0, 1, 2}, cw = {0, 2, 1};
  std::vector<float> vary;
  Solid s{{1, 1, 1, 1}};
  for (auto [idx, cull, expect] :
       {std::tuple{&ccw, CullMode::kBack, true}, std::tuple{&cw, CullMode::kBack, false},
        std::tuple{&ccw, CullMode::kFront, false}, std::tuple{&cw, CullMode::kNone, true}}) {
    DrawCall dc;
    dc.clip = clip;
    dc.varyings = vary;
    dc.indices = *idx;
    dc.cull = cull;
    dc.shader = &solid_shader;
    dc.user = &s;
    Framebuffer fb(kW, kH);
    Rasterizer r(pool);
    const RasterStats st = r.draw(fb, std::span<const DrawCall>(&dc, 1));
    EXPECT_EQ(st.work.fragments > 0, expect);
  }
}

// Records, per pixel, the ids (varying 0, constant over each triangle) of the triangles that
// covered it, in the order the shader saw them.
struct OrderLog {
  std::vector<std::vector<int>> ids = std::vector<std::vector<int>>(kW * kH);
};

void log_shader(const void* user, const FragmentPacket& p, FragmentOutput& out, WorkCounters&) {
  auto* log = static_cast<OrderLog*>(const_cast<void*>(user));
  for (int lane = 0; lane < p.num_quads * 4; ++lane) {
    out.depth[lane] = 0.0f;
    if (!p.lane_covered(lane)) continue;
    const int x = static_cast<int>(p.frag_x[lane]), y = static_cast<int>(p.frag_y[lane]);
    log->ids[y * kW + x].push_back(static_cast<int>(std::lround(p.varyings[0][lane])));
  }
}

// The setup runs in segments of triangles on every thread and each segment bins its own; tiles
// must still see every pixel's triangles in submission order, whatever the threads and tiles.
TEST(Pipeline, ManySegmentsKeepSubmissionOrderForAnyThreadCountAndTile) {
  constexpr int kTriangles = 100000;  // more than three setup segments
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.0, kW), uy(0.0, kH), r(1.0, 6.0), a(0.0, 6.2832);
  std::vector<glm::vec4> clip;
  std::vector<float> vary;
  std::vector<uint32_t> idx;
  for (int t = 0; t < kTriangles; ++t) {
    const glm::dvec2 c(ux(rng), uy(rng));
    const double a0 = a(rng);
    for (int k = 0; k < 3; ++k) {
      const double ak = a0 + k * 2.0944, rk = r(rng);
      clip.push_back(to_clip(c + rk * glm::dvec2(std::cos(ak), std::sin(ak)), 1.0));
      vary.push_back(static_cast<float>(t));
      idx.push_back(static_cast<uint32_t>(idx.size()));
    }
  }
  std::vector<std::vector<int>> first;
  for (auto [threads, tile] :
       {std::pair{1, 64}, std::pair{2, 16}, std::pair{3, 64}, std::pair{2, 512}}) {
    SCOPED_TRACE(::testing::Message() << threads << " threads, tile " << tile);
    ThreadPool pool(threads);
    OrderLog log;
    const RasterStats st = draw_recording(pool, tile, clip, vary, 1, idx, &log_shader, &log);
    EXPECT_EQ(st.triangles_in, static_cast<uint64_t>(kTriangles));
    size_t fragments = 0;
    for (const std::vector<int>& ids : log.ids) {
      fragments += ids.size();
      ASSERT_TRUE(std::is_sorted(ids.begin(), ids.end()));
    }
    EXPECT_GT(fragments, static_cast<size_t>(kTriangles));
    if (first.empty())
      first = log.ids;
    else
      EXPECT_EQ(log.ids, first);
  }
}

}  // namespace
}  // namespace relief
