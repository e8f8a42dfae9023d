// Buffers reused between frames (Backend::recycle, shadow maps kept by the CPU backend, tiles
// clearing their own pixels) must not change a single bit of any frame.
#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "render/render.h"

namespace relief {
namespace {

struct Frame {
  const char* scene;
  const char* technique;
};

RenderResult render_with(Backend& backend, Frame f) {
  Result<Scene> scene = make_builtin_scene(f.scene);
  EXPECT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 160;
  opt.height = 120;
  opt.technique = f.technique;
  opt.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kHitDepth) | aov_bit(Aov::kSteps);
  Result<Plan> plan = make_plan(*scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = backend.render(*scene, *plan);
  EXPECT_TRUE(r.ok());
  return std::move(r).value();
}

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.color.pixels == b.color.pixels && a.depth.values == b.depth.values && a.aov == b.aov;
}

TEST(Recycle, AFrameOnRecycledBuffersEqualsOneOnFreshBuffers) {
  // room has a shadow-casting spot light, so its shadow maps are reused too; plane and pattern
  // leave different colour, depth and AOVs behind for the next frame to clear.
  const Frame frames[] = {{"room", "relief"},  {"plane", "exact"}, {"room", "relief"},
                          {"pattern", "flat"}, {"room", "pom"},    {"pattern", "relief"}};
  auto reused = make_cpu_backend({.threads = 2});
  for (const Frame& f : frames) {
    RenderResult fresh = render_with(*make_cpu_backend({.threads = 2}), f);
    RenderResult again = render_with(*reused, f);
    EXPECT_TRUE(identical(fresh.framebuffer, again.framebuffer)) << f.scene << " " << f.technique;
    reused->recycle(std::move(again));
  }
}

}  // namespace
}  // namespace relief
