#include "bake/cone_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "tests/sanitized.h"

namespace relief {
namespace {

Texture map_from(int w, int h, const std::function<float(int, int)>& d) {
  std::vector<float> v(static_cast<size_t>(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) v[y * w + x] = d(x, y);
  return Texture::from_floats(TexFormat::kR32F, w, h, v.data());
}

Texture random_map(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(static_cast<size_t>(w) * h);
  for (float& x : v) x = u(rng);
  return Texture::from_floats(TexFormat::kR32F, w, h, v.data());
}

// Smooth bumps plus noise: long cones and long relaxed marches.
Texture bumpy_map(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  return map_from(w, h, [&](int x, int y) {
    const float fu = (x + 0.5f) / w, fv = (y + 0.5f) / h;
    float d = 0.5f + 0.25f * std::sin(6.2831853f * 2 * fu) * std::cos(6.2831853f * 3 * fv);
    return std::clamp(d + 0.05f * u(rng), 0.0f, 1.0f);
  });
}

// Deep floor with one-texel walls at depth 0.1 every 7 columns and a ring of shallow texels.
Texture walls_map(int w, int h) {
  return map_from(w, h, [&](int x, int y) {
    if (x % 7 == 3) return 0.1f;
    if (y == h / 2 && x % 2 == 0) return 0.3f;
    return 0.9f;
  });
}

Texture spike_map(int w, int h, int sx, int sy) {
  return map_from(w, h, [&](int x, int y) { return (x == sx && y == sy) ? 0.0f : 1.0f; });
}

struct Case {
  std::string name;
  Texture depth;
};

// The 64 x 64 maps cost 16 times a 32 x 32 one in the brute force: a sanitizer build
// (tests/sanitized.h) compares the smaller maps only.
std::vector<Case> cases() {
  std::vector<Case> c;
  const bool big = !test::kSanitizedBuild;
  c.push_back({"random32", random_map(32, 32, 1)});
  if (big) c.push_back({"random64", random_map(64, 64, 2)});
  if (big) c.push_back({"bumpy64", bumpy_map(64, 64, 3)});
  c.push_back({"walls32", walls_map(32, 32)});
  if (big) c.push_back({"walls64", walls_map(64, 64)});
  c.push_back({"spike32", spike_map(32, 32, 13, 20)});
  c.push_back({"pattern32", make_pattern_depth(32)});
  if (big) c.push_back({"pattern64", make_pattern_depth(64)});
  c.push_back({"flat32", map_from(32, 32, [](int, int) { return 0.0f; })});
  c.push_back({"deep32", map_from(32, 32, [](int, int) { return 1.0f; })});
  c.push_back({"nonsquare48x20", bumpy_map(48, 20, 4)});
  c.push_back({"npot37x29", random_map(37, 29, 5)});
  return c;
}

void expect_same(const ConeRatios& a, const ConeRatios& b, const std::string& what) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.channels, b.channels);
  int bad = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < a.channels; ++c)
        if (a.at(x, y, c) != b.at(x, y, c) && bad++ < 5)
          ADD_FAILURE() << what << " texel " << x << "," << y << " ch " << c << ": fast "
                        << a.at(x, y, c) << " brute " << b.at(x, y, c);
  EXPECT_EQ(bad, 0) << what;
}

void fast_equals_brute(ConeKind kind, bool bilinear = false) {
  for (const Case& c : cases())
    for (bool wrap : {false, true}) {
      ConeBakeOptions o;
      o.kind = kind;
      o.wrap = wrap;
      o.bilinear = bilinear;
      o.threads = 2;
      expect_same(bake_cone_ratios(c.depth, o), bake_cone_ratios_brute_force(c.depth, o),
                  c.name + (wrap ? " wrap" : " clamp"));
    }
}

TEST(ConeMap, ConservativeFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kConservative);
}
TEST(ConeMap, QuadFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kQuad);
}
TEST(ConeMap, RelaxedFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kRelaxed);
}

TEST(ConeMap, BilinearConservativeFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kConservative, true);
}
TEST(ConeMap, BilinearQuadFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kQuad, true);
}
TEST(ConeMap, BilinearRelaxedFastEqualsBruteForce) {
  fast_equals_brute(ConeKind::kRelaxed, true);
}

