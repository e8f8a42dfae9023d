// The GL backend against the CPU backend: every built-in scene with every technique that has a
// GLSL twin, rendered at 256x192 by both.
// Metric (render/compare.h, sRGB-encoded RGB): PSNR >= 35 dB and at most 0.5% of the pixels with
// a channel off by more than 8/255. Depth: where both cover a pixel, the view depths (recovered
// from the reversed-Z buffer through the camera's projection) agree within 1e-4 world units;
// pixels covered by one backend only count against the same 0.5% budget.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "gl/gl_backend.h"
#include "gl_test_util.h"
#include "plugins/registry.h"
#include "render/compare.h"
#include "scene/builtin.h"

namespace relief {
namespace {

constexpr int kWidth = 256;
constexpr int kHeight = 192;
constexpr double kMinPsnr = 35.0;
constexpr double kMaxOverFraction = 0.005;
constexpr float kThreshold = 8.0f / 255.0f;
constexpr double kMaxViewDepthError = 1e-4;

// View-space distance along the view axis for a reversed-Z depth value d (> 0).
double view_depth(const glm::mat4& p, float d) {
  // clip.z = A z + B, clip.w = C z + D for the camera's perspective or orthographic matrix.
  const double a = p[2][2], b = p[3][2], c = p[2][3], dd = p[3][3];
  const double z = (d * dd - b) / (a - d * c);
  return -z;
}

struct DepthAgreement {
  size_t coverage_mismatch = 0;
  size_t both = 0;
  double max_error = 0.0;
  size_t over = 0;  // both covered, error above the bound
};

DepthAgreement compare_depth(const Plane& cpu, const Plane& gl, const glm::mat4& proj) {
  DepthAgreement r;
  for (int y = 0; y < cpu.height; ++y)
    for (int x = 0; x < cpu.width; ++x) {
      const float a = cpu.at(x, y), b = gl.at(x, y);
      if ((a > 0.0f) != (b > 0.0f)) {
        ++r.coverage_mismatch;
        continue;
      }
      if (a <= 0.0f) continue;
      ++r.both;
      const double e = std::fabs(view_depth(proj, a) - view_depth(proj, b));
      r.max_error = std::max(r.max_error, e);
      if (e > kMaxViewDepthError) ++r.over;
    }
  return r;
}

TEST(GlAgreement, BuiltinScenesMatchCpu) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend(-1);
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  std::unique_ptr<Backend> cpu = make_cpu_backend(0);
  int compared = 0;
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    Result<Scene> scene = make_builtin_scene(info.name);
    ASSERT_TRUE(scene.ok()) << scene.status().message();
    for (const PluginDescriptor* plugin : PluginRegistry::global().all()) {
      if (!gl_has_twin(plugin->name)) continue;
      SCOPED_TRACE(info.name + " / " + plugin->name);
      RenderOptions opt;
      opt.width = kWidth;
      opt.height = kHeight;
      opt.technique = plugin->name;
      Result<Plan> plan = make_plan(*scene, opt);
      if (!plan.ok()) {
        std::printf("[ skip     ] %s / %s: %s\n", info.name.c_str(), plugin->name,
                    plan.status().message().c_str());
        continue;
      }
      Result<RenderResult> rc = cpu->render(*scene, *plan, opt);
      ASSERT_TRUE(rc.ok()) << rc.status().message();
      Result<RenderResult> rg = (*gl)->render(*scene, *plan, opt);
      ASSERT_TRUE(rg.ok()) << rg.status().message();
      const ImageDiff d = compare_images(rc->framebuffer.color, rg->framebuffer.color, kThreshold);
      const Camera& cam = scene->cameras[opt.camera];
      const glm::mat4 proj = cam.projection(static_cast<float>(kWidth) / kHeight);
      const DepthAgreement z = compare_depth(rc->framebuffer.depth, rg->framebuffer.depth, proj);
      const double pixels = static_cast<double>(kWidth) * kHeight;
      const double off = static_cast<double>(d.over_count) / pixels;
      const double cov = static_cast<double>(z.coverage_mismatch) / pixels;
      std::printf(
          "[ measure  ] %s / %s: PSNR %.2f dB, RMSE %.5f, max %.1f/255, over 8/255 %.3f%%; "
          "coverage mismatch %.3f%%, view depth max |err| %.3g over %zu px (%zu above 1e-4)\n",
          info.name.c_str(), plugin->name, d.psnr_db, d.rmse, d.max_error * 255.0, 100.0 * off,
          100.0 * cov, z.max_error, z.both, z.over);
      EXPECT_GE(d.psnr_db, kMinPsnr);
      EXPECT_LE(off, kMaxOverFraction);
      EXPECT_LE(cov, kMaxOverFraction);
      EXPECT_GT(z.both, 0u);
      EXPECT_LE(z.max_error, kMaxViewDepthError);
      ++compared;
    }
  }
  EXPECT_GE(compared, 2);
}

