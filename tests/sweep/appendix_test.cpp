// The appendix yardstick (gl/appendix_relief.h, sweep/sweep.h AppendixRow): the relief paper's own
// shader on GL finds the hits the CPU backend's relief finds with the same steps at level 0,
// shades the diffuse term of its own hit, refuses what it cannot draw, and `run_sweep` reports it
// beside the rows when GL and relief are in the sweep.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "gl/appendix_relief.h"
#include "plugins/registry.h"
#include "render/render.h"
#include "sweep/sweep.h"
#include "tests/frames/cpu_frame.h"
#include "tests/sanitized.h"

namespace relief::sweep {
namespace {

// The yardstick's context, or why there is none (a sanitizer build: Mesa's allocations read as
// leaks of the instrumented program, as for test_gl).
std::unique_ptr<gl::AppendixRelief> yardstick(std::string& why) {
  if (test::kSanitizedBuild) {
    why = "a sanitizer build runs no GL";
    return nullptr;
  }
  Result<std::unique_ptr<gl::AppendixRelief>> a = gl::AppendixRelief::create();
  if (!a.ok()) {
    why = a.status().message();
    return nullptr;
  }
  return std::move(a).value();
}

Field field(size_t i) {
  Result<std::vector<Field>> b = builtin_fields();
  EXPECT_TRUE(b.ok());
  return b->at(i);
}

// The sweep's view with the yardstick's effects off, and the CPU side's options (the bench's own,
// sweep.h appendix_lean) with the hits as an AOV.
AppendixLean lean(const Field& f, double angle, int w, int h) {
  AppendixLean l = appendix_lean(view_scene(f, angle, w, h), w, h);
  l.options.aovs = aov_bit(Aov::kHitUv);
  return l;
}

// The paper's texture as the yardstick packs it: normal (rgb) and depth (a), RGBA8.
Texture packed(const Field& f) {
  const Texture& d = f.depth();
  const Texture& n = *f.material.textures.at("normal");
  const int w = d.width(), h = d.height();
  std::vector<float> v(static_cast<size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const glm::vec4 t = n.fetch(0, x * n.width() / w, y * n.height() / h);
      float* o = &v[(static_cast<size_t>(y) * w + x) * 4];
      o[0] = t.x;
      o[1] = t.y;
      o[2] = t.z;
      o[3] = d.fetch_r(0, x, y);
    }
  return Texture::from_floats(TexFormat::kRGBA8, w, h, v.data());
}

TEST(Appendix, FindsTheHitsOfCpuReliefAndShadesTheirDiffuse) {
  std::string why;
  std::unique_ptr<gl::AppendixRelief> a = yardstick(why);
  if (!a) GTEST_SKIP() << why;
  constexpr int kW = 96, kH = 72;
  for (size_t fi : {size_t{0}, size_t{1}}) {  // bricks, pattern
    const Field f = field(fi);
    const Texture rm = packed(f);
    SamplerState bilinear = f.material.sampler;
    bilinear.filter = Filter::kBilinear;
    for (double angle : {0.0, 40.0, 70.0}) {
      SCOPED_TRACE(f.name + " at " + std::to_string(angle) + " deg");
      const AppendixLean view = lean(f, angle, kW, kH);
      const Scene& scene = view.scene;
      ASSERT_TRUE(a->prepare(scene, kW, kH, kAppendixLinearSteps, kAppendixBinarySteps).ok());
      Image color, hits;
      ASSERT_TRUE(a->draw_hits(color, hits).ok());
      std::optional<Framebuffer> cpu = test::render_frame(scene, view.options);
      ASSERT_TRUE(cpu.has_value());
      // the same pixels, the same hits (within a texel), and the diffuse of the hit's normal
      const glm::vec3 l = glm::normalize(-scene.lights[0].direction);
      const glm::vec3 diffuse = glm::vec3(scene.materials[0].base_color) * scene.lights[0].color *
                                scene.lights[0].intensity;
      long covered = 0, coverage_differs = 0, same = 0, shade_off = 0;
      double lum_sum = 0.0, lum_sq = 0.0;
      for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
          const glm::vec4 g = hits.at(x, y);
          const bool gl_covers = g.w > 0.0f, cpu_covers = cpu->depth.at(x, y) > 0.0f;
          coverage_differs += gl_covers != cpu_covers;
          if (!gl_covers || !cpu_covers) continue;
          ++covered;
          const float* aov = cpu->aov_at(x, y);
          double du = aov[kAovOffset[0]] - g.x, dv = aov[kAovOffset[0] + 1] - g.y;
          du -= std::round(du);
          dv -= std::round(dv);
          same += std::hypot(du * f.depth().width(), dv * f.depth().height()) <= 1.0;
          // n = (0, 1, 0) on the sweep's quad, t = +x (u), b = +z (v)
          const glm::vec4 t = sample_lod(rm, bilinear, glm::vec2(g.x, g.y), 0.0f);
          const glm::vec3 nn = glm::normalize(glm::vec3(t.x * 2 - 1, t.z * 2 - 1, 1 - t.y * 2));
          const float att = std::clamp(l.y, 0.0f, 1.0f);
          const float diff = std::clamp(glm::dot(l, nn), 0.0f, 1.0f);
          const glm::vec3 want = scene.ambient * diffuse + att * diff * diffuse;
          const glm::vec4 c = color.at(x, y);
          const float err = std::max({std::fabs(c.r - std::min(want.r, 1.0f)),
                                      std::fabs(c.g - std::min(want.g, 1.0f)),
                                      std::fabs(c.b - std::min(want.b, 1.0f))});
          shade_off += err > 4.0f / 255.0f;
          const double lum = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
          lum_sum += lum;
          lum_sq += lum * lum;
        }
      ASSERT_GT(covered, kW * kH / 2);
      EXPECT_LE(coverage_differs, kW * kH / 200);
      std::printf("[ measure  ] %s at %.0f deg: same hit %.4f, shading off %.4f\n", f.name.c_str(),
                  angle, static_cast<double>(same) / covered,
                  static_cast<double>(shade_off) / covered);
      // At 70 degrees a linear step spans several of pattern's one-texel walls: where the
      // bracket holds more than one crossing, the appendix's halvings (its first re-reads the
      // inside sample, so four narrow the bracket) and its 8-bit depth can settle on another
      // crossing than ours (measured: 0.983 there, 0.9925 on bricks, >= 0.999 at 0 and 40).
      EXPECT_GE(static_cast<double>(same) / covered, angle < 60.0 ? 0.99 : 0.97);
      EXPECT_LE(static_cast<double>(shade_off) / covered, 0.01);
      // the relief shows: the shading varies over the frame
      const double mean = lum_sum / covered;
      EXPECT_GT(lum_sq / covered - mean * mean, 1e-4);
    }
  }
}

TEST(Appendix, RefusesWhatItCannotDraw) {
  std::string why;
  std::unique_ptr<gl::AppendixRelief> a = yardstick(why);
  if (!a) GTEST_SKIP() << why;
  const Field f = field(0);
  const Scene scene = lean(f, 30.0, 32, 32).scene;
  EXPECT_FALSE(a->prepare(scene, 32, 32, 1, 5).ok());
  EXPECT_FALSE(a->prepare(scene, 32, 32, 10, -1).ok());
  EXPECT_FALSE(a->prepare(scene, 0, 32, 10, 5).ok());
  Scene no_depth = scene;
  no_depth.materials[0].textures.erase("depth");
  const Status s = a->prepare(no_depth, 32, 32, 10, 5);
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no depth map"), std::string::npos) << s.message();
  Scene unlit = scene;
  unlit.lights.clear();
  EXPECT_FALSE(a->prepare(unlit, 32, 32, 10, 5).ok());
  Image c, h;
  ASSERT_TRUE(a->prepare(scene, 32, 32, 10, 5).ok());
  EXPECT_TRUE(a->draw_hits(c, h).ok());
  EXPECT_TRUE(a->draw().ok());
}

TEST(Appendix, SweepReportsItBesideTheRowsWhenReliefRunsOnGl) {
  std::string why;
  if (!yardstick(why)) GTEST_SKIP() << why;
  Options o;
  o.width = 48;
  o.height = 48;
  o.threads = 2;
  o.angles = {0, 60};
  o.warmup = 0;
  o.repeats = 2;
  o.gl = true;
  const Field f = field(1);
  const std::vector<Setting> relief = settings_for(*PluginRegistry::global().find("relief"), {8});
  Result<SweepResult> r = run_sweep({f}, relief, o);
  ASSERT_TRUE(r.ok()) << r.status().message();
  ASSERT_EQ(r->appendix.size(), 2u);  // one per angle
  for (const AppendixRow& a : r->appendix) {
    EXPECT_EQ(a.field, "pattern");
    EXPECT_TRUE(a.note.empty()) << a.note;
    EXPECT_GT(a.fragments, 48 * 48 / 2);
    EXPECT_GT(a.cpu_ns_median, 0.0);
    EXPECT_GT(a.gl_ns_median, 0.0);
    EXPECT_DOUBLE_EQ(a.speedup, a.gl_ns_median / a.cpu_ns_median);
    EXPECT_GE(a.same_hit_frac, 0.99);
  }
  EXPECT_NE(to_json(*r, RunInfo{}).find("\"appendix\""), std::string::npos);
  EXPECT_NE(format_appendix_table(r->appendix).find("pattern"), std::string::npos);
  // without relief, or without GL, no yardstick
  const std::vector<Setting> pom = settings_for(*PluginRegistry::global().find("pom"), {8});
  Result<SweepResult> p = run_sweep({f}, pom, o);
  ASSERT_TRUE(p.ok());
  EXPECT_TRUE(p->appendix.empty());
  o.gl = false;
  Result<SweepResult> c = run_sweep({f}, relief, o);
  ASSERT_TRUE(c.ok());
  EXPECT_TRUE(c->appendix.empty());
}

}  // namespace
}  // namespace relief::sweep
