// The environment bake (bake/environment_bake.h) and its lookups (shaders_cpp/environment.h):
// constant environments, SH of a known function, a bright texel's lobe against roughness, the
// split-sum table against brute-force quadrature, determinism, the octahedral layout and float vs
// lanes bit agreement.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

#include "bake/environment_bake.h"
#include "shaders_cpp/environment.h"
#include "tests/shaders_cpp/float_bits.h"

namespace relief {
namespace {

using testing::float_bits;
constexpr double kPi = 3.14159265358979323846;

// Small maps: quick to bake, same code paths.
EnvironmentBakeOptions small_options() {
  EnvironmentBakeOptions o;
  o.specular_size = 64;
  o.specular_samples = 128;
  o.lut_size = 32;
  o.lut_samples = 512;
  return o;
}

Image constant_image(int w, int h, float value) {
  return Image(w, h, glm::vec4(value, value, value, 1.0f));
}

std::vector<glm::vec3> test_directions() {
  std::vector<glm::vec3> d;
  for (int i = 0; i < 200; ++i) {  // a Fibonacci sphere, plus the axes
    const double y = 1.0 - (i + 0.5) / 100.0, r = std::sqrt(1.0 - y * y);
    const double phi = i * 2.39996322972865332;
    d.emplace_back(r * std::cos(phi), y, r * std::sin(phi));
  }
  for (glm::vec3 a : {glm::vec3(1, 0, 0), glm::vec3(0, 1, 0), glm::vec3(0, 0, 1)}) {
    d.push_back(a);
    d.push_back(-a);
  }
  return d;
}

V3<float> v3(glm::vec3 d) {
  return V3<float>(d.x, d.y, d.z);
}

TEST(EnvironmentBake, ConstantEnvironmentGivesConstantIrradianceAndSpecular) {
  // 0.75 is exact in half floats; the texel-centre projection's error falls as 1 / height^2
  // (1.2e-4 relative at 128x64, 8e-6 at 512x256).
  const float L = 0.75f;
  Result<EnvironmentMaps> maps = bake_environment(constant_image(512, 256, L), small_options());
  ASSERT_TRUE(maps.ok()) << maps.status().message();
  const EnvironmentView view;
  for (glm::vec3 d : test_directions()) {
    const V3<float> e = env_irradiance(*maps, view, v3(d));
    EXPECT_NEAR(e.x, L, 1e-4 * L);
    EXPECT_NEAR(e.z, L, 1e-4 * L);
    for (float rough : {0.0f, 0.1f, 0.25f, 0.6f, 1.0f}) {
      const V3<float> s = env_specular(*maps, view, v3(d), rough);
      EXPECT_NEAR(s.y, L, 1e-3 * L) << rough;
    }
  }
  const V3<float> bright = env_irradiance(*maps, environment_view(33.0f, 2.0f), v3({0, 0, 1}));
  EXPECT_NEAR(bright.x, 2.0f * L, 2e-4 * L);  // intensity scales
}

TEST(EnvironmentBake, ShOfOnePlusYGivesTheAnalyticIrradiance) {
  // L(d) = 1 + d.y: E(n) / pi = 1 + (2/3) n.y (band 1 scaled by A1 / pi).
  Image img(256, 128);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::vec3 d = equirect_direction((x + 0.5) / img.width, (y + 0.5) / img.height);
      img.at(x, y) = glm::vec4(1.0f + d.y, 1.0f + d.y, 1.0f + d.y, 1.0f);
    }
  EnvironmentMaps maps;
  maps.sh = environment_sh(img, 2);
  for (glm::vec3 d : test_directions()) {
    const V3<float> e = env_irradiance(maps, EnvironmentView{}, v3(d));
    EXPECT_NEAR(e.x, 1.0 + 2.0 / 3.0 * d.y, 2e-4) << d.x << " " << d.y << " " << d.z;
  }
  // Turned about +Y, a function of y alone does not change.
  const V3<float> e = env_irradiance(maps, environment_view(70.0f, 1.0f), v3({0.6f, 0.8f, 0.0f}));
  EXPECT_NEAR(e.x, 1.0 + 2.0 / 3.0 * 0.8, 2e-4);
}

TEST(EnvironmentBake, EquirectConventionAndRotation) {
  // Centre column looks along -Z, u = 0.75 along +X, the top row along +Y.
  const glm::vec3 c = equirect_direction(0.5, 0.5), x = equirect_direction(0.75, 0.5);
  EXPECT_NEAR(c.z, -1.0f, 1e-6);
  EXPECT_NEAR(x.x, 1.0f, 1e-6);
  EXPECT_NEAR(equirect_direction(0.3, 0.0).y, 1.0f, 1e-6);
  const glm::vec2 uv = equirect_uv({1.0f, 0.0f, 0.0f});
  EXPECT_NEAR(uv.x, 0.75f, 1e-6);
  EXPECT_NEAR(uv.y, 0.5f, 1e-6);
  // An environment turned by +90 degrees shows at world +X what it held at -Z... no: R_y(90)
  // takes -Z to -X, so the lookup at world -X reads the environment's -Z.
  const V3<float> e = env_direction(environment_view(90.0f, 1.0f), V3<float>(-1.0f, 0.0f, 0.0f));
  EXPECT_NEAR(e.z, -1.0f, 1e-6);
  EXPECT_NEAR(e.x, 0.0f, 1e-6);
}

// The lobe of env_specular around `peak`, over a fine equirect grid: the solid angle (sr) where
// it exceeds half its peak value, and its second moment, the mean of (1 - cos angle) weighted by
// the value (half-max alone does not grow between levels: trilinear blends a narrow peak that
// sets the maximum with a wide lobe below half of it).
struct Lobe {
  double half_max_sr = 0.0;
  double moment = 0.0;
};
Lobe lobe(const EnvironmentMaps& maps, float rough, glm::vec3 peak_dir) {
  const int w = 1024, h = 512;
  std::vector<float> v(static_cast<size_t>(w) * h);
  float peak = 0.0f;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec3 d = equirect_direction((x + 0.5) / w, (y + 0.5) / h);
      v[size_t(y) * w + x] = env_specular(maps, EnvironmentView{}, v3(d), rough).x;
      peak = std::max(peak, v[size_t(y) * w + x]);
    }
  Lobe out;
  double total = 0.0;
  for (int y = 0; y < h; ++y) {
    const double band = (2.0 * kPi / w) * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
    for (int x = 0; x < w; ++x) {
      const float value = v[size_t(y) * w + x];
      const glm::vec3 d = equirect_direction((x + 0.5) / w, (y + 0.5) / h);
      const double c = d.x * peak_dir.x + d.y * peak_dir.y + d.z * peak_dir.z;
      out.half_max_sr += value > 0.5f * peak ? band : 0.0;
      out.moment += value * (1.0 - c) * band;
      total += value * band;
    }
  }
  out.moment /= total;
  return out;
}

