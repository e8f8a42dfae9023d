// Image-based light (docs/environment.md) on the GL backend against the CPU one: built-in scenes
// with their lights removed, so that make_plan lights them with the built-in studio environment,
// turned (35 degrees) and scaled (intensity 1.4), with every material metallic-roughness (a
// different metallic and roughness each) or Blinn-Phong, through the twins of every lighting call
// site (flat, normal, the relief shell, relief_dual, relief_quadric, a cone search). 320x240, the
// agreement metric of agreement_test.cpp: sRGB RGB PSNR >= 35 dB and at most 0.5% of the pixels
// off by more than 8/255; both images finite, and the environment must change the image (the
// same frame with the scene's ambient colour instead differs).
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "tests/gl/gl_agreement.h"
#include "tests/gl/gl_test_util.h"

namespace relief {
namespace {

using gl::testing::kMaxOverFraction;
using gl::testing::kMinPsnr;
using gl::testing::kThreshold;

constexpr int kWidth = 320;
constexpr int kHeight = 240;

bool finite_image(const Image& img) {
  for (const glm::vec4& p : img.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(p.w))
      return false;
  return true;
}

// The scene without lights; every material metallic-roughness with metallic and roughness spread
// over [0, 1] (the floor keeps its roughness texture), or Blinn-Phong.
Scene unlit_by_lights(const Scene& s, ShadingModel shading) {
  Scene out = s;
  out.lights.clear();
  const float metallic[] = {1.0f, 0.0f, 0.6f, 1.0f, 0.0f};
  const float roughness[] = {0.1f, 0.45f, 0.8f, 0.6f, 0.3f};
  for (size_t i = 0; i < out.materials.size(); ++i) {
    Material& m = out.materials[i];
    m.shading = shading;
    m.metallic = metallic[i % 5];
    if (!m.metallic_roughness_texture) m.roughness = roughness[i % 5];
  }
  return out;
}

struct Case {
  const char* scene;
  const char* technique;
  ShadingModel shading;
};
// gtest's name for a case in ctest's list (not its bytes).
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.scene << " / " << c.technique << (c.shading == ShadingModel::kBlinnPhong ? " bp" : "");
}

void expect_environment_agreement(const Case& c) {
  const std::string label = std::string(c.scene) + " / " + c.technique +
                            (c.shading == ShadingModel::kBlinnPhong ? " (Blinn-Phong)" : "");
  SCOPED_TRACE(label);
  Result<Scene> builtin = make_builtin_scene(c.scene);
  ASSERT_TRUE(builtin.ok()) << builtin.status().message();
  const Scene scene = unlit_by_lights(*builtin, c.shading);
  RenderOptions opt;
  opt.width = kWidth;
  opt.height = kHeight;
  opt.technique = c.technique;
  opt.env_view = environment_view(35.0f, 1.4f);
  Result<Plan> plan = make_plan(scene, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  ASSERT_NE(plan->frame.environment, nullptr) << "no studio environment for a scene without lights";
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<RenderResult> rc = cpu->render(scene, *plan);
  ASSERT_TRUE(rc.ok()) << rc.status().message();
  Backend* gl = gl::testing::shared_gl_backend();
  ASSERT_NE(gl, nullptr);
  Result<RenderResult> rg = gl->render(scene, *plan);
  ASSERT_TRUE(rg.ok()) << rg.status().message();
  EXPECT_TRUE(finite_image(rc->framebuffer.color));
  EXPECT_TRUE(finite_image(rg->framebuffer.color));
  const ImageDiff d = compare_images(rc->framebuffer.color, rg->framebuffer.color, kThreshold);
  const double off = static_cast<double>(d.over_count) / (static_cast<double>(kWidth) * kHeight);
  std::printf("[ measure  ] environment %s: PSNR %.2f dB, max %.1f/255, over 8/255 %.3f%%\n",
              label.c_str(), d.psnr_db, d.max_error * 255.0, 100.0 * off);
  EXPECT_GE(d.psnr_db, kMinPsnr);
  EXPECT_LE(off, kMaxOverFraction);
  // The environment reached the GL image: without it (the ambient colour) the frame differs.
  RenderOptions ambient = opt;
  ambient.studio_environment = false;
  Result<Plan> flat_plan = make_plan(scene, ambient);
  ASSERT_TRUE(flat_plan.ok()) << flat_plan.status().message();
  ASSERT_EQ(flat_plan->frame.environment, nullptr);
  Result<RenderResult> ra = gl->render(scene, *flat_plan);
  ASSERT_TRUE(ra.ok()) << ra.status().message();
  const ImageDiff lit = compare_images(ra->framebuffer.color, rg->framebuffer.color, kThreshold);
  EXPECT_GT(lit.over_count, static_cast<size_t>(kWidth * kHeight / 20));
}

// One case per test (ctest runs them side by side), named scene_technique[_blinn_phong].
class GlEnvironment : public ::testing::TestWithParam<Case> {};

TEST_P(GlEnvironment, MatchesCpu) {
  RELIEF_REQUIRE_GL();
  expect_environment_agreement(GetParam());
}

constexpr ShadingModel kMr = ShadingModel::kMetallicRoughness;
constexpr ShadingModel kBp = ShadingModel::kBlinnPhong;
INSTANTIATE_TEST_SUITE_P(
    StudioEnvironment, GlEnvironment,
    ::testing::Values(Case{"materials", "flat", kMr}, Case{"materials", "normal", kMr},
                      Case{"materials", "relief", kMr}, Case{"materials", "relaxed_cone", kMr},
                      Case{"materials", "relief_quadric", kMr},
                      Case{"impostor", "relief_dual", kMr}, Case{"materials", "normal", kBp},
                      Case{"materials", "relief", kBp}),
    [](const ::testing::TestParamInfo<Case>& i) {
      return std::string(i.param.scene) + "_" + i.param.technique +
             (i.param.shading == kBp ? "_blinn_phong" : "");
    });

// Maps the plan does not own (FrameUniforms::environment set by hand, Plan::environment null) go
// up for that frame only and give the image the cached upload of the same data gives, bit for bit;
// the cached maps still serve the next frame.
TEST(GlEnvironmentUpload, UnownedMapsGiveTheCachedImage) {
  RELIEF_REQUIRE_GL();
  Result<Scene> builtin = make_builtin_scene("materials");
  ASSERT_TRUE(builtin.ok()) << builtin.status().message();
  const Scene scene = unlit_by_lights(*builtin, ShadingModel::kMetallicRoughness);
  RenderOptions opt;
  opt.width = 96;
  opt.height = 72;
  opt.technique = "normal";
  Result<Plan> plan = make_plan(scene, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  ASSERT_NE(plan->environment, nullptr);
  Backend* gl = gl::testing::shared_gl_backend();
  ASSERT_NE(gl, nullptr);
  Result<RenderResult> cached = gl->render(scene, *plan);
  ASSERT_TRUE(cached.ok()) << cached.status().message();
  const EnvironmentMaps copy = *plan->environment;
  Plan unowned = *plan;
  unowned.environment = nullptr;
  unowned.frame.environment = &copy;
  Result<RenderResult> once = gl->render(scene, unowned);
  ASSERT_TRUE(once.ok()) << once.status().message();
  EXPECT_EQ(cached->framebuffer.color.pixels, once->framebuffer.color.pixels);
  Result<RenderResult> again = gl->render(scene, *plan);
  ASSERT_TRUE(again.ok()) << again.status().message();
  EXPECT_EQ(cached->framebuffer.color.pixels, again->framebuffer.color.pixels);
}

}  // namespace
}  // namespace relief
