// `shells` on the GL backend against the CPU (the agreement metric of agreement_test.cpp: PSNR >=
// 35 dB, at most 0.5% of the pixels off by more than 8/255): the layered geometry comes from the
// shared prepare stage, the coverage test and the shading from the twin. On `plane` (no shadow
// pass) with and without the self-shadow darkening, and on `room`, whose spot light's shadow pass
// draws the shells with their alpha-tested shadow-pass variant and every material receives.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "tests/gl/gl_agreement.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

TEST(GlShells, MatchesCpu) {
  RELIEF_REQUIRE_GL();
  Backend* gl = gl::testing::shared_gl_backend();
  ASSERT_NE(gl, nullptr);
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 0});
  struct Case {
    const char* scene;
    int layers;
    bool self_shadow;
  };
  for (const Case& c : {Case{"plane", 8, true}, Case{"plane", 32, false}, Case{"room", 16, true}}) {
    const std::string label = std::string(c.scene) + " layers=" + std::to_string(c.layers) +
                              (c.self_shadow ? " self_shadow" : "");
    SCOPED_TRACE(label);
    Result<Scene> scene = make_builtin_scene(c.scene);
    ASSERT_TRUE(scene.ok()) << scene.status().message();
    RenderOptions opt;
    opt.width = 256;
    opt.height = 192;
    opt.technique = "shells";
    opt.params["layers"] = std::to_string(c.layers);
    opt.self_shadow = c.self_shadow;
    Result<Plan> plan = make_plan(*scene, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> rc = cpu->render(*scene, *plan);
    ASSERT_TRUE(rc.ok()) << rc.status().message();
    Result<RenderResult> rg = gl->render(*scene, *plan);
    ASSERT_TRUE(rg.ok()) << rg.status().message();
    ASSERT_EQ(rc->passes.size(), rg->passes.size());
    const ImageDiff d =
        compare_images(rc->framebuffer.color, rg->framebuffer.color, gl::testing::kThreshold);
    const double off = static_cast<double>(d.over_count) / (256.0 * 192.0);
    std::printf("[ measure  ] shells %s: PSNR %.2f dB, over 8/255 %.3f%%, %zu passes\n",
                label.c_str(), d.psnr_db, 100.0 * off, rc->passes.size());
    EXPECT_GE(d.psnr_db, gl::testing::kMinPsnr);
    EXPECT_LE(off, gl::testing::kMaxOverFraction);
  }
}

}  // namespace
}  // namespace relief
