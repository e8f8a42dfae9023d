// Every technique kernel instantiated for float and for F8 gives bit-identical results lane by
// lane (DESIGN.md: kernels written once, both instantiations tested to agree), and degenerate rays
// (grazing at 0.01 degrees, along the normal, depth scale 0) give finite hits in range.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "shaders_cpp/exact_trace.h"
#include "shaders_cpp/ray.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/shadow.h"
#include "tests/bake/field_fixture.h"

namespace relief {
namespace {

using testing::FloatField;

uint32_t bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}

// Inputs of one batch of 8 lanes.
struct Batch {
  float wx[8], wy[8], wz[8];  // world position
  float nx[8], ny[8], nz[8], tx[8], ty[8], tz[8], sign[8];
  float scale[8], lx[8], ly[8], lz[8];
  bool active[8];
};

// Outputs, one row per lane.
struct Out {
  float v[64];
  int n = 0;
  void put(float x) { v[n++] = x; }
  void put(const SearchHit<float>& h) {
    put(h.uv.x);
    put(h.uv.y);
    put(h.depth);
    put(h.steps);
    put(h.fetches);
  }
};

// The whole per-fragment chain of the techniques, written once.
template <class F>
void run_chain(const FloatField& f, const HeightField& hf, const glm::mat4& vp, glm::vec3 eye,
               V3<F> wpos, V3<F> N, V3<F> T, F sign, F scale, V3<F> L, mask_t<F> active,
               SearchHit<F>* hits, ShadowResult<F>* sh, F* extra) {
  TangentFrame<F> fr = make_tangent_frame(N, T, sign);
  V3<F> w = world_view_dir(wpos, eye, false, glm::vec3(0, 0, -1), -fr.n);
  V3<F> V = fr.to_tangent(w);
  V2<F> ds = texture_step(V, scale);
  V2<F> uv(wpos.x * F(0.37f), wpos.z * F(0.41f));
  F n = relief_step_count(V.z, 8.0f, 48.0f);
  hits[0] = linear_search(f, uv, ds, n, active);
  hits[1] = relief_search(f, uv, ds, n, 6, active);
  hits[2] = pom_search(f, uv, ds, n, active);
  hits[3] = steep_parallax_search(f, uv, ds, n, active);
  hits[4] = parallax_offset(f, uv, ds, V.z, false, active);
  hits[5] = parallax_offset(f, uv, ds, V.z, true, active);
  hits[6] = exact_search(hf, uv, ds, active);
  V3<F> Lt = fr.to_tangent(L);
  V2<F> dl = light_step(Lt, scale);
  sh[0] = self_shadow(f, hits[1].uv, hits[1].depth, dl, Lt.z, 24, 1e-3f, active);
  sh[1] = self_shadow<true>(f, hits[1].uv, hits[1].depth, dl, Lt.z, 24, 1e-3f, active);
  F st;
  extra[0] = exact_shadow(hf, hits[6].uv, hits[6].depth, dl, Lt.z, 1e-4f, active, &st);
  extra[1] = st;
  V3<F> hit = hit_world_position(wpos, w, V.z, hits[1].depth, scale * F(2.0f));
  extra[2] = reversed_z_depth(vp, hit, F(0.5f));
  extra[3] = ds.x;
  extra[4] = V.z;
}

TEST(KernelLanes, FloatAndF8AreBitIdentical) {
  FloatField f = testing::thin_walls(32, 6, 31);
  HeightField hf = f.exact();
  glm::mat4 vp(0.0f);
  vp[0][0] = 1.0f;
  vp[1][1] = 1.0f;
  vp[2][3] = -1.0f;
  vp[3][2] = 0.1f;
  const glm::vec3 eye(0.2f, 3.0f, 4.0f);
  std::mt19937 rng(32);
  std::uniform_real_distribution<float> c(-1.0f, 1.0f), u01(0.0f, 1.0f);
  const int kRays = 100000;
  long compared = 0;
  for (int b = 0; b < kRays / 8; ++b) {
    Batch in;
    for (int i = 0; i < 8; ++i) {
      in.wx[i] = 2.0f * c(rng);
      in.wy[i] = 0.05f * c(rng);
      in.wz[i] = 2.0f * c(rng);
      in.nx[i] = 0.3f * c(rng);
      in.ny[i] = 1.0f;
      in.nz[i] = 0.3f * c(rng);
      in.tx[i] = 1.0f;
      in.ty[i] = 0.2f * c(rng);
      in.tz[i] = 0.2f * c(rng);
      in.sign[i] = c(rng) < 0.0f ? -1.0f : 1.0f;
      in.scale[i] = 0.1f * u01(rng);
      in.lx[i] = c(rng);
      in.ly[i] = c(rng);
      in.lz[i] = c(rng);
      in.active[i] = u01(rng) > 0.1f;
    }
    // F8
    auto ld = [](const float* p) { return F8::load(p); };
    M8 act8 = F8(0.0f) != F8(0.0f);
    for (int i = 0; i < 8; ++i) set_lane(act8, i, in.active[i]);
    SearchHit<F8> h8[7];
    ShadowResult<F8> s8[2];
    F8 e8[5];
    run_chain<F8>(f, hf, vp, eye, V3<F8>(ld(in.wx), ld(in.wy), ld(in.wz)),
                  V3<F8>(ld(in.nx), ld(in.ny), ld(in.nz)), V3<F8>(ld(in.tx), ld(in.ty), ld(in.tz)),
                  ld(in.sign), ld(in.scale), V3<F8>(ld(in.lx), ld(in.ly), ld(in.lz)), act8, h8, s8,
                  e8);
    for (int i = 0; i < 8; ++i) {
      SearchHit<float> h1[7];
      ShadowResult<float> s1[2];
      float e1[5];
      run_chain<float>(f, hf, vp, eye, V3<float>(in.wx[i], in.wy[i], in.wz[i]),
                       V3<float>(in.nx[i], in.ny[i], in.nz[i]),
                       V3<float>(in.tx[i], in.ty[i], in.tz[i]), in.sign[i], in.scale[i],
                       V3<float>(in.lx[i], in.ly[i], in.lz[i]), in.active[i], h1, s1, e1);
      Out a, o;
      for (int k = 0; k < 7; ++k) {
        a.put(h1[k]);
        o.put(SearchHit<float>{V2<float>(lane(h8[k].uv.x, i), lane(h8[k].uv.y, i)),
                               lane(h8[k].depth, i), lane(h8[k].steps, i), lane(h8[k].fetches, i)});
      }
      for (int k = 0; k < 2; ++k) {
        a.put(s1[k].visibility);
        a.put(s1[k].steps);
        a.put(s1[k].fetches);
        o.put(lane(s8[k].visibility, i));
        o.put(lane(s8[k].steps, i));
        o.put(lane(s8[k].fetches, i));
      }
      for (int k = 0; k < 5; ++k) {
        a.put(e1[k]);
        o.put(lane(e8[k], i));
      }
      ASSERT_EQ(a.n, o.n);
      for (int k = 0; k < a.n; ++k) {
        ASSERT_EQ(bits(a.v[k]), bits(o.v[k])) << "batch " << b << " lane " << i << " output " << k
                                              << ": " << a.v[k] << " vs " << o.v[k];
        ASSERT_TRUE(std::isfinite(a.v[k])) << k;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, kRays);
}

TEST(KernelLanes, DegenerateRaysAreFinite) {
  for (Wrap wrap : {Wrap::kRepeat, Wrap::kClamp}) {
    FloatField f = testing::thin_walls(32, 5, 33);
    f.wrap_u = f.wrap_v = wrap;
    HeightField hf = f.exact();
    const float g = 0.01f * static_cast<float>(M_PI / 180.0);
    const V3<float> views[] = {V3<float>(std::cos(g), 0.0f, -std::sin(g)),
                               V3<float>(0.0f, -std::cos(g), -std::sin(g)),
                               V3<float>(0.0f, 0.0f, -1.0f), V3<float>(0.8f, 0.0f, 0.6f)};
    for (V3<float> V : views) {
      for (float scale : {0.0f, 0.05f, 0.5f}) {
        V2<float> ds = texture_step(V, scale);
        V2<float> uv(0.31f, 0.77f);
        float n = relief_step_count(V.z, 8.0f, 64.0f);
        const SearchHit<float> hits[] = {relief_search(f, uv, ds, n, 8, true),
                                         pom_search(f, uv, ds, n, true),
                                         steep_parallax_search(f, uv, ds, n, true),
                                         parallax_offset(f, uv, ds, V.z, false, true),
                                         parallax_offset(f, uv, ds, V.z, true, true),
                                         exact_search(hf, uv, ds, true)};
        for (const SearchHit<float>& h : hits) {
          EXPECT_TRUE(std::isfinite(h.uv.x) && std::isfinite(h.uv.y)) << V.x << " " << scale;
          EXPECT_GE(h.depth, 0.0f);
          EXPECT_LE(h.depth, 1.0f);
          if (scale == 0.0f) {
            EXPECT_EQ(h.uv.x, uv.x);
          }
        }
        V2<float> dl = light_step(V3<float>(-V.x, -V.y, -V.z), scale);
        ShadowResult<float> s =
            self_shadow(f, hits[0].uv, hits[0].depth, dl, -V.z, 32, 1e-3f, true);
        EXPECT_TRUE(s.visibility == 0.0f || s.visibility == 1.0f);
        float e = exact_shadow(hf, hits[5].uv, hits[5].depth, dl, -V.z, 1e-4f, true);
        EXPECT_TRUE(e == 0.0f || e == 1.0f);
      }
    }
  }
}

}  // namespace
}  // namespace relief
