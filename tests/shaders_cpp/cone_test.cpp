// Cone stepping kernels (shaders_cpp/cone.h): conservative and quad-directional cones never step
// a ray past the first intersection, relaxed cone stepping + binary search (GPU Gems 3 ch. 18,
// listing 18-3) beats linear + binary search and conservative cones at the chapter's 15 (+6)
// steps on the `pattern` depth map (the figure 18-1 claim, measured against the exact
// reference), the light ray agrees with the exact shadow, and float and F8 lanes agree.
#include "shaders_cpp/cone.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bake/cone_map.h"
#include "field_fixture.h"
#include "scene/builtin.h"
#include "shaders_cpp/exact.h"
#include "shaders_cpp/ray.h"

namespace relief {
namespace {

using testing::FloatField;

// Nearest-texel depth of a FloatField: the field relaxed cones are defined on.
struct BoxField {
  const FloatField* f;
  float operator()(int, float u, float v) const {
    const float x = std::floor(u * static_cast<float>(f->w)),
                y = std::floor(v * static_cast<float>(f->h));
    if (!(std::fabs(x) < 1e15f) || !(std::fabs(y) < 1e15f)) return f->texel(0, 0);
    return f->texel(FloatField::wrap(static_cast<long long>(x), f->w, f->wrap_u),
                    FloatField::wrap(static_cast<long long>(y), f->h, f->wrap_v));
  }
};

// A depth field (bilinear, repeat: the exact reference's field) and its three cone maps.
struct ConeField {
  std::string name;
  FloatField f;
  HeightField exact;
  Texture cons, quad, relaxed;
  BoxField box() const { return {&f}; }  // not a member: ConeFields move

