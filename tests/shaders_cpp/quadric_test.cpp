// Tests for shaders_cpp/quadric.h (Oliveira and Policarpo 2005, sections 3.1 to 3.4): equation 6
// against a numerical root of equation 5, the growth of equation 7's error toward the normal
// (figure 10), t_max, and hard cases (grazing, along the normal, planes, saddles, huge
// curvature) in both lane types.
#include "shaders_cpp/quadric.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace relief {
namespace {

constexpr float kPi = 3.14159265358979f;

// Tangent-space view direction at `deg` degrees from the normal, azimuth `az` (V.z < 0).
V3<float> view_at(float deg, float az) {
  const float th = deg * kPi / 180.0f;
  return {std::sin(th) * std::cos(az), std::sin(th) * std::sin(az), -std::cos(th)};
}

// The root s of f nearest 0 in the direction that equation 6 takes (first sign change of f(s)
// from s = 0 towards +s when f(0) < 0, the point inside, towards -s when above), in double; NaN
// when none lies within |s| < limit.
template <class Fn>
double first_root(const Fn& f, double limit) {
  const double f0 = f(0.0);
  if (f0 == 0.0) return 0.0;
  const double dir = f0 < 0.0 ? 1.0 : -1.0;
  const double h = limit * 2e-6;
  for (double s = 0.0; std::fabs(s) < limit; s += dir * h) {
    if ((f(s + dir * h) < 0.0) != (f0 < 0.0)) {
      double lo = s, hi = s + dir * h;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((f(mid) < 0.0) == (f0 < 0.0) ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
  }
  return NAN;
}

// Equation 5 along the ray's own U in texture space (its root is equation 6's s).
double reference_distance(const QuadricRay<float>& r, double t) {
  const double px = r.dir.x * t, py = r.dir.y * t, pz = r.dir.z * t;
  return first_root(
      [&](double s) {
        const double x = px + r.up.x * s, y = py + r.up.y * s, z = pz + r.up.z * s;
        return r.alpha * x * x + r.beta * y * y - z;
      },
      50.0);
}

TEST(Quadric, AccurateDistanceMatchesNumericalRoot) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> ab(-2.0f, 2.0f), ang(5.0f, 85.0f), az(0.0f, 2.0f * kPi),
      frac(0.0f, 1.0f);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const V3<float> V = view_at(ang(rng), az(rng));
    const QuadricRay<float> r = make_quadric_ray<QuadricDistance::kAccurate>(
        V, V2<float>(ab(rng), ab(rng)), V2<float>(1.0f, 1.0f), 1.0f);
    const float t = frac(rng) * r.t_max;
    const V3<float>& u = r.up;
    const float A = r.alpha * u.x * u.x + r.beta * u.y * u.y;
    const float px = r.dir.x * t, py = r.dir.y * t, pz = r.dir.z * t;
    const float B = 2.0f * (r.alpha * px * u.x + r.beta * py * u.y) - u.z;
    const float C = r.alpha * px * px + r.beta * py * py - pz;
    if (B * B - 4.0f * A * C < 1e-3f) continue;  // equation 7's domain, or a double root
    const double ref = reference_distance(r, t);
    if (!std::isfinite(ref) || std::fabs(ref) > 2.0) continue;
    EXPECT_NEAR(quadric_distance_accurate(r, t), ref, 1e-4) << i;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
}

// Equation 6 is defined in tangent space (section 3.1): U perpendicular to the view ray there,
// s in object units. Section 3.4 moves the computation to texture space; with tiles and depth
// scales far from 1 and from each other (sz much smaller than sx, as on every built-in curved
// scene) the texture-space distance must still be the tangent-space one divided by sz. The
// reference here is built in tangent space only: the point P = V t_o, the unit U, the quadric
// z = a x^2 + b y^2 in object units, its root along U found numerically.
TEST(Quadric, AccurateDistanceIsTheTangentSpaceDistanceInDepthUnits) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> ab(-1.0f, 1.0f), ang(5.0f, 85.0f), az(0.0f, 2.0f * kPi),
      frac(0.0f, 1.0f), tile(0.2f, 3.0f), depth(0.01f, 0.3f);
  int compared = 0;
  for (int i = 0; i < 2000; ++i) {
    const V3<float> V = view_at(ang(rng), az(rng));
    const float a = ab(rng), b = ab(rng), sx = tile(rng), sy = tile(rng), sz = depth(rng);
    const QuadricRay<float> r =
        make_quadric_ray<QuadricDistance::kAccurate>(V, V2<float>(a, b), V2<float>(sx, sy), sz);
    const float t = frac(rng) * r.t_max;
    // tangent space, depth convention (z into the surface)
    const double to = double(t) * r.world_per_t;
    const double vx = V.x, vy = V.y, vz = -V.z;
    const double px = vx * to, py = vy * to, pz = vz * to;
    // U = (0, 0, -1) minus its part along the ray, normalised
    double ux = vz * vx, uy = vz * vy, uz = -1.0 + vz * vz;
    const double ul = std::sqrt(ux * ux + uy * uy + uz * uz);
    ux /= ul, uy /= ul, uz /= ul;
    const double A = a * ux * ux + b * uy * uy;
    const double B = 2.0 * (a * px * ux + b * py * uy) - uz;
    const double C = a * px * px + b * py * py - pz;
    if (B * B - 4.0 * A * C < 1e-3 * sz * sz) continue;  // equation 7's domain, or a double root
    const double ref = first_root(
        [&](double s) {
          const double x = px + ux * s, y = py + uy * s, z = pz + uz * s;
          return a * x * x + b * y * y - z;
        },
        50.0 * sz);
    if (!std::isfinite(ref) || std::fabs(ref / sz) > 2.0) continue;
    EXPECT_NEAR(quadric_distance_accurate(r, t), ref / sz, 1e-4) << i;
    ++compared;
  }
  EXPECT_GT(compared, 1000);
}

// |eq 7 - eq 6| where the ray is 0.2 depth units below the tangent plane (P.z = 0.2), on a
// gently curved convex quadric, `deg` from the normal.
float approximation_error(float deg) {
  const QuadricRay<float> r = make_quadric_ray<QuadricDistance::kAccurate>(
      view_at(deg, 0.3f), V2<float>(0.05f, 0.05f), V2<float>(1.0f, 1.0f), 1.0f);
  const float t = 0.2f / r.dir.z;
  EXPECT_LE(t, r.t_max) << deg;
  return std::fabs(quadric_distance_vertical(r, t) - quadric_distance_accurate(r, t));
}

TEST(Quadric, ApproximateErrorGrowsTowardTheNormal) {
  float prev = 0.0f;
  for (float deg : {80.0f, 60.0f, 45.0f, 30.0f, 15.0f}) {
    const float e = approximation_error(deg);
    printf("approximation error at %.0f deg from the normal: %.4f\n", deg, e);
    EXPECT_GT(e, prev) << deg;
    prev = e;
  }
  EXPECT_GT(prev, 10.0f * approximation_error(80.0f));
}

TEST(Quadric, TmaxIsWhereTheRayReachesDepthOneOrReturns) {
  for (float deg : {10.0f, 50.0f, 85.0f})
    for (V2<float> q : {V2<float>(0.5f, 0.5f), V2<float>(0.0f, 0.0f), V2<float>(-1.0f, 2.0f)}) {
      const auto r =
          make_quadric_ray<QuadricDistance::kApproximate>(view_at(deg, 1.0f), q, {1, 1}, 1.0f);
      const float D = quadric_distance_vertical(r, r.t_max);
      EXPECT_NEAR(D, r.bottom ? 1.0f : 0.0f, 1e-4f) << deg;
      for (int i = 1; i < 100; ++i) {  // inside (0, 1) before t_max
        const float d = quadric_distance_vertical(r, r.t_max * i / 100.0f);
        EXPECT_GT(d, 0.0f);
        EXPECT_LT(d, 1.0f);
      }
    }
}

// A depth source: rolling hills in [0.2, 1].
struct Hills {
  float operator()(int, float u, float v) const {
    return 0.6f + 0.4f * std::sin(7.0f * u) * std::cos(5.0f * v);
  }
};

template <QuadricDistance kD, class F>
QuadricHit<F> search_lanes(const std::vector<V3<float>>& views, const std::vector<V2<float>>& qs,
                           QuadricRay<F>* ray_out, size_t first) {
  V3<F> V;
  V2<F> q;
  for (int i = 0; i < lane_width<F>; ++i) {
    const size_t k = (first + i) % views.size();
    set_lane(V.x, i, views[k].x);
    set_lane(V.y, i, views[k].y);
    set_lane(V.z, i, views[k].z);
    set_lane(q.x, i, qs[k].x);
    set_lane(q.y, i, qs[k].y);
  }
  const QuadricRay<F> r = make_quadric_ray<kD>(V, q, V2<F>(F(0.5f), F(0.8f)), F(0.1f));
  *ray_out = r;
  return quadric_search<kD>(Hills(), V2<F>(F(0.3f), F(0.7f)), r, F(16.0f), 8, true_mask<F>());
}

template <QuadricDistance kD>
void hard_cases() {
  std::vector<V3<float>> views = {view_at(0.0f, 0.0f),  {0.0f, 0.0f, -1.0f},  view_at(89.9f, 0.4f),
                                  view_at(89.9f, 2.0f), view_at(45.0f, 1.0f), view_at(89.99f, 0.0f),
                                  {1.0f, 0.0f, 0.0f},   {0.0f, 0.0f, 1.0f}};
  std::vector<V2<float>> qs = {{0.0f, 0.0f},   {2.0f, -2.0f},  {1e6f, 1e6f}, {-1e6f, 3.0f},
                               {1e-30f, 0.0f}, {-5.0f, -5.0f}, {0.5f, 0.5f}, {1e6f, -1e6f}};
  for (size_t first = 0; first < views.size(); ++first) {
    for (size_t qi = 0; qi < qs.size(); ++qi) {
      std::vector<V2<float>> q1(views.size(), qs[qi]);
      QuadricRay<float> rs;
      QuadricRay<F8> r8;
      const QuadricHit<float> hs = search_lanes<kD, float>(views, q1, &rs, first);
      const QuadricHit<F8> h8 = search_lanes<kD, F8>(views, q1, &r8, first);
      ASSERT_TRUE(std::isfinite(rs.t_max) && rs.t_max > 0.0f) << first << " " << qi;
      ASSERT_TRUE(std::isfinite(hs.t) && hs.t >= 0.0f && hs.t <= rs.t_max) << first << " " << qi;
      ASSERT_TRUE(std::isfinite(hs.hit.uv.x) && std::isfinite(hs.hit.uv.y));
      ASSERT_TRUE(std::isfinite(hs.hit.depth) && hs.hit.depth >= 0.0f && hs.hit.depth <= 1.0f);
      // the 8-lane kernel gives the scalar one's bits on its first lane
      EXPECT_EQ(lane(h8.t, 0), hs.t);
      EXPECT_EQ(lane(h8.miss, 0), hs.miss);
      EXPECT_EQ(lane(h8.hit.depth, 0), hs.hit.depth);
      EXPECT_EQ(lane(r8.t_max, 0), rs.t_max);
      // search=relaxed_cone on the same rays
      struct Ratio {
        float operator()(int, float, float) const { return 0.6f; }
      };
      const QuadricHit<float> hc = quadric_relaxed_cone_search<kD>(
          Hills(), Ratio(), V2<float>(0.3f, 0.7f), rs, 15, 8, 8, 1.0f / 512.0f, true);
      ASSERT_TRUE(std::isfinite(hc.t) && hc.t >= 0.0f && hc.t <= rs.t_max) << first << " " << qi;
      ASSERT_TRUE(std::isfinite(hc.hit.depth) && hc.hit.depth >= 0.0f && hc.hit.depth <= 1.0f);
      ASSERT_TRUE(std::isfinite(hc.hit.uv.x) && std::isfinite(hc.hit.uv.y));
      for (int i = 0; i < 1000; ++i) {
        const float t = rs.t_max * i / 999.0f;
        ASSERT_TRUE(std::isfinite(quadric_distance<kD>(rs, t))) << first << " " << qi;
      }
    }
  }
}

TEST(Quadric, HardCasesStayFiniteApproximate) {
  hard_cases<QuadricDistance::kApproximate>();
}
TEST(Quadric, HardCasesStayFiniteAccurate) {
  hard_cases<QuadricDistance::kAccurate>();
}

TEST(Quadric, ConvexGrazingRaysReturnAndAreDiscarded) {
  // a sphere-like quadric seen at 89 degrees: the ray leaves the relief before depth 1
  const auto r = make_quadric_ray<QuadricDistance::kApproximate>(
      view_at(89.0f, 0.0f), V2<float>(2.0f, 2.0f), V2<float>(1.0f, 1.0f), 0.05f);
  EXPECT_FALSE(r.bottom);
  struct Deep {
    float operator()(int, float, float) const { return 0.9f; }
  };
  const QuadricHit<float> h = quadric_search<QuadricDistance::kApproximate>(
      Deep(), V2<float>(0.0f, 0.0f), r, 32.0f, 8, true);
  EXPECT_TRUE(h.miss);
  // a plane (a = b = 0) at the same angle always reaches the bottom: a hit
  const auto p = make_quadric_ray<QuadricDistance::kApproximate>(
      view_at(89.0f, 0.0f), V2<float>(0.0f, 0.0f), V2<float>(1.0f, 1.0f), 0.05f);
  EXPECT_TRUE(p.bottom);
  EXPECT_FALSE((quadric_search<QuadricDistance::kApproximate>(Deep(), V2<float>(0.0f, 0.0f), p,
                                                              32.0f, 8, true)
                    .miss));
}

// search=relaxed_cone on a field at constant depth c, with the wide cones such a field has
// (ratios 1 to 8): each step solves the ray's parabola against the cone exactly, so the gap to
// the plane shrinks every step and within 64 steps the march reaches the analytic root of
// D(t) = c by equation 7, k t^2 - dz t + c = 0 (the halvings refine it where a step lands
// inside); where that root lies beyond t_max the ray returns to depth 0 first and is a
// silhouette miss. Both lane types, the 8-lane result bit-equal to the scalar one.
TEST(Quadric, RelaxedConeSearchFindsTheAnalyticHitOnAConstantField) {
  struct Constant {
    float c;
    float operator()(int, float, float) const { return c; }
  };
  struct Ratio {
    float r;
    float operator()(int, float, float) const { return r; }
  };
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> ab(-3.0f, 3.0f), ang(0.0f, 89.0f), az(0.0f, 2.0f * kPi),
      depth(0.05f, 0.95f), ratio(1.0f, 8.0f);
  int hits = 0, misses = 0;
  for (int i = 0; i < 4000; ++i) {
    const Constant field{depth(rng)};
    const Ratio cone{ratio(rng)};
    const V3<float> V = view_at(ang(rng), az(rng));
    const V2<float> q(ab(rng), ab(rng));
    const auto r =
        make_quadric_ray<QuadricDistance::kApproximate>(V, q, V2<float>(0.7f, 0.4f), 0.08f);
    const QuadricHit<float> h = quadric_relaxed_cone_search<QuadricDistance::kApproximate>(
        field, cone, V2<float>(0.2f, 0.6f), r, 64, 8, 24, 1.0f / 512.0f, true);
    const float k = r.alpha * r.dir.x * r.dir.x + r.beta * r.dir.y * r.dir.y;
    const float t_ref =
        HWY_NAMESPACE::detail::smallest_positive_root(k, -r.dir.z, field.c, 3.0e38f);
    const bool miss_ref = !(t_ref <= r.t_max);
    ASSERT_EQ(h.miss, miss_ref) << i << " t_ref " << t_ref << " t_max " << r.t_max;
    if (miss_ref) {
      ++misses;
    } else {
      ++hits;
      EXPECT_NEAR(h.t, t_ref, 1e-4f * r.t_max + 1e-6f) << i;
      EXPECT_NEAR(h.hit.depth, field.c, 1e-3f) << i;
    }
    // the 8-lane kernel, all lanes alike, gives the scalar bits
    const auto r8 = make_quadric_ray<QuadricDistance::kApproximate>(
        V3<F8>(F8(V.x), F8(V.y), F8(V.z)), V2<F8>(F8(q.x), F8(q.y)), V2<F8>(F8(0.7f), F8(0.4f)),
        F8(0.08f));
    const QuadricHit<F8> h8 = quadric_relaxed_cone_search<QuadricDistance::kApproximate>(
        field, cone, V2<F8>(F8(0.2f), F8(0.6f)), r8, 64, 8, 24, F8(1.0f / 512.0f), true_mask<F8>());
    EXPECT_EQ(lane(h8.t, 5), h.t);
    EXPECT_EQ(lane(h8.miss, 5), h.miss);
    EXPECT_EQ(lane(h8.hit.steps, 5), h.hit.steps);
  }
  // both outcomes were exercised
  EXPECT_GT(hits, 400);
  EXPECT_GT(misses, 400);
}

// With cones no wider than the field allows (the Lipschitz bound of Hills: |grad| <= 0.4 sqrt(74)
// depth per uv, so a ratio of 1 / 3.5 is conservative) the march can never step past the first
// hit on the deformed field: it stops inside at or after it only within the last step, and a
// ray that returns to depth 0 without a hit is discarded while a ray that hits is kept. The
// reference: the linear search with 4096 steps and 30 halvings.
TEST(Quadric, ConservativeConesNeverPassTheFirstHitOnTheDeformedField) {
  struct Ratio {
    float operator()(int, float, float) const { return 1.0f / 3.5f; }
  };
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> ab(-2.0f, 2.0f), ang(0.0f, 88.0f), az(0.0f, 2.0f * kPi);
  int compared = 0, kept = 0, discarded = 0, disagreed = 0;
  for (int i = 0; i < 1500; ++i) {
    const V3<float> V = view_at(ang(rng), az(rng));
    const V2<float> q(ab(rng), ab(rng));
    const auto r =
        make_quadric_ray<QuadricDistance::kApproximate>(V, q, V2<float>(0.5f, 0.8f), 0.1f);
    const V2<float> uv(0.3f, 0.7f);
    const QuadricHit<float> ref =
        quadric_search<QuadricDistance::kApproximate>(Hills(), uv, r, 4096.0f, 30, true);
    const QuadricHit<float> h = quadric_relaxed_cone_search<QuadricDistance::kApproximate>(
        Hills(), Ratio(), uv, r, 256, 8, 30, 1.0f / 512.0f, true);
    ++compared;
    if (h.miss != ref.miss) {
      ++disagreed;  // a ray that grazes the field within the reference's 1 / 4096 sampling
      continue;
    }
    if (ref.miss) {
      ++discarded;
      continue;
    }
    ++kept;
    EXPECT_LE(h.t, ref.t + 1e-3f * r.t_max) << i;
  }
  EXPECT_LE(disagreed, compared / 100);
  EXPECT_GT(kept, 300);
  EXPECT_GT(discarded, 100);
}

}  // namespace
}  // namespace relief