TEST(EnvironmentBake, BrightTexelLobeWidensWithRoughness) {
  Image img(256, 128);
  img.at(128, 64) = glm::vec4(1000.0f, 1000.0f, 1000.0f, 1.0f);  // just below the horizon, -Z
  const glm::vec3 peak_dir = equirect_direction(128.5 / 256, 64.5 / 128);
  EnvironmentBakeOptions o = small_options();
  o.specular_size = 128;
  Result<EnvironmentMaps> maps = bake_environment(img, o);
  ASSERT_TRUE(maps.ok());
  const double source_texel = (2.0 * kPi / 256) * (kPi / 128);
  const double output_texel = 4.0 * kPi / (128.0 * 128.0);
  double last_moment = 0.0, last_sr = 0.0;
  for (float rough : {0.0f, 0.125f, 0.25f, 0.375f, 0.5f, 0.625f, 0.75f, 0.875f, 1.0f}) {
    const Lobe l = lobe(*maps, rough, peak_dir);
    std::printf("roughness %.3f: half-max lobe %.5f sr, mean 1 - cos %.5f\n", rough, l.half_max_sr,
                l.moment);
    EXPECT_GT(l.moment, last_moment) << rough;
    EXPECT_GE(l.half_max_sr, last_sr) << rough;
    last_moment = l.moment;
    last_sr = l.half_max_sr;
    if (rough == 0.0f) {
      EXPECT_GT(l.half_max_sr, 0.25 * std::max(source_texel, output_texel));
      EXPECT_LT(l.half_max_sr, 8.0 * std::max(source_texel, output_texel));
    }
  }
  EXPECT_GT(last_sr, 0.5);  // roughness 1: a lobe of a large part of the hemisphere
}