  ConeField(std::string n, FloatField field) : name(std::move(n)), f(std::move(field)) {
    exact = f.exact();
    const Texture depth = Texture::from_floats(TexFormat::kR32F, f.w, f.h, f.d.data());
    // the maps the plugins derive (render/derived_maps.h): bilinear-safe conservative cones
    ConeBakeOptions o;
    o.wrap = true;
    o.bilinear = true;
    o.kind = ConeKind::kConservative;
    cons = bake_cone_map(depth, o);
    o.kind = ConeKind::kQuad;
    quad = bake_cone_map(depth, o);
    o.bilinear = false;
    o.kind = ConeKind::kRelaxed;
    relaxed = bake_cone_map(depth, o);
  }
  TextureCone cone(const Texture& t) const {
    TextureCone c;
    c.texture = &t;
    c.sampler = cone_sampler(SamplerState{});
    return c;
  }
  QuadTextureCone quad_cone() const {
    QuadTextureCone c;
    c.texture = &quad;
    c.sampler = cone_sampler(SamplerState{});
    return c;
  }
};

FloatField pattern_field(int n) {
  const Texture t = make_pattern_depth(n);
  FloatField f;
  f.w = f.h = n;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) f.d.push_back(t.fetch_r(0, x, y));
  return f;
}

const std::vector<ConeField>& fields() {
  static const std::vector<ConeField>* v = [] {
    auto* r = new std::vector<ConeField>();
    r->emplace_back("smooth", testing::smooth_bumps(64));
    r->emplace_back("walls", testing::thin_walls(64, 11, 21));
    r->emplace_back("pattern", pattern_field(256));
    return r;
  }();
  return *v;
}

std::vector<testing::RandomRay> rays(int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<testing::RandomRay> r;
  for (int k = 0; k < count; ++k) r.push_back(testing::random_ray(rng, 75.0f, 0.02f, 0.1f));
  return r;
}

FloatField constant_field(float d) {
  FloatField f;
  f.w = f.h = 8;
  f.d.assign(64, d);
  return f;
}

TEST(Cone, StraightDownReachesAFlatSurfaceInOneStep) {
  const ConeField c("flat", constant_field(0.5f));
  // ds = 0: d = r h / (0 + r) = h, then the sample at t = 0.5 is inside and the lane stops
  const SearchHit<float> h =
      cone_search(c.f, c.cone(c.cons), V2<float>(0.3f, 0.6f), V2<float>(0.0f, 0.0f), 15, true);
  EXPECT_EQ(h.depth, 0.5f);
  EXPECT_EQ(h.steps, 2.0f);
  EXPECT_EQ(h.fetches, 4.0f);  // depth + cone per step
  EXPECT_EQ(h.uv.x, 0.3f);
}

TEST(Cone, StepsFollowEquationThree) {
  // Flat at 0.5, every ratio 1 (the clamp), |ds| = 1: each step covers half of what is left,
  // t_k = 0.5 (1 - 2^-k); the march never gets inside.
  const ConeField c("flat", constant_field(0.5f));
  const SearchHit<float> h =
      cone_search(c.f, c.cone(c.cons), V2<float>(0.1f, 0.1f), V2<float>(0.6f, 0.8f), 4, true);
  EXPECT_FLOAT_EQ(h.depth, 0.5f * (1.0f - 1.0f / 16.0f));
  EXPECT_EQ(h.steps, 4.0f);
  EXPECT_FLOAT_EQ(h.uv.x, 0.1f + 0.6f * h.depth);
}

TEST(Cone, RelaxedBinarySearchRunsFromHToK) {
  const ConeField c("flat", constant_field(0.5f));
  const V2<float> uv(0.1f, 0.1f), ds(0.6f, 0.8f);
  // March never inside: the binary search on [K/2, K] converges to K.
  const SearchHit<float> k = cone_march(c.f, c.cone(c.relaxed), uv, ds, 4, 1.0f, true);
  const SearchHit<float> h =
      relaxed_cone_search(c.box(), c.f, c.cone(c.relaxed), uv, ds, 4, 6, true);
  EXPECT_EQ(h.depth, k.depth);
  EXPECT_EQ(h.steps, 4.0f + 6.0f);
  EXPECT_EQ(h.fetches, 8.0f + 6.0f);
  // Straight down, K = 0.5 is inside after one step: the search stays in [0.25, 0.5].
  const SearchHit<float> s =
      relaxed_cone_search(c.box(), c.f, c.cone(c.relaxed), uv, V2<float>(0.0f, 0.0f), 15, 3, true);
  EXPECT_EQ(s.depth, 0.5f);  // every halving of [0.25, 0.5] samples outside, hi stays at K
  EXPECT_EQ(s.steps, 2.0f + 3.0f);
}

TEST(Cone, InactiveLanesDoNothing) {
  const ConeField& c = fields()[0];
  M8 active = true_mask<F8>();
  set_lane(active, 5, false);
  const SearchHit<F8> h =
      relaxed_cone_search(c.box(), c.f, c.cone(c.relaxed), V2<F8>(F8(0.3f), F8(0.4f)),
                          V2<F8>(F8(0.05f), F8(0.02f)), 15, 6, active);
  EXPECT_EQ(lane(h.steps, 5), 0.0f);
  EXPECT_EQ(lane(h.fetches, 5), 0.0f);
  EXPECT_EQ(lane(h.depth, 5), 0.0f);
  EXPECT_GT(lane(h.steps, 0), 0.0f);
}

// Mean |uv - exact uv| in texels and the worst overshoot (hit depth beyond the exact first
// hit) of a search over random rays.
struct Score {
  double mean_texels = 0.0;
  double max_late = 0.0;  // max(hit depth - exact depth), <= 0 when never late
  double mean_fetches = 0.0;
};

template <class Search>
Score score(const ConeField& c, const std::vector<testing::RandomRay>& rs, Search&& search) {
  Score s;
  s.max_late = -1.0;
  for (const testing::RandomRay& r : rs) {
    const ExactHit e = c.exact.intersect(r.u, r.v, r.dsx, r.dsy);
    const SearchHit<float> h = search(V2<float>(r.u, r.v), V2<float>(r.dsx, r.dsy));
    EXPECT_TRUE(std::isfinite(h.depth) && std::isfinite(h.uv.x) && std::isfinite(h.uv.y));
    s.mean_texels += std::hypot((h.uv.x - e.u) * c.f.w, (h.uv.y - e.v) * c.f.h);
    s.max_late = std::max(s.max_late, h.depth - e.t);
    s.mean_fetches += h.fetches;
  }
  s.mean_texels /= rs.size();
  s.mean_fetches /= rs.size();
  return s;
}

TEST(Cone, ConservativeConesNeverPassTheFirstHit) {
  const auto rs = rays(3000, 41);
  for (const ConeField& c : fields())
    for (int n : {15, 64, 256}) {
      const TextureCone cone = c.cone(c.cons);
      QuadTextureCone quad = c.quad_cone();
      const Score sc = score(c, rs, [&](V2<float> uv, V2<float> ds) {
        return cone_search(c.f, cone, uv, ds, n, true);
      });
      const Score sq = score(c, rs, [&](V2<float> uv, V2<float> ds) {
        quad.aim(ds);
        return cone_search(c.f, quad, uv, ds, n, true);
      });
      std::printf(
          "%-8s n=%3d conservative max late %.3g mean err %.4f texel | quad max late %.3g "
          "mean err %.4f\n",
          c.name.c_str(), n, sc.max_late, sc.mean_texels, sq.max_late, sq.mean_texels);
      // the reference is double, the kernel float: its rounding of t (measured at most 4.4e-6)
      EXPECT_LE(sc.max_late, 1e-5) << c.name << " n=" << n;
      EXPECT_LE(sq.max_late, 1e-5) << c.name << " n=" << n;
    }
}

TEST(Cone, RelaxedBeatsReliefAndConservativeOnPattern) {
  const ConeField& c = fields()[2];
  const auto rs = rays(4000, 42);
  const TextureCone cons = c.cone(c.cons), rel = c.cone(c.relaxed);
  QuadTextureCone quad = c.quad_cone();
  const Score relaxed = score(c, rs, [&](V2<float> uv, V2<float> ds) {
    return relaxed_cone_search(c.box(), c.f, rel, uv, ds, 15, 6, true);
  });
  const Score relief = score(c, rs, [&](V2<float> uv, V2<float> ds) {
    return relief_search(c.f, uv, ds, 15.0f, 6, true);
  });
  const Score conservative = score(
      c, rs, [&](V2<float> uv, V2<float> ds) { return cone_search(c.f, cons, uv, ds, 15, true); });
  const Score quadc = score(c, rs, [&](V2<float> uv, V2<float> ds) {
    quad.aim(ds);
    return cone_search(c.f, quad, uv, ds, 15, true);
  });
  std::printf(
      "pattern 256, 4000 rays: mean error (texels) / fetches: relaxed 15+6 %.4f / %.1f, "
      "relief 15+6 %.4f / %.1f, cone 15 %.4f / %.1f, cone_quad 15 %.4f / %.1f\n",
      relaxed.mean_texels, relaxed.mean_fetches, relief.mean_texels, relief.mean_fetches,
      conservative.mean_texels, conservative.mean_fetches, quadc.mean_texels, quadc.mean_fetches);
  RecordProperty("relaxed_15_6_mean_texel_error", std::to_string(relaxed.mean_texels));
  RecordProperty("relief_15_6_mean_texel_error", std::to_string(relief.mean_texels));
  RecordProperty("cone_15_mean_texel_error", std::to_string(conservative.mean_texels));
  RecordProperty("cone_quad_15_mean_texel_error", std::to_string(quadc.mean_texels));
  EXPECT_LT(relaxed.mean_texels, relief.mean_texels);
  EXPECT_LT(relaxed.mean_texels, conservative.mean_texels);
  // Four ratios are never narrower than the one conservative ratio.
  EXPECT_LE(quadc.mean_texels, conservative.mean_texels);
}

// Hard shadows of random surface points (exact hits of random view rays) toward random lights:
// the light ray searched with the technique against the exact shadow test. Returns the fractions
// of points wrongly shadowed and wrongly lit.
struct ShadowScore {
  double false_shadow = 0.0, false_lit = 0.0;
};
template <class Search>
ShadowScore shadow_disagreement(const ConeField& c, Search&& search) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  const auto rs = rays(3000, 43);
  ShadowScore sc;
  for (const testing::RandomRay& r : rs) {
    const ExactHit e = c.exact.intersect(r.u, r.v, r.dsx, r.dsy);
    const float theta = (10.0f + 60.0f * u01(rng)) * static_cast<float>(M_PI / 180.0);
    const float phi = 2.0f * static_cast<float>(M_PI) * u01(rng);
    const V3<float> L(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                      std::cos(theta));
    const V2<float> dl = light_step(L, 0.06f);
    const V2<float> uv(static_cast<float>(e.u), static_cast<float>(e.v));
    const float t = static_cast<float>(e.t);
    const ConeShadow<float> s = light_ray_shadow(uv, t, dl, L.z, 0.01f, true, search);
    const float ex = exact_shadow(c.exact, uv, t, dl, L.z, 0.01f, true);
    EXPECT_TRUE(s.visibility == 0.0f || s.visibility == 1.0f);
    sc.false_shadow += s.visibility < ex;
    sc.false_lit += s.visibility > ex;
  }
  sc.false_shadow /= rs.size();
  sc.false_lit /= rs.size();
  return sc;
}

