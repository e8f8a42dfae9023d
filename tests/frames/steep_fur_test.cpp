// Steep parallax's `shadow=depth` (plugins/steep_parallax.cpp, shaders_cpp/shadow.h
// depth_darkening): the poster's fur-and-grass self-shadow darkens a hit at depth t by
// 1 - strength x t, for each light and for the indirect light, so on a field of constant depth
// every pixel is the self-shadow-off pixel times exactly that factor; it reads no depth beyond the
// search's; --explain says it is a darkening, not rays.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "builtin/builtin.h"
#include "render/render.h"
#include "tests/frames/cpu_frame.h"

namespace relief {
namespace {

constexpr int kW = 96, kH = 64;

// The built-in plane with its depth map replaced by a constant `depth` (level 0 only).
Scene constant_depth_plane(float depth) {
  Result<Scene> s = make_builtin_scene("plane");
  EXPECT_TRUE(s.ok()) << s.status().message();
  if (!s.ok()) return {};
  const std::vector<float> d(16 * 16, depth);
  s->materials[0].textures["depth"] =
      std::make_shared<Texture>(Texture::from_floats(TexFormat::kR32F, 16, 16, d.data()));
  return *s;
}

RenderOptions steep(const char* shadow, float strength, bool self_shadow) {
  RenderOptions opt = test::cpu_options(kW, kH, "steep_parallax");
  opt.params = {{"steps", "32"}, {"shadow", shadow}, {"shadow_strength", std::to_string(strength)}};
  opt.self_shadow = self_shadow;
  opt.shadows = false;
  return opt;
}

TEST(SteepDepthShadow, ScalesEveryPixelByOneMinusStrengthTimesDepth) {
  // 32 planes reach depth 0.5 exactly at plane 16: the hit depth is 0.5 and the factor 0.7
  const Scene scene = constant_depth_plane(0.5f);
  const std::optional<Framebuffer> off = test::render_frame(scene, steep("depth", 0.6f, false));
  const std::optional<Framebuffer> on = test::render_frame(scene, steep("depth", 0.6f, true));
  ASSERT_TRUE(off && on);
  int covered = 0;
  for (size_t i = 0; i < on->color.pixels.size(); ++i) {
    if (!(on->depth.values[i] > 0.0f)) continue;
    ++covered;
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(on->color.pixels[i][c], 0.7f * off->color.pixels[i][c],
                  2e-6f + 1e-5f * off->color.pixels[i][c])
          << "pixel " << i << " channel " << c;
  }
  EXPECT_GT(covered, kW * kH / 2);
}

TEST(SteepDepthShadow, StrengthZeroAndTipsAreUnshadowed) {
  // strength 0, or a hit at depth 0 (the tips), leaves the frame as self-shadow off has it
  for (auto [depth, strength] : {std::pair{0.5f, 0.0f}, std::pair{0.0f, 0.9f}}) {
    const Scene scene = constant_depth_plane(depth);
    const std::optional<Framebuffer> off =
        test::render_frame(scene, steep("depth", strength, false));
    const std::optional<Framebuffer> on = test::render_frame(scene, steep("depth", strength, true));
    ASSERT_TRUE(off && on);
    EXPECT_EQ(on->color.pixels, off->color.pixels) << "depth " << depth << " strength " << strength;
  }
}

TEST(SteepDepthShadow, ReadsNoDepthBeyondTheSearch) {
  // the ray mode marches toward the light; the depth mode reads nothing more than no self-shadow
  const Scene scene = constant_depth_plane(0.75f);
  RenderOptions opt = steep("depth", 0.5f, true);
  Renderer renderer(make_cpu_backend({.threads = 2}));
  auto fetches = [&](const RenderOptions& o) -> uint64_t {
    Result<Frame> f = renderer.render(scene, o);
    EXPECT_TRUE(f.ok()) << f.status().message();
    uint64_t n = 0;
    if (f.ok())
      for (const PassStats& p : f->result.passes)
        if (p.kind == PassPlan::Kind::kMain) n += p.raster.work.texture_fetches;
    return n;
  };
  const uint64_t depth_mode = fetches(opt);
  const uint64_t none = fetches(steep("depth", 0.5f, false));
  const uint64_t ray_mode = fetches(steep("ray", 0.5f, true));
  EXPECT_EQ(depth_mode, none);
  EXPECT_GT(ray_mode, none);
}

TEST(SteepDepthShadow, ExplainSaysDarkeningOrRays) {
  // --explain names what the self-shadow is: the darkening (shadow=depth, shells) or rays
  const Scene scene = constant_depth_plane(0.5f);
  auto explain = [&](const RenderOptions& o) {
    Result<Plan> plan = make_plan(scene, o);
    EXPECT_TRUE(plan.ok()) << plan.status().message();
    return plan.ok() ? plan->explain() : std::string();
  };
  EXPECT_NE(explain(steep("depth", 0.5f, true)).find("darkening with depth, no shadow rays"),
            std::string::npos);
  EXPECT_NE(explain(steep("ray", 0.5f, true)).find("rays only where N.L > 0"), std::string::npos);
  RenderOptions shells = test::cpu_options(kW, kH, "shells");
  EXPECT_NE(explain(shells).find("darkening with depth, no shadow rays"), std::string::npos);
}

}  // namespace
}  // namespace relief