// Bilinear depth of the map (GL LINEAR at level 0, clamp or repeat) at texel-space point (px, py).
double bilinear_depth(const Texture& d, bool wrap, double px, double py) {
  const int w = d.width(), h = d.height();
  auto at = [&](int x, int y) {
    if (wrap) {
      x = ((x % w) + w) % w;
      y = ((y % h) + h) % h;
    } else {
      x = std::clamp(x, 0, w - 1);
      y = std::clamp(y, 0, h - 1);
    }
    return static_cast<double>(d.fetch_r(0, x, y));
  };
  const double x = px - 0.5, y = py - 0.5, fx = std::floor(x), fy = std::floor(y);
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const double a = x - fx, b = y - fy;
  const double top = at(ix, iy) + a * (at(ix + 1, iy) - at(ix, iy));
  const double bot = at(ix, iy + 1) + a * (at(ix + 1, iy + 1) - at(ix, iy + 1));
  return top + b * (bot - top);
}

// The bilinear-safe and the texel-point maps of one kind.
struct BilinearAndPoint {
  ConeRatios bilinear, point;
};
BilinearAndPoint bake_both(const Texture& d, ConeKind kind, bool wrap) {
  ConeBakeOptions o;
  o.kind = kind;
  o.wrap = wrap;
  o.bilinear = true;
  BilinearAndPoint out;
  out.bilinear = bake_cone_ratios(d, o);
  o.bilinear = false;
  out.point = bake_cone_ratios(d, o);
  return out;
}

TEST(ConeMap, BilinearConesHoldNoBilinearSurfacePoint) {
  // Sampled definition check: for apexes (p, D(p)) anywhere in a texel's cell and surface points
  // (q, D(q)) on a fine grid of the bilinear surface, no q lies strictly inside the cone; the
  // texel-point cones, by contrast, do hold some (which is why the kernels need these).
  for (bool wrap : {false, true}) {
    const Texture d = bumpy_map(24, 20, 51);
    const BilinearAndPoint maps = bake_both(d, ConeKind::kConservative, wrap);
    const ConeRatios &r = maps.bilinear, &point = maps.point;
    int point_violations = 0;
    for (int y = 1; y < 20; y += 4)
      for (int x = 2; x < 24; x += 5)
        for (double sy : {0.05, 0.5, 0.95})
          for (double sx : {0.05, 0.5, 0.95}) {
            const double px = x + sx, py = y + sy, dp = bilinear_depth(d, wrap, px, py);
            for (double qy = 0.125; qy < 20; qy += 0.25)
              for (double qx = 0.125; qx < 24; qx += 0.25) {
                const double dq = bilinear_depth(d, wrap, qx, qy);
                if (!(dq < dp)) continue;
                const double D = std::hypot((qx - px) / 24.0, (qy - py) / 20.0);
                EXPECT_GE(D, r.at(x, y) * (dp - dq) * (1 - 1e-5)) << x << "," << y;
                point_violations += D < point.at(x, y) * (dp - dq) * (1 - 1e-5);
              }
          }
    EXPECT_GT(point_violations, 0);
  }
}

// Samples the segment of a ray from the axis point (p, t) of an apex (p, D(p)) to where it leaves
// the cone of ratio r (uv per unit depth; the ray's uv direction dir, its uv per unit depth s).
// Returns how often it comes out of the bilinear surface (inside, then outside) on the way.
int exits_inside_cone(const Texture& d, bool wrap, double px, double py, double t, double dirx,
                      double diry, double s, double r) {
  const int w = d.width(), h = d.height();
  const double a = bilinear_depth(d, wrap, px, py);
  // cone boundary: uv distance k s from the axis at depth t + k equals r (a - t - k)
  const double kmax = r * (a - t) / (s + r);
  int exits = 0;
  bool inside = false;
  const int n = test::sanitized_or(1000, 250);  // samples along the segment
  for (int i = 1; i <= n; ++i) {
    const double k = kmax * i / n;
    const double qx = px + dirx * k * s * w, qy = py + diry * k * s * h;
    if (!wrap && (qx < 0 || qy < 0 || qx > w || qy > h)) break;
    const bool in = t + k > bilinear_depth(d, wrap, qx, qy) + 1e-6;
    exits += inside && !in;
    inside = in;
  }
  return exits;
}