// Brute-force (A, B): midpoint quadrature of the glTF BRDF over the hemisphere of L.
glm::dvec2 quadrature_split_sum(double nv, double rough) {
  const double a2 = rough * rough * rough * rough;
  const glm::dvec3 v(std::sqrt(1.0 - nv * nv), 0.0, nv);
  const int nt = 2048, np = 512;
  double a = 0.0, b = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double t = (i + 0.5) * (kPi / 2) / nt;
    for (int j = 0; j < np; ++j) {
      const double p = (j + 0.5) * 2.0 * kPi / np;
      const glm::dvec3 l(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
      glm::dvec3 h = l + v;
      h /= std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
      const double nh = h.z, vh = v.x * h.x + v.y * h.y + v.z * h.z;
      const double dd = nh * nh * (a2 - 1.0) + 1.0;
      const double d = a2 / (kPi * dd * dd);
      const double f = d * smith_visibility(l.z, nv, a2) * l.z;
      const double sr = std::sin(t) * ((kPi / 2) / nt) * (2.0 * kPi / np);
      const double fc = std::pow(1.0 - vh, 5.0);
      a += (1.0 - fc) * f * sr;
      b += fc * f * sr;
    }
  }
  return {a, b};
}

TEST(EnvironmentBake, SplitSumTableAgreesWithQuadratureAndNeverGainsEnergy) {
  Result<EnvironmentMaps> maps = bake_environment(constant_image(16, 8, 1.0f), small_options());
  ASSERT_TRUE(maps.ok());
  const Texture& lut = maps->brdf_lut;
  const int n = lut.width();
  double worst = 0.0;
  int worst_i = 0, worst_j = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::vec4 ab = lut.fetch(0, i, j);
      EXPECT_LE(ab.x + ab.y, 1.0f + 1e-3f) << i << " " << j;
      EXPECT_GE(ab.x, 0.0f);
      EXPECT_GE(ab.y, 0.0f);
      if (j == 0) {  // roughness 1/64: a mirror
        EXPECT_NEAR(ab.x + ab.y, 1.0f, 0.01f) << i;
      }
      if (1.0 - (ab.x + ab.y) > worst) {
        worst = 1.0 - (ab.x + ab.y);
        worst_i = i;
        worst_j = j;
      }
    }
  std::printf("worst single-scattering loss in the %dx%d table: %.3f at texel (%d, %d)\n", n, n,
              worst, worst_i, worst_j);
  std::printf("loss 1 - (A + B) | NdotV 0.05 | 0.25 | 0.5 | 1.0\n");  // docs/environment.md
  for (float rough : {0.0f, 0.25f, 0.5f, 0.75f, 1.0f}) {
    std::printf("roughness %.2f", rough);
    for (float nv : {0.05f, 0.25f, 0.5f, 1.0f}) {
      const glm::vec2 ab = integrate_split_sum(nv, rough, 4096);
      std::printf(" | %.3f", 1.0f - (ab.x + ab.y));
    }
    std::printf("\n");
  }
  for (double nv : {0.2, 0.5, 0.9})
    for (double rough : {0.3, 0.6, 1.0}) {
      const glm::dvec2 q = quadrature_split_sum(nv, rough);
      const glm::vec2 s =
          integrate_split_sum(static_cast<float>(nv), static_cast<float>(rough), 1024);
      EXPECT_NEAR(s.x, q.x, 0.01) << nv << " " << rough;
      EXPECT_NEAR(s.y, q.y, 0.01) << nv << " " << rough;
      // The table's bilinear read between texel centres stays close too.
      const V2<float> t = env_brdf(*maps, static_cast<float>(nv), static_cast<float>(rough));
      EXPECT_NEAR(t.x, q.x, 0.02) << nv << " " << rough;
      EXPECT_NEAR(t.y, q.y, 0.02) << nv << " " << rough;
    }
}

