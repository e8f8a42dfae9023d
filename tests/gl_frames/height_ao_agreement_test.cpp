// Height-field ambient occlusion on the GL backend (gl/shaders/relief_shell.glsl height_ao_factor)
// against the CPU (shaders_cpp/height_ao.h): the built-in plane with a strong ambient light, so
// the occlusion is most of the picture, agrees at >= 35 dB (sRGB PSNR, the metric of
// agreement_test.cpp) with AO on, for the relief and pom searches; the CPU frame without AO is
// far from it (an AO-less twin would fail).
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "render/render.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

constexpr int kW = 128, kH = 80;

Image render(Backend& backend, const Scene& s, const RenderOptions& opt) {
  Result<Plan> plan = make_plan(s, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> r = backend.render(s, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer.color : Image{};
}

TEST(GlHeightAo, AgreesWithCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl =
      make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<Scene> s = make_builtin_scene("plane");
  ASSERT_TRUE(s.ok());
  s->ambient = glm::vec3(0.7f);  // the occluded term dominates
  for (const char* technique : {"relief", "pom"}) {
    SCOPED_TRACE(technique);
    RenderOptions opt;
    opt.width = kW;
    opt.height = kH;
    opt.technique = technique;
    const Image cpu_off = render(*cpu, *s, opt);
    opt.height_ao_rays = 8;
    const Image cpu_on = render(*cpu, *s, opt);
    const Image gl_on = render(**gl, *s, opt);
    const ImageDiff d = compare_images(cpu_on, gl_on, 8.0f / 255.0f);
    const ImageDiff effect = compare_images(cpu_on, cpu_off, 8.0f / 255.0f);
    std::printf("[ measure  ] %s: GL vs CPU with AO %.2f dB; CPU AO on vs off %.2f dB\n", technique,
                d.psnr_db, effect.psnr_db);
    EXPECT_GE(d.psnr_db, 35.0);
    EXPECT_LT(effect.psnr_db, 30.0) << "AO changes too little for the agreement to mean much";
  }
}

}  // namespace
}  // namespace relief
