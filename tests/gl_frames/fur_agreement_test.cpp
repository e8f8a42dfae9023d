// Fur and grass on the GL backend against the CPU (issue 27; the agreement metric of
// agreement_test.cpp: PSNR >= 35 dB, at most 0.5% of the pixels off by more than 8/255).
// `shells`: the layered geometry comes from the shared prepare stage, the coverage test and the
// shading from the twin; on `plane` (no shadow pass) with and without the self-shadow darkening,
// on `room`, whose spot light's shadow pass draws the shells with their alpha-tested shadow-pass
// variant and every material receives, and on the `fur` scene. Steep parallax's `shadow=depth`
// (gl/shaders/steep_parallax.frag) on `plane` at strength 0.8 and on the `grass` scene (its own
// material); on `plane` the darkening also changes the CPU frame far more than the agreement
// allows (a twin that ignored it would fail).
#include <cstdio>
#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "tests/gl/gl_agreement.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

struct Case {
  const char* scene;
  const char* technique;
  std::map<std::string, std::string> params;
  bool self_shadow;
};

// The CPU and GL frames of one case (256x192), compared; the CPU frame for further checks.
Image agree(Backend& cpu, Backend& gl, const Case& c) {
  std::string label = std::string(c.scene) + " " + c.technique;
  for (const auto& [k, v] : c.params) label += " " + k + "=" + v;
  label += c.self_shadow ? " self_shadow" : "";
  SCOPED_TRACE(label);
  Result<Scene> scene = make_builtin_scene(c.scene);
  EXPECT_TRUE(scene.ok()) << scene.status().message();
  if (!scene.ok()) return {};
  RenderOptions opt;
  opt.width = 256;
  opt.height = 192;
  opt.technique = c.technique;
  opt.params = c.params;
  opt.self_shadow = c.self_shadow;
  Result<Plan> plan = make_plan(*scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> rc = cpu.render(*scene, *plan);
  Result<RenderResult> rg = gl.render(*scene, *plan);
  EXPECT_TRUE(rc.ok() && rg.ok());
  if (!rc.ok() || !rg.ok()) return {};
  EXPECT_EQ(rc->passes.size(), rg->passes.size());
  const ImageDiff d =
      compare_images(rc->framebuffer.color, rg->framebuffer.color, gl::testing::kThreshold);
  const double off = static_cast<double>(d.over_count) / (256.0 * 192.0);
  std::printf("[ measure  ] %s: PSNR %.2f dB, over 8/255 %.3f%%, %zu passes\n", label.c_str(),
              d.psnr_db, 100.0 * off, rc->passes.size());
  EXPECT_GE(d.psnr_db, gl::testing::kMinPsnr);
  EXPECT_LE(off, gl::testing::kMaxOverFraction);
  return rc->framebuffer.color;
}

TEST(GlFur, ShellsAndSteepDepthShadowMatchCpu) {
  RELIEF_REQUIRE_GL();
  Backend* gl = gl::testing::shared_gl_backend();
  ASSERT_NE(gl, nullptr);
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 0});
  for (const Case& c :
       {Case{"plane", "shells", {{"layers", "8"}}, true},
        Case{"plane", "shells", {{"layers", "32"}}, false},
        Case{"room", "shells", {{"layers", "16"}}, true},
        Case{"fur", "shells", {{"layers", "16"}}, true}, Case{"grass", "", {}, true}})
    agree(*cpu, *gl, c);
  // steep parallax's darkening: agreement, and a CPU frame far from the one without it
  const Case depth{
      "plane", "steep_parallax", {{"shadow", "depth"}, {"shadow_strength", "0.8"}}, true};
  const Image on = agree(*cpu, *gl, depth);
  Case off_case = depth;
  off_case.self_shadow = false;
  const Image off = agree(*cpu, *gl, off_case);
  EXPECT_LT(compare_images(on, off, gl::testing::kThreshold).psnr_db, 30.0)
      << "the darkening changes too little for the agreement to mean much";
}

}  // namespace
}  // namespace relief
