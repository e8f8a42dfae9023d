// The exact reference (shaders_cpp/exact_trace.h) against closed-form intersections and dense
// marches.
#include "shaders_cpp/exact_trace.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tests/bake/field_fixture.h"

namespace relief {
namespace {

using testing::FloatField;

FloatField sampled(int n, Wrap wrap, double (*fn)(double, double)) {
  FloatField f;
  f.w = f.h = n;
  f.wrap_u = f.wrap_v = wrap;
  f.d.resize(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      f.d[static_cast<size_t>(j) * n + i] = static_cast<float>(fn((i + 0.5) / n, (j + 0.5) / n));
  return f;
}

// A plane is reproduced exactly by bilinear interpolation between texel centres.
double ramp(double u, double v) {
  return 0.1 + 0.5 * u + 0.3 * v;
}
// |u - c| + |v - c| with its kinks on texel centres (n odd, c = 0.5) is a sum of 1D piecewise
// linear functions, also reproduced exactly: a diamond pyramid with apex depth 0.05.
double pyramid(double u, double v) {
  return 0.05 + 0.8 * (std::abs(u - 0.5) + std::abs(v - 0.5));
}

// First root of pyramid(u0 + t dsx, v0 + t dsy) = t, piece by piece.
double pyramid_hit(double u0, double v0, double dsx, double dsy) {
  std::vector<double> cuts = {0.0, 1.0};
  if (dsx != 0.0) cuts.push_back((0.5 - u0) / dsx);
  if (dsy != 0.0) cuts.push_back((0.5 - v0) / dsy);
  std::sort(cuts.begin(), cuts.end());
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    double a = std::max(cuts[k], 0.0), b = std::min(cuts[k + 1], 1.0);
    if (a >= b) continue;
    double m = 0.5 * (a + b);
    double sx = (u0 + m * dsx - 0.5) < 0 ? -1.0 : 1.0, sy = (v0 + m * dsy - 0.5) < 0 ? -1.0 : 1.0;
    // g(t) = c0 + c1 t on this piece
    double c0 = 0.05 + 0.8 * (sx * (u0 - 0.5) + sy * (v0 - 0.5));
    double c1 = 0.8 * (sx * dsx + sy * dsy) - 1.0;
    if (c0 + c1 * a <= 0.0) return a;
    if (c0 + c1 * b <= 0.0) return -c0 / c1;
  }
  return 1.0;
}

TEST(Exact, RampMatchesClosedForm) {
  FloatField f = sampled(16, Wrap::kClamp, ramp);
  HeightField hf = f.exact();
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> start(0.3f, 0.7f), dir(-0.2f, 0.2f);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    float u = start(rng), v = start(rng), dsx = dir(rng), dsy = dir(rng);
    double t = ramp(u, v) / (1.0 - 0.5 * dsx - 0.3 * dsy);
    ExactHit h = hf.intersect(u, v, dsx, dsy);
    worst = std::max({worst, std::abs(h.u - (u + t * dsx)), std::abs(h.v - (v + t * dsy))});
    ASSERT_NEAR(h.t, t, 1e-6);
  }
  EXPECT_LT(worst, 1e-5);
  RecordProperty("worst_uv_error", std::to_string(worst));
}

TEST(Exact, PyramidMatchesClosedForm) {
  FloatField f = sampled(17, Wrap::kClamp, pyramid);
  HeightField hf = f.exact();
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> start(0.25f, 0.75f), dir(-0.2f, 0.2f);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    float u = start(rng), v = start(rng), dsx = dir(rng), dsy = dir(rng);
    if (k % 10 == 0) dsx = 0.0f;  // axis-aligned rays run along cell edges
    double t = pyramid_hit(u, v, dsx, dsy);
    ExactHit h = hf.intersect(u, v, dsx, dsy);
    worst = std::max({worst, std::abs(h.u - (u + t * dsx)), std::abs(h.v - (v + t * dsy))});
    ASSERT_NEAR(h.t, t, 1e-5) << u << " " << v << " " << dsx << " " << dsy;
  }
  EXPECT_LT(worst, 1e-5);
}

TEST(Exact, DepthAtMatchesFloatSampler) {
  for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
    FloatField f = testing::thin_walls(16, 5, 3);
    f.wrap_u = f.wrap_v = wrap;
    HeightField hf = f.exact();
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> uv(-2.0f, 3.0f);
    for (int k = 0; k < 10000; ++k) {
      float u = uv(rng), v = uv(rng);
      ASSERT_NEAR(hf.depth_at(u, v), f(0, u, v), 2e-6) << u << " " << v;
    }
  }
}

// The exact hit is on the surface (g <= 0 there) and never after the first inside sample of a
// 1e5-step march; over the texture edges too (repeat and clamp, rays crossing several tiles).
TEST(Exact, NeverLaterThanDenseMarch) {
  const int kMarch = 100000;
  for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
    FloatField f = testing::thin_walls(32, 7, 5);
    f.wrap_u = f.wrap_v = wrap;
    HeightField hf = f.exact();
    std::mt19937 rng(6);
    int slivers = 0;
    for (int k = 0; k < 150; ++k) {
      testing::RandomRay r = testing::random_ray(rng, 85.0f, 0.05f, 0.3f);
      ExactHit h = hf.intersect(r.u, r.v, r.dsx, r.dsy);
      ASSERT_LE(hf.depth_at(h.u, h.v) - h.t, 1e-9);
      double tm = 1.0;
      for (int i = 0; i <= kMarch; ++i) {
        double t = static_cast<double>(i) / kMarch;
        if (hf.depth_at(r.u + t * r.dsx, r.v + t * r.dsy) <= t) {
          tm = t;
          break;
        }
      }
      ASSERT_LE(h.t, tm + 1e-12) << k;
      if (tm - h.t > 2.0 / kMarch) ++slivers;  // a crossing the march stepped over
    }
    RecordProperty(wrap == Wrap::kRepeat ? "slivers_repeat" : "slivers_clamp", slivers);
  }
}