TEST(ConeMap, BilinearRelaxedConesLetNoRayOutOfTheSurface) {
  // The property relaxed cone stepping needs, on the bilinear surface the kernels sample: a ray
  // leaving the axis of any apex in a texel's cell, above the surface, in any direction and at any
  // slope, that enters the surface inside the cone does not come out of it inside the cone. The
  // chapter's texel-point relaxed cones break it (the thin-wall wrong layers of issue 22).
  for (bool wrap : {false, true}) {
    const Texture d = bumpy_map(24, 20, 51);
    const BilinearAndPoint maps = bake_both(d, ConeKind::kRelaxed, wrap);
    const ConeRatios &r = maps.bilinear, &point = maps.point;
    const ConeRatios cons = bake_both(d, ConeKind::kConservative, wrap).bilinear;
    const int dirs = test::sanitized_or(12, 4);
    int exits = 0, point_exits = 0, rays = 0;
    double wider = 0;  // mean ratio of the bilinear relaxed cone to the conservative one
    int sources = 0;
    for (int y = 1; y < 20; y += 3)
      for (int x = 1; x < 24; x += 3) {
        wider += r.at(x, y) / cons.at(x, y);
        ++sources;
        EXPECT_GE(r.at(x, y), cons.at(x, y)) << x << "," << y;
        for (double sy : {0.1, 0.5, 0.9})
          for (double sx : {0.1, 0.5, 0.9}) {
            const double px = x + sx, py = y + sy, a = bilinear_depth(d, wrap, px, py);
            for (double tf : {0.0, 0.8})
              for (int k = 0; k < dirs; ++k) {
                const double ang = 2 * M_PI * (k + 0.37) / dirs;
                for (double s : {0.02, 0.5}) {
                  ++rays;
                  exits += exits_inside_cone(d, wrap, px, py, tf * a, std::cos(ang), std::sin(ang),
                                             s, r.at(x, y));
                  point_exits += exits_inside_cone(d, wrap, px, py, tf * a, std::cos(ang),
                                                   std::sin(ang), s, point.at(x, y));
                }
              }
          }
      }
    EXPECT_EQ(exits, 0) << "of " << rays << " rays";
    if (!test::kSanitizedBuild) {
      EXPECT_GT(point_exits, 0);
    }
    std::cout << (wrap ? "wrap" : "clamp") << ": " << rays
              << " rays, texel-point relaxed cones let " << point_exits
              << " out; bilinear relaxed / bilinear conservative ratio, mean " << wider / sources
              << "\n";
  }
}

TEST(ConeMap, MaxRatioOtherThanOne) {
  Texture d = bumpy_map(24, 24, 9);
  for (ConeKind kind : {ConeKind::kConservative, ConeKind::kQuad, ConeKind::kRelaxed})
    for (float R : {0.25f, 2.5f})
      for (bool wrap : {false, true}) {
        ConeBakeOptions o;
        o.kind = kind;
        o.max_ratio = R;
        o.wrap = wrap;
        ConeRatios fast = bake_cone_ratios(d, o);
        expect_same(fast, bake_cone_ratios_brute_force(d, o),
                    std::string(cone_kind_name(kind)) + " R=" + std::to_string(R));
        EXPECT_LE(*std::max_element(fast.values.begin(), fast.values.end()), R);
      }
}

TEST(ConeMap, SpikeConservativeIsDistance) {
  // Deep floor (1) with one texel at the surface (0): every floor texel's cone is limited by the
  // spike alone, r = min(1, D); the spike itself gets the maximum.
  const int w = 32, h = 32, sx = 13, sy = 20;
  ConeBakeOptions o;
  o.kind = ConeKind::kConservative;
  ConeRatios r = bake_cone_ratios(spike_map(w, h, sx, sy), o);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (x == sx && y == sy) {
        EXPECT_EQ(r.at(x, y), 1.0f);
        continue;
      }
      const float D = std::hypot((x - sx) / float(w), (y - sy) / float(h));
      EXPECT_NEAR(r.at(x, y), std::min(1.0f, D), 1e-6f) << x << "," << y;
    }
}

TEST(ConeMap, SpikeRelaxedExitsBehindTheSpike) {
  // The ray from above a floor texel through the spike's top runs level (depth 0) and comes out
  // of the spike's cell at its far side: for an offset of k texels along u, t = 1 + 0.5 / k, so
  // r = t D / (1 - 0) = (k + 0.5) / w.
  const int w = 32, h = 32, sx = 13, sy = 20;
  ConeBakeOptions o;
  o.kind = ConeKind::kRelaxed;
  ConeRatios r = bake_cone_ratios(spike_map(w, h, sx, sy), o);
  for (int k = 1; k <= 12; ++k) {
    EXPECT_NEAR(r.at(sx - k, sy), (k + 0.5f) / w, 1e-6f) << k;
    EXPECT_NEAR(r.at(sx, sy - k), (k + 0.5f) / h, 1e-6f) << k;
  }
  // Diagonal: the ray passes the spike cell's corner, t = 1 + 0.5 / k.
  EXPECT_NEAR(r.at(sx + 3, sy + 3), 3.5f / 3.0f * std::hypot(3.0f / w, 3.0f / h), 1e-6f);
}

