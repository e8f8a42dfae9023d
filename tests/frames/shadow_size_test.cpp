// A shadow map the view needs (issue 26; render/shadow_map.h ShadowSize, `--shadow-size`): with
// kView the planner sizes each map to a texel per pixel of the view, never above the light's
// shadow_resolution, and what it samples of the visible receivers holds at the pixels the frame
// really covers; kLight (the default) keeps the light's resolution whatever the view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <glm/matrix.hpp>

#include "builtin/builtin.h"
#include "render/render.h"
#include "tests/apps/cli_run.h"

namespace relief {
namespace {

Scene builtin(const std::string& name) {
  Result<Scene> s = make_builtin_scene(name);
  EXPECT_TRUE(s.ok()) << name;
  return std::move(s).value();
}

RenderOptions options(int w, int h, ShadowSize size) {
  RenderOptions o;
  o.width = w;
  o.height = h;
  o.shadow_size = size;
  return o;
}

const PassPlan* shadow_pass(const Plan& p) {
  for (const PassPlan& pass : p.passes)
    if (pass.kind == PassPlan::Kind::kShadow) return &pass;
  return nullptr;
}

int planned_size(const Scene& s, int w, int h, ShadowSize size) {
  Result<Plan> p = make_plan(s, options(w, h, size));
  EXPECT_TRUE(p.ok()) << p.status().message();
  const PassPlan* pass = p.ok() ? shadow_pass(*p) : nullptr;
  EXPECT_NE(pass, nullptr);
  return pass ? pass->shadow.size : 0;
}

TEST(ShadowSize, ViewSizeFollowsTheViewAndNeverPassesTheLights) {
  for (const char* name : {"room", "teatime", "materials"}) {
    SCOPED_TRACE(name);
    const Scene s = builtin(name);
    const int light = s.lights[0].shadow_resolution;
    const int small = planned_size(s, 128, 96, ShadowSize::kView);
    const int mid = planned_size(s, 256, 192, ShadowSize::kView);
    EXPECT_GE(small, 16);
    EXPECT_LT(small, mid);
    EXPECT_LE(mid, light);
    // linear in the view's height (a pixel's world size is), up to rounding and the refit
    if (mid < light) {
      EXPECT_NEAR(static_cast<double>(mid) / small, 2.0, 0.1);
    }
    EXPECT_EQ(planned_size(s, 3840, 2880, ShadowSize::kView), light);
    for (int h : {96, 192, 2880})
      EXPECT_EQ(planned_size(s, h * 4 / 3, h, ShadowSize::kLight), light);
  }
}

// The planner bounds the texel on the receivers' triangles clipped to the view; the frame's own
// pixels are the check: unprojected from the depth buffer (relief hits included), every covered
// pixel the map sees has a texel no larger than itself, to rounding.
TEST(ShadowSize, ATexelCoversAtMostAPixelWhereTheFrameLooks) {
  constexpr int kW = 256, kH = 192;
  for (const char* name : {"room", "teatime", "materials"}) {
    SCOPED_TRACE(name);
    const Scene s = builtin(name);
    Result<Plan> plan = make_plan(s, options(kW, kH, ShadowSize::kView));
    ASSERT_TRUE(plan.ok());
    const ShadowPassSetup& setup = shadow_pass(*plan)->shadow;
    ASSERT_LT(setup.size, s.lights[0].shadow_resolution);
    Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(s, *plan);
    ASSERT_TRUE(r.ok());
    const glm::mat4 inv = glm::inverse(plan->frame.view_proj);
    const glm::mat4 proj = plan->frame.view_proj * glm::inverse(plan->frame.view);
    long seen = 0, over = 0;
    double worst = 0.0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const float d = r->framebuffer.depth.at(x, y);
        if (!(d > 0.0f)) continue;
        const glm::vec4 h = inv * glm::vec4((x + 0.5f) / kW * 2 - 1, 1 - (y + 0.5f) / kH * 2, d, 1);
        const glm::vec3 p = glm::vec3(h) / h.w;
        const glm::vec4 e = setup.view[0] * glm::vec4(p, 1.0f);
        const glm::vec4 c = setup.proj[0] * e;
        if (!(c.w > 0.0f) || std::fabs(c.x) > c.w || std::fabs(c.y) > c.w) continue;
        const double texel = setup.texel * -e.z;
        const double pixel =
            2.0 * (plan->frame.view_proj * glm::vec4(p, 1.0f)).w / (kH * std::fabs(proj[1][1]));
        ++seen;
        worst = std::max(worst, texel / pixel);
        over += texel > pixel * 1.001;
      }
    std::printf("[ measure  ] %s %dx%d: map %d, texel/pixel max %.3f, over 1.001 at %ld of %ld\n",
                name, kW, kH, setup.size, worst, over, seen);
    ASSERT_GT(seen, kW * kH / 4);
    EXPECT_LE(static_cast<double>(over) / seen, 0.001);
    EXPECT_LT(worst, 1.01);
  }
}

// What it costs and buys on `room` at 256x192: the shadow pass, drawn whole, shades a quarter of
// the fragments or fewer; the image changes little (the shadows relief casters write into the
// floor's grooves soften: the bias and the filter are counted in texels).
TEST(ShadowSize, ViewSizedRoomShadesFewerShadowFragmentsForNearlyTheSameImage) {
  const Scene s = builtin("room");
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<Plan> pl = make_plan(s, options(256, 192, ShadowSize::kLight));
  Result<Plan> pv = make_plan(s, options(256, 192, ShadowSize::kView));
  ASSERT_TRUE(pl.ok() && pv.ok());
  pl->shadow_on_demand = pv->shadow_on_demand = false;  // the maps' sizes, each drawn whole
  Result<RenderResult> rl = cpu->render(s, *pl);
  Result<RenderResult> rv = cpu->render(s, *pv);
  ASSERT_TRUE(rl.ok() && rv.ok());
  const uint64_t fl = rl->passes[0].raster.work.fragments, fv = rv->passes[0].raster.work.fragments;
  EXPECT_LE(fv * 4, fl) << fv << " against " << fl;
  double sum = 0.0;
  for (size_t i = 0; i < rl->framebuffer.color.pixels.size(); ++i) {
    const glm::vec4 a = rl->framebuffer.color.pixels[i], b = rv->framebuffer.color.pixels[i];
    sum += (std::fabs(a.r - b.r) + std::fabs(a.g - b.g) + std::fabs(a.b - b.b)) / 3.0;
    ASSERT_TRUE(std::isfinite(b.r) && std::isfinite(b.g) && std::isfinite(b.b));
  }
  const double mean = sum / static_cast<double>(rl->framebuffer.color.pixels.size());
  std::printf(
      "[ measure  ] room 256x192: shadow fragments %llu (light) %llu (view), mean |diff| "
      "%.4f\n",
      static_cast<unsigned long long>(fl), static_cast<unsigned long long>(fv), mean);
  EXPECT_GT(mean, 0.0);  // a coarser map is not the same map
  EXPECT_LT(mean, 0.02);
}

// The clipped polygons hold what the view sees of a triangle and nothing else: one reaching from
// behind the camera to past its far plane keeps its middle, every corner inside the clip volume.
TEST(ShadowSize, VisibleReceiverPolygonsKeepWhatTheViewSeesOfATriangle) {
  Scene s;
  Mesh m;
  m.positions = {{-0.5f, -0.2f, 5.0f}, {0.5f, -0.2f, 5.0f}, {0.0f, -0.2f, -500.0f}};
  m.indices = {0, 1, 2};
  s.meshes.push_back(m);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  Camera cam;  // at z = 3 looking down -z, far plane at 100
  cam.znear = 0.1f;
  cam.zfar = 100.0f;
  const glm::mat4 vp = cam.projection(4.0f / 3.0f) * cam.view();
  const auto polys = visible_receiver_polygons(s, {0}, vp);
  ASSERT_EQ(polys.size(), 1u);
  ASSERT_GE(polys[0].size(), 3u);
  float nearest = 1e9f, farthest = 0.0f;
  for (const glm::vec3& p : polys[0]) {
    const glm::vec4 c = vp * glm::vec4(p, 1.0f);
    EXPECT_GT(c.w, 0.0f);
    EXPECT_LE(std::fabs(c.x), c.w * 1.0001f);
    EXPECT_LE(std::fabs(c.y), c.w * 1.0001f);
    EXPECT_GE(c.z, -1e-4f * c.w);
    EXPECT_LE(c.z, c.w * 1.0001f);
    nearest = std::min(nearest, c.w);
    farthest = std::max(farthest, c.w);
  }
  // cut by the near plane (or the frame's bottom edge) in front, by the far plane behind
  EXPECT_LT(nearest, 2.0f);
  EXPECT_NEAR(farthest, 100.0f, 0.5f);
  // a triangle wholly behind the camera leaves nothing
  s.meshes[0].positions = {{-1, 0, 10}, {1, 0, 10}, {0, 1, 12}};
  EXPECT_TRUE(visible_receiver_polygons(s, {0}, vp).empty());
}

TEST(ShadowSize, CliTakesViewOrLightAndRefusesAnythingElse) {
  const std::string dir = test::fresh_test_dir("shadow_size_cli").string();
  CliRun r =
      run("render room --size 64x48 --threads 2 --shadow-size view --explain -o " + dir + "/v.png");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("the light asks for 1024; a texel per pixel of this view is"),
            std::string::npos)
      << r.out;
  r = run("render room --size 64x48 --threads 2 --shadow-size texel -o " + dir + "/bad.png");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--shadow-size: expected view or light, got 'texel'"), std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bad.png"));
}

}  // namespace
}  // namespace relief
