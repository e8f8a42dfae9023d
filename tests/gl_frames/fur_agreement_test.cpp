// Fur and grass on the GL backend against the CPU (issue 27): steep parallax with the poster's
// depth-darkening self-shadow (`shadow=depth`, gl/shaders/steep_parallax.frag) agrees at >= 35 dB
// (sRGB PSNR, the metric of agreement_test.cpp), and the darkening changes the CPU frame far more
// than that (a twin that ignored it would fail).
#include <cstdio>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "render/render.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

constexpr int kW = 128, kH = 96;

Image render(Backend& backend, const Scene& s, const RenderOptions& opt) {
  Result<Plan> plan = make_plan(s, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> r = backend.render(s, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer.color : Image{};
}

RenderOptions options(const std::string& technique, std::map<std::string, std::string> params) {
  RenderOptions opt;
  opt.width = kW;
  opt.height = kH;
  opt.technique = technique;
  opt.params = std::move(params);
  return opt;
}

TEST(GlFur, SteepDepthShadowAgreesWithCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend();
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<Scene> s = make_builtin_scene("plane");
  ASSERT_TRUE(s.ok());
  const RenderOptions on =
      options("steep_parallax", {{"shadow", "depth"}, {"shadow_strength", "0.8"}});
  RenderOptions off = on;
  off.self_shadow = false;
  const Image cpu_on = render(*cpu, *s, on);
  const Image gl_on = render(**gl, *s, on);
  const ImageDiff d = compare_images(cpu_on, gl_on, 8.0f / 255.0f);
  const ImageDiff effect = compare_images(cpu_on, render(*cpu, *s, off), 8.0f / 255.0f);
  std::printf("[ measure  ] steep shadow=depth: GL vs CPU %.2f dB; CPU on vs off %.2f dB\n",
              d.psnr_db, effect.psnr_db);
  EXPECT_GE(d.psnr_db, 35.0);
  EXPECT_LT(effect.psnr_db, 30.0) << "the darkening changes too little for agreement to mean much";
}

}  // namespace
}  // namespace relief
