#include <gtest/gtest.h>

#include <cmath>

#include "builtin/builtin.h"
#include "render/renderer.h"

namespace relief {
namespace {

RenderResult render_plane(int threads, int tile, const std::string& technique, bool scalar = false,
                          const char* scene_name = "plane") {
  Result<Scene> scene = make_builtin_scene(scene_name);
  EXPECT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 200;
  opt.height = 150;
  opt.technique = technique;
  opt.scalar_lanes = scalar;
  opt.aovs = aov_bit(Aov::kHitUv) | aov_bit(Aov::kNormal);
  Renderer renderer(make_cpu_backend({.threads = threads, .tile_size = tile}));
  Result<Frame> frame = renderer.render(*scene, opt);
  EXPECT_TRUE(frame.ok()) << frame.status().message();
  return std::move(frame->result);
}

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.color.pixels == b.color.pixels && a.depth.values == b.depth.values && a.aov == b.aov;
}

TEST(Determinism, PlaneIsBitIdenticalForAnyThreadCountAndTileSize) {
  for (const char* scene : {"plane", "pattern"})
    for (const char* technique : {"flat", "normal", "relief", "pom", "exact", "shells"}) {
      const RenderResult ref = render_plane(1, 64, technique, false, scene);
      for (auto [threads, tile] :
           {std::pair{2, 64}, std::pair{7, 64}, std::pair{2, 16}, std::pair{7, 128}}) {
        const RenderResult r = render_plane(threads, tile, technique, false, scene);
        EXPECT_TRUE(identical(ref.framebuffer, r.framebuffer))
            << scene << " " << technique << " threads=" << threads << " tile=" << tile;
      }
    }
}

TEST(Determinism, ScalarAndSimdLanesAgreeBitForBit) {
  for (const char* scene : {"plane", "pattern"})
    for (const char* technique :
         {"flat", "normal", "parallax", "steep_parallax", "pom", "relief", "shells"}) {
      const RenderResult simd = render_plane(2, 64, technique, false, scene);
      const RenderResult scalar = render_plane(2, 64, technique, true, scene);
      EXPECT_TRUE(identical(simd.framebuffer, scalar.framebuffer)) << scene << " " << technique;
    }
}

TEST(Render, PlaneHasNoNaNAndNormalDiffersFromFlat) {
  const RenderResult flat = render_plane(2, 64, "flat");
  const RenderResult normal = render_plane(2, 64, "normal");
  int differ = 0, covered = 0;
  for (size_t i = 0; i < flat.framebuffer.color.pixels.size(); ++i) {
    for (int k = 0; k < 4; ++k) {
      ASSERT_TRUE(std::isfinite(flat.framebuffer.color.pixels[i][k]));
      ASSERT_TRUE(std::isfinite(normal.framebuffer.color.pixels[i][k]));
    }
    ASSERT_TRUE(std::isfinite(normal.framebuffer.depth.values[i]));
    covered += normal.framebuffer.depth.values[i] > 0.0f;
    const glm::vec4 d = flat.framebuffer.color.pixels[i] - normal.framebuffer.color.pixels[i];
    differ += std::fabs(d.r) + std::fabs(d.g) + std::fabs(d.b) > 0.02f;
  }
  EXPECT_GT(covered, 200 * 150 / 2);
  EXPECT_GT(differ, covered / 10);  // the normal map changes the shading visibly
}

}  // namespace
}  // namespace relief