// The plugins' shadow rays at their default 32 steps. Conservative cones never pass an occluder,
// so they never light a shadowed point (up to float rounding at the bias: at most 0.1% of
// points); out of steps they stall and shadow a lit one. The relaxed march (bilinear depth, no
// binary search) errs both ways. Measured (fraction of 3000 points, wrong in total): cone 0.040 /
// 0.092 / 0.075 on smooth / walls / pattern, cone_quad 0.032 / 0.078 / 0.065, relaxed 0.003 /
// 0.059 / 0.092 (64 steps: cone 0.011 / 0.022 / 0.021). Bound: 0.10 on every field.
TEST(Cone, LightRayAgreesWithExactShadow) {
  for (const ConeField& c : fields()) {
    const TextureCone cons = c.cone(c.cons), rel = c.cone(c.relaxed);
    QuadTextureCone quad = c.quad_cone();
    const ShadowScore dc = shadow_disagreement(c, [&](V2<float> uv, V2<float> d, float tm, bool a) {
      return cone_search(c.f, cons, uv, d, 32, a, tm);
    });
    const ShadowScore dq = shadow_disagreement(c, [&](V2<float> uv, V2<float> d, float tm, bool a) {
      quad.aim(d);
      return cone_search(c.f, quad, uv, d, 32, a, tm);
    });
    const ShadowScore dr = shadow_disagreement(c, [&](V2<float> uv, V2<float> d, float tm, bool a) {
      return cone_march(c.f, rel, uv, d, 32, tm, a);
    });
    std::printf(
        "%-8s shadow wrong (shadowed + lit): cone %.4f + %.4f, cone_quad %.4f + %.4f, "
        "relaxed %.4f + %.4f\n",
        c.name.c_str(), dc.false_shadow, dc.false_lit, dq.false_shadow, dq.false_lit,
        dr.false_shadow, dr.false_lit);
    RecordProperty(c.name + "_shadow_wrong_cone", std::to_string(dc.false_shadow + dc.false_lit));
    RecordProperty(c.name + "_shadow_wrong_relaxed",
                   std::to_string(dr.false_shadow + dr.false_lit));
    EXPECT_LE(dc.false_lit, 0.001) << c.name;
    EXPECT_LE(dq.false_lit, 0.001) << c.name;
    EXPECT_LT(dc.false_shadow + dc.false_lit, 0.10) << c.name;
    EXPECT_LT(dq.false_shadow + dq.false_lit, 0.10) << c.name;
    EXPECT_LT(dr.false_shadow + dr.false_lit, 0.10) << c.name;
  }
}