bool same_texture(const Texture& a, const Texture& b) {
  if (a.levels() != b.levels()) return false;
  for (int k = 0; k < a.levels(); ++k)
    if (a.level(k).data != b.level(k).data) return false;
  return true;
}

TEST(EnvironmentBake, SameBytesTwiceAndForAnyThreadCount) {
  Image img = studio_environment(128, 64);
  img.at(3, 5) = glm::vec4(std::numeric_limits<float>::quiet_NaN(), 1.0f, -2.0f, 1.0f);
  img.at(7, 9) = glm::vec4(std::numeric_limits<float>::infinity());
  EnvironmentBakeOptions o = small_options();
  o.threads = 1;
  Result<EnvironmentMaps> a = bake_environment(img, o), b = bake_environment(img, o);
  o.threads = 2;
  Result<EnvironmentMaps> c = bake_environment(img, o);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->replaced_texels, 2);
  for (const Result<EnvironmentMaps>* m : {&b, &c}) {
    EXPECT_EQ(std::memcmp(a->sh.data(), (*m)->sh.data(), sizeof(a->sh)), 0);
    EXPECT_TRUE(same_texture(a->specular, (*m)->specular));
    EXPECT_TRUE(same_texture(a->brdf_lut, (*m)->brdf_lut));
  }
  for (int k = 0; k < a->specular.levels(); ++k)
    for (int y = 0; y < a->specular.height(k); ++y)
      for (int x = 0; x < a->specular.width(k); ++x) {
        const glm::vec4 t = a->specular.fetch(k, x, y);
        ASSERT_TRUE(std::isfinite(t.x) && t.x >= 0.0f && t.y >= 0.0f && t.z >= 0.0f);
      }
}

TEST(EnvironmentBake, RefusesEmptyAndOversizedInputsAndBadOptions) {
  EXPECT_FALSE(bake_environment(Image()).ok());
  EnvironmentBakeOptions o;
  o.specular_size = 100;  // not a power of two
  EXPECT_FALSE(bake_environment(constant_image(8, 4, 1.0f), o).ok());
  Image huge;  // the limit is checked from the size, before any texel is read
  huge.width = 16384;
  huge.height = 8192;
  huge.pixels.resize(1);
  EXPECT_FALSE(bake_environment(huge).ok());
}

TEST(EnvironmentBake, OctahedralRoundTrip) {
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const V2<float> uv((x + 0.5f) / 64, (y + 0.5f) / 64);
      const V3<float> d = octahedral_direction(uv);
      EXPECT_NEAR(d.x * d.x + d.y * d.y + d.z * d.z, 1.0f, 1e-5f);
      const V2<float> back = octahedral_uv(d);
      EXPECT_NEAR(back.x, uv.x, 1e-6f);
      EXPECT_NEAR(back.y, uv.y, 1e-6f);
    }
  for (glm::vec3 g : test_directions()) {
    const V3<float> d = octahedral_direction(octahedral_uv(v3(g)));
    EXPECT_NEAR(d.x, g.x, 1e-5f);
    EXPECT_NEAR(d.y, g.y, 1e-5f);
    EXPECT_NEAR(d.z, g.z, 1e-5f);
  }
  const V2<float> up = octahedral_uv(V3<float>(0.0f, 1.0f, 0.0f));  // the centre
  EXPECT_EQ(up.x, 0.5f);
  EXPECT_EQ(up.y, 0.5f);
  const V2<float> px = octahedral_uv(V3<float>(1.0f, 0.0f, 0.0f));  // u toward +X
  EXPECT_EQ(px.x, 1.0f);
  EXPECT_EQ(px.y, 0.5f);
}