TEST(ConeMap, FlatAndDeepMapsGetTheMaximum) {
  for (float depth : {0.0f, 1.0f, 0.4f})
    for (ConeKind kind : {ConeKind::kConservative, ConeKind::kQuad, ConeKind::kRelaxed}) {
      ConeBakeOptions o;
      o.kind = kind;
      o.max_ratio = 0.75f;
      ConeRatios r = bake_cone_ratios(map_from(16, 9, [&](int, int) { return depth; }), o);
      for (float v : r.values) EXPECT_EQ(v, 0.75f);
    }
}

TEST(ConeMap, QuadHalfPlanesCoverTheConservativeCone) {
  // The +u and -u closed half-planes together hold every destination, so their minimum is the
  // conservative ratio (and likewise for +v, -v); each quad ratio is at least as wide.
  for (bool wrap : {false, true}) {
    Texture d = bumpy_map(40, 28, 11);
    ConeBakeOptions o;
    o.wrap = wrap;
    o.kind = ConeKind::kConservative;
    ConeRatios c = bake_cone_ratios(d, o);
    o.kind = ConeKind::kQuad;
    ConeRatios q = bake_cone_ratios(d, o);
    ASSERT_EQ(q.channels, 4);
    for (int y = 0; y < d.height(); ++y)
      for (int x = 0; x < d.width(); ++x) {
        EXPECT_EQ(std::min(q.at(x, y, 0), q.at(x, y, 1)), c.at(x, y));
        EXPECT_EQ(std::min(q.at(x, y, 2), q.at(x, y, 3)), c.at(x, y));
      }
  }
}

TEST(ConeMap, QuadHalfPlanesAreClosed) {
  // A destination straight along v (ox = 0) limits both the +u and the -u cone.
  const int w = 32, h = 32, sx = 13, sy = 20;
  ConeBakeOptions o;
  o.kind = ConeKind::kQuad;
  ConeRatios q = bake_cone_ratios(spike_map(w, h, sx, sy), o);
  const float D = 5.0f / h;  // texel (sx, sy - 5)
  EXPECT_NEAR(q.at(sx, sy - 5, 0), D, 1e-6f);
  EXPECT_NEAR(q.at(sx, sy - 5, 1), D, 1e-6f);
  EXPECT_NEAR(q.at(sx, sy - 5, 2), D, 1e-6f);  // the spike is at +v from there
  EXPECT_EQ(q.at(sx, sy - 5, 3), 1.0f);        // nothing shallower at -v
}

TEST(ConeMap, ConservativeConeHoldsNoSurfacePoint) {
  // Definition check, independent of the bakers' loops: no texel's surface point lies strictly
  // inside the cone, and the cone is as wide as allowed (touches a point, or is at max_ratio).
  Texture d = bumpy_map(32, 24, 12);
  ConeBakeOptions o;
  o.kind = ConeKind::kConservative;
  ConeRatios r = bake_cone_ratios(d, o);
  for (int y = 0; y < 24; ++y)
    for (int x = 0; x < 32; ++x) {
      const float di = d.fetch_r(0, x, y), ri = r.at(x, y);
      bool touches = ri == 1.0f;
      for (int j = 0; j < 24; ++j)
        for (int i = 0; i < 32; ++i) {
          const float dj = d.fetch_r(0, i, j);
          if ((i == x && j == y) || dj >= di) continue;
          const double D = std::hypot((i - x) / 32.0, (j - y) / 24.0);
          EXPECT_GE(D, ri * (di - dj) * (1 - 1e-6)) << x << "," << y;
          if (std::abs(D - ri * (di - dj)) <= 1e-6 * D) touches = true;
        }
      EXPECT_TRUE(touches) << x << "," << y;
    }
}

// Nearest-texel depth of the clamped map at texel-space point p.
float cell_depth(const Texture& d, double px, double py) {
  const int x = std::clamp(static_cast<int>(std::floor(px)), 0, d.width() - 1);
  const int y = std::clamp(static_cast<int>(std::floor(py)), 0, d.height() - 1);
  return d.fetch_r(0, x, y);
}