uint32_t bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}

TEST(Cone, FloatAndF8LanesAgree) {
  const ConeField& c = fields()[2];
  const auto rs = rays(800, 44);
  const TextureCone cons = c.cone(c.cons), rel = c.cone(c.relaxed);
  for (size_t k0 = 0; k0 + 8 <= rs.size(); k0 += 8) {
    V2<F8> uv, ds;
    F8 tmax, lz;
    M8 active = true_mask<F8>();
    for (int i = 0; i < 8; ++i) {
      const testing::RandomRay& r = rs[k0 + i];
      set_lane(uv.x, i, r.u);
      set_lane(uv.y, i, r.v);
      set_lane(ds.x, i, r.dsx);
      set_lane(ds.y, i, r.dsy);
      set_lane(tmax, i, 0.25f + 0.75f * static_cast<float>(i) / 7.0f);
      set_lane(lz, i, r.vz < -0.5f ? -r.vz : (i == 3 ? -0.2f : 0.3f));
      if (i == 6) set_lane(active, i, false);
    }
    QuadTextureCone q8 = c.quad_cone(), q1 = c.quad_cone();
    q8.aim(ds);
    const SearchHit<F8> h8[3] = {
        cone_search(c.f, cons, uv, ds, 15, active, tmax),
        cone_search(c.f, q8, uv, ds, 15, active, tmax),
        relaxed_cone_search(c.box(), c.f, rel, uv, ds, 15, 6, active, tmax)};
    const ConeShadow<F8> s8 = light_ray_shadow(
        h8[2].uv, h8[2].depth, ds, lz, 0.01f, active, [&](V2<F8> u, V2<F8> d, F8 tm, M8 a) {
          return relaxed_cone_search(c.box(), c.f, rel, u, d, 15, 6, a, tm);
        });
    for (int i = 0; i < 8; ++i) {
      const V2<float> u1(lane(uv.x, i), lane(uv.y, i)), d1(lane(ds.x, i), lane(ds.y, i));
      const bool a1 = lane(active, i);
      const float tm = lane(tmax, i);
      q1.aim(d1);
      const SearchHit<float> h1[3] = {
          cone_search(c.f, cons, u1, d1, 15, a1, tm), cone_search(c.f, q1, u1, d1, 15, a1, tm),
          relaxed_cone_search(c.box(), c.f, rel, u1, d1, 15, 6, a1, tm)};
      for (int k = 0; k < 3; ++k) {
        ASSERT_EQ(bits(lane(h8[k].uv.x, i)), bits(h1[k].uv.x)) << k << " lane " << i;
        ASSERT_EQ(bits(lane(h8[k].uv.y, i)), bits(h1[k].uv.y)) << k;
        ASSERT_EQ(bits(lane(h8[k].depth, i)), bits(h1[k].depth)) << k;
        ASSERT_EQ(lane(h8[k].steps, i), h1[k].steps) << k;
        ASSERT_EQ(lane(h8[k].fetches, i), h1[k].fetches) << k;
      }
      const ConeShadow<float> s1 =
          light_ray_shadow(h1[2].uv, h1[2].depth, d1, lane(lz, i), 0.01f, a1,
                           [&](V2<float> u, V2<float> d, float t, bool a) {
                             return relaxed_cone_search(c.box(), c.f, rel, u, d, 15, 6, a, t);
                           });
      ASSERT_EQ(lane(s8.visibility, i), s1.visibility) << i;
      ASSERT_EQ(lane(s8.steps, i), s1.steps) << i;
      ASSERT_EQ(lane(s8.fetches, i), s1.fetches) << i;
    }
  }
}

}  // namespace
}  // namespace relief