TEST(EnvironmentBake, LanesAgreeWithFloatBitForBit) {
  Result<EnvironmentMaps> maps = bake_environment(studio_environment(128, 64), small_options());
  ASSERT_TRUE(maps.ok());
  const EnvironmentView view = environment_view(-37.0f, 1.3f);
  const std::vector<glm::vec3> dirs = test_directions();
  for (size_t base = 0; base + 8 <= dirs.size(); base += 8) {
    F8 x, y, z, rough, nv;
    for (int i = 0; i < 8; ++i) {
      x.set(i, dirs[base + i].x);
      y.set(i, dirs[base + i].y);
      z.set(i, dirs[base + i].z);
      rough.set(i, static_cast<float>((base + i) % 23) / 20.0f - 0.05f);  // out of range too
      nv.set(i, static_cast<float>((base + 3 * i) % 17) / 16.0f);
    }
    const V3<F8> d(x, y, z);
    const V3<F8> e8 = env_irradiance(*maps, view, d), s8 = env_specular(*maps, view, d, rough);
    const V2<F8> b8 = env_brdf(*maps, nv, rough);
    const V2<F8> o8 = octahedral_uv(d);
    for (int i = 0; i < 8; ++i) {
      const V3<float> di(lane(x, i), lane(y, i), lane(z, i));
      const V3<float> e = env_irradiance(*maps, view, di);
      const V3<float> s = env_specular(*maps, view, di, lane(rough, i));
      const V2<float> b = env_brdf(*maps, lane(nv, i), lane(rough, i));
      const V2<float> o = octahedral_uv(di);
      EXPECT_EQ(float_bits(lane(e8.x, i)), float_bits(e.x));
      EXPECT_EQ(float_bits(lane(e8.z, i)), float_bits(e.z));
      EXPECT_EQ(float_bits(lane(s8.y, i)), float_bits(s.y));
      EXPECT_EQ(float_bits(lane(b8.x, i)), float_bits(b.x));
      EXPECT_EQ(float_bits(lane(b8.y, i)), float_bits(b.y));
      EXPECT_EQ(float_bits(lane(o8.x, i)), float_bits(o.x));
      EXPECT_EQ(float_bits(lane(o8.y, i)), float_bits(o.y));
    }
  }
}

TEST(EnvironmentBake, StudioEnvironmentIsNeutralFiniteAndMidBright) {
  const Image img = studio_environment(256, 128);
  double sum = 0.0, sr_total = 0.0;
  float lo = 1e30f, hi = 0.0f;
  for (int y = 0; y < img.height; ++y) {
    const double band = (2.0 * kPi / img.width) *
                        (std::cos(kPi * y / img.height) - std::cos(kPi * (y + 1) / img.height));
    for (int x = 0; x < img.width; ++x) {
      const glm::vec4 p = img.at(x, y);
      ASSERT_TRUE(std::isfinite(p.x));
      ASSERT_EQ(p.x, p.y);
      ASSERT_EQ(p.x, p.z);
      lo = std::min(lo, p.x);
      hi = std::max(hi, p.x);
      sum += p.x * band;
      sr_total += band;
    }
  }
  const double mean = sum / sr_total;
  std::printf("studio: mean radiance %.3f, min %.3f, max %.3f\n", mean, lo, hi);
  EXPECT_GT(mean, 0.5);
  EXPECT_LT(mean, 1.0);
  EXPECT_GT(lo, 0.0f);
  EXPECT_GT(hi, 4.0f);  // a key light that casts a highlight
  // Brighter overhead than below the horizon.
  EXPECT_GT(img.at(10, 2).x, img.at(10, img.height - 3).x);
}

}  // namespace
}  // namespace relief