TEST(ConeMap, RelaxedConeDefiningPropertyBySampledRays) {
  // For each source texel and every destination texel, march the ray from (c_i, 0) through S_j
  // beyond S_j in small fixed steps (an independent sampler, not the bakers' cell walk) until it
  // first comes out of the surface: that exit point must not lie inside the relaxed cone (up to
  // the step size), and some destination (or max_ratio) must limit the cone.
  const int w = 24, h = 20;
  for (const Texture& d : {bumpy_map(w, h, 21), random_map(w, h, 22), walls_map(w, h)}) {
    ConeBakeOptions o;
    o.kind = ConeKind::kRelaxed;
    ConeRatios r = bake_cone_ratios(d, o);
    ConeRatios cons = [&] {
      ConeBakeOptions c = o;
      c.kind = ConeKind::kConservative;
      return bake_cone_ratios(d, c);
    }();
    for (int y = 0; y < h; y += 3)
      for (int x = 0; x < w; x += 2) {
        const double di = d.fetch_r(0, x, y), ri = r.at(x, y);
        EXPECT_GE(ri, cons.at(x, y));  // relaxed cones are never narrower
        double tightest = 1e30;        // smallest ratio an exit point asks for
        for (int j = 0; j < h; ++j)
          for (int i = 0; i < w; ++i) {
            const double dj = d.fetch_r(0, i, j);
            if ((i == x && j == y) || dj >= di) continue;
            const double ex = i - x, ey = j - y;  // texel-space direction, t = 1 at S_j
            const double dt = 1.0 / (64.0 * std::max(std::abs(ex), std::abs(ey)));
            for (double t = 1.0 + dt; t * dj < di; t += dt) {
              if (cell_depth(d, x + 0.5 + t * ex, y + 0.5 + t * ey) > t * dj) {
                const double D = t * std::hypot(ex / w, ey / h);
                const double need = D / (di - t * dj);
                tightest = std::min(tightest, need);
                // Not inside the cone; slack of one step along the ray.
                const double slack = (dt + 1e-9) * std::hypot(ex / w, ey / h) * 4 / (di - t * dj);
                EXPECT_GE(need + slack, ri) << x << "," << y << " -> " << i << "," << j;
                break;
              }
            }
          }
        if (ri < 1.0f) {
          EXPECT_NEAR(tightest, ri, 0.05 * ri + 1e-3) << x << "," << y;
        }
      }
  }
}

TEST(ConeMap, RelaxedPairMatchesBaker) {
  // The exported pair value is what the baker minimises over.
  Texture d = bumpy_map(16, 16, 31);
  ConeBakeOptions o;
  o.kind = ConeKind::kRelaxed;
  ConeRatios r = bake_cone_ratios_brute_force(d, o);
  for (int y = 0; y < 16; y += 5)
    for (int x = 0; x < 16; x += 3) {
      float m = 1.0f;
      for (int oy = -y; oy < 16 - y; ++oy)
        for (int ox = -x; ox < 16 - x; ++ox)
          m = std::min(m, relaxed_pair_ratio(d, x, y, ox, oy, 1.0f, false));
      EXPECT_EQ(m, r.at(x, y));
    }
}

TEST(ConeMap, TextureFormatsAndMinMips) {
  Texture d = bumpy_map(20, 12, 41);
  ConeBakeOptions o;
  o.kind = ConeKind::kRelaxed;
  Texture t = bake_cone_map(d, o);
  ConeRatios r = bake_cone_ratios(d, o);
  EXPECT_EQ(t.format(), TexFormat::kR32F);
  EXPECT_EQ(t.levels(), 5);  // 20x12, 10x6, 5x3, 2x1, 1x1
  EXPECT_EQ(t.fetch_r(0, 7, 5), r.at(7, 5));
  EXPECT_EQ(t.fetch_r(1, 3, 2), std::min({r.at(6, 4), r.at(7, 4), r.at(6, 5), r.at(7, 5)}));
  float all = 1e9f;
  for (float v : r.values) all = std::min(all, v);
  EXPECT_EQ(t.fetch_r(t.levels() - 1, 0, 0), all);

  o.kind = ConeKind::kQuad;
  ConeRatios q = bake_cone_ratios(d, o);
  Texture tq = cone_ratios_to_texture(q, false);
  EXPECT_EQ(tq.format(), TexFormat::kRGBA16F);
  EXPECT_EQ(tq.levels(), 1);
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < 20; ++x)
      for (int c = 0; c < 4; ++c) {
        const float s = tq.fetch(0, x, y)[c];
        EXPECT_LE(s, q.at(x, y, c));  // rounded down: never wider than baked
        EXPECT_GE(s, q.at(x, y, c) * (1 - 1.0f / 1024));
      }
}

TEST(ConeMap, ProgressReachesOneInOrder) {
  std::vector<float> seen;
  ConeBakeOptions o;
  o.kind = ConeKind::kConservative;
  o.threads = 2;
  o.progress = [&](float f) { seen.push_back(f); };
  (void)bake_cone_ratios(random_map(16, 16, 3), o);
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 1.0f);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
}

}  // namespace
}  // namespace relief