TEST(Exact, MirrorWrapIsPeriodicReflection) {
  FloatField f = testing::thin_walls(8, 3, 7);
  HeightField m(f.w, f.h, f.d.data(), Wrap::kMirror, Wrap::kMirror);
  // mirrored repeat: u in [1, 2) reads the texture reflected
  for (int k = 0; k < 100; ++k) {
    double u = 0.06 + 0.0088 * k, v = 0.3;
    EXPECT_NEAR(m.depth_at(2.0 - u, v), m.depth_at(u, v), 1e-12);
    EXPECT_NEAR(m.depth_at(u + 2.0, v), m.depth_at(u, v), 1e-12);
  }
  ExactHit h = m.intersect(0.9f, 0.4f, 2.5f, 0.7f);
  EXPECT_LE(m.depth_at(h.u, h.v) - h.t, 1e-9);
}

// Shadow query vs a march over s. g(s) = D - (t - s) is Lipschitz with constant `lip`, so on a
// march segment of length h the true minimum lies within lip * h / 2 below the smaller end value.
// Segments that could still dip under -bias are re-marched 256 times finer; a point whose answer
// stays undecidable at that resolution is only counted.
TEST(Exact, ShadowAgreesWithMarch) {
  FloatField f = testing::thin_walls(32, 9, 8);
  HeightField hf = f.exact();
  const double kBias = 1e-4;
  const int kMarch = 1000, kFine = 256;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  int shadowed = 0, undecided = 0;
  for (int k = 0; k < 10000; ++k) {
    double u = u01(rng), v = u01(rng);
    double t = hf.depth_at(u, v);
    double elev = (5.0 + 80.0 * u01(rng)) * M_PI / 180.0, az = 2.0 * M_PI * u01(rng);
    double scale = 0.02 + 0.1 * u01(rng);
    double dlx = std::cos(az) * scale / std::tan(elev), dly = std::sin(az) * scale / std::tan(elev);
    // |dD/ds| <= 32 * (|dlx| + |dly|): neighbouring texels differ by at most 1
    double lip = 1.0 + 32.0 * (std::abs(dlx) + std::abs(dly));
    auto g = [&](double s) { return hf.depth_at(u + s * dlx, v + s * dly) - (t - s); };
    bool march_shadow = false, unsure = false;
    double h = t / kMarch, ga = 0.0;  // g(0) = 0: the point is on the surface
    for (int i = 1; i <= kMarch && !march_shadow; ++i) {
      double gb = g(h * i);
      if (gb < -kBias) march_shadow = true;
      if (std::min(ga, gb) - lip * h / 2 < -kBias && !march_shadow) {
        double hf2 = h / kFine, fa = ga;
        for (int j = 1; j <= kFine; ++j) {
          double fb = g(h * (i - 1) + hf2 * j);
          if (fb < -kBias) {
            march_shadow = true;
            break;
          }
          if (std::min(fa, fb) - lip * hf2 / 2 < -kBias) unsure = true;
          fa = fb;
        }
      }
      ga = gb;
    }
    bool exact = hf.shadowed(u, v, t, dlx, dly, kBias);
    if (march_shadow) {
      ASSERT_TRUE(exact) << k;
    } else if (!unsure) {
      ASSERT_FALSE(exact) << k;
    } else {
      ++undecided;
      continue;
    }
    shadowed += exact;
  }
  EXPECT_GT(shadowed, 1000);  // the set is not trivially lit
  EXPECT_LT(undecided, 100);
  RecordProperty("shadowed", shadowed);
  RecordProperty("undecided", undecided);
}

TEST(Exact, DegenerateRaysAreFinite) {
  FloatField f = testing::thin_walls(16, 4, 10);
  for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
    HeightField hf(f.w, f.h, f.d.data(), wrap, wrap);
    float big = 0.1f / std::tan(0.01f * static_cast<float>(M_PI / 180.0));  // 0.01 degrees
    for (auto [dsx, dsy] : {std::pair{0.0f, 0.0f}, {big, 0.0f}, {-big, big * 0.3f}, {0.0f, -big}}) {
      ExactHit h = hf.intersect(0.37f, 0.61f, dsx, dsy);
      EXPECT_TRUE(std::isfinite(h.u) && std::isfinite(h.v) && std::isfinite(h.t));
      EXPECT_GE(h.t, 0.0);
      EXPECT_LE(h.t, 1.0);
      EXPECT_LE(hf.depth_at(h.u, h.v) - h.t, 1e-6);
    }
  }
  // a 1 x 1 field, clamp: constant depth
  float one = 0.25f;
  HeightField c(1, 1, &one, Wrap::kClamp, Wrap::kClamp);
  EXPECT_NEAR(c.intersect(0.5f, 0.5f, 0.3f, -0.2f).t, 0.25, 1e-12);
}

}  // namespace
}  // namespace relief