TEST(GlBackend, SecondFrameCompilesNothingAndIsIdentical) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend(-1);
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  Result<Scene> scene = make_builtin_scene(default_scene_name());
  ASSERT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 64;
  opt.height = 48;
  opt.technique = "flat";
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_TRUE(plan.ok());
  Result<RenderResult> a = (*gl)->render(*scene, *plan, opt);
  Result<RenderResult> b = (*gl)->render(*scene, *plan, opt);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_GT(a->compile_ms, 0.0);
  EXPECT_EQ(b->compile_ms, 0.0);
  ASSERT_EQ(b->passes.size(), 1u);
  EXPECT_EQ(b->passes[0].name, "main");
  EXPECT_GT(b->passes[0].ms, 0.0);
  EXPECT_FALSE(b->device.empty());
  EXPECT_EQ(a->framebuffer.color.pixels, b->framebuffer.color.pixels);
  EXPECT_EQ(a->framebuffer.depth.values, b->framebuffer.depth.values);
}

TEST(GlBackend, ImageIsTopDownAndBackgroundIsCleared) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend(-1);
  ASSERT_TRUE(gl.ok());
  // One triangle in the top half of the view, facing the camera.
  Scene s;
  s.name = "tri";
  Mesh m;
  m.positions = {{-1.0f, 0.1f, 0.0f}, {1.0f, 0.1f, 0.0f}, {0.0f, 0.9f, 0.0f}};
  m.normals.assign(3, glm::vec3(0, 0, 1));
  m.uvs.assign(3, glm::vec2(0));
  m.tangents.assign(3, glm::vec4(1, 0, 0, 1));
  m.indices = {0, 1, 2};  // counter-clockwise seen from +z
  s.meshes.push_back(m);
  Material mat;
  mat.technique = "flat";
  mat.base_color = glm::vec4(1.0f);
  s.materials.push_back(mat);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  Camera cam;
  cam.position = {0, 0, 3};
  s.cameras.push_back(cam);
  s.ambient = glm::vec3(1.0f);
  s.background = glm::vec4(0.0f, 0.0f, 1.0f, 1.0f);
  RenderOptions opt;
  opt.width = 40;
  opt.height = 30;
  Result<Plan> plan = make_plan(s, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = (*gl)->render(s, *plan, opt);
  ASSERT_TRUE(r.ok()) << r.status().message();
  const Framebuffer& fb = r->framebuffer;
  // Covered near the top centre, background at the bottom; depth 0 where nothing was drawn.
  EXPECT_GT(fb.depth.at(20, 10), 0.0f);
  EXPECT_EQ(fb.depth.at(20, 25), 0.0f);
  EXPECT_EQ(fb.color.at(20, 25), glm::vec4(0.0f, 0.0f, 1.0f, 1.0f));
  EXPECT_NEAR(fb.color.at(20, 10).r, 1.0f, 1e-5f);  // ambient 1 x albedo 1
  // Seen from behind, the single-sided triangle is culled.
  s.cameras[0].position = {0, 0, -3};
  Result<Plan> back = make_plan(s, opt);
  ASSERT_TRUE(back.ok());
  r = (*gl)->render(s, *back, opt);
  ASSERT_TRUE(r.ok());
  float covered = 0.0f;
  for (float v : r->framebuffer.depth.values) covered += v > 0.0f ? 1.0f : 0.0f;
  EXPECT_EQ(covered, 0.0f);
  // Double-sided: drawn from behind too.
  s.materials[0].double_sided = true;
  Result<Plan> both = make_plan(s, opt);
  ASSERT_TRUE(both.ok());
  r = (*gl)->render(s, *both, opt);
  ASSERT_TRUE(r.ok());
  EXPECT_GT(r->framebuffer.depth.at(20, 10), 0.0f);
}

TEST(GlBackend, UnknownTwinIsAnError) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend(-1);
  ASSERT_TRUE(gl.ok());
  for (const PluginDescriptor* plugin : PluginRegistry::global().all()) {
    if (gl_has_twin(plugin->name)) continue;
    Result<Scene> scene = make_builtin_scene(default_scene_name());
    ASSERT_TRUE(scene.ok());
    RenderOptions opt;
    opt.width = 16;
    opt.height = 16;
    opt.technique = plugin->name;
    Result<Plan> plan = make_plan(*scene, opt);
    if (!plan.ok()) continue;
    Result<RenderResult> r = (*gl)->render(*scene, *plan, opt);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.status().message().find("no GLSL twin"), std::string::npos)
        << r.status().message();
    return;
  }
  GTEST_SKIP() << "every registered technique has a GLSL twin";
}

}  // namespace
}  // namespace relief
