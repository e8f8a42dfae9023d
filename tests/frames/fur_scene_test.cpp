// The built-in `fur` and `grass` scenes (builtin/builtin_fur.h) render on the CPU backend: finite
// colour everywhere, the relief covering much of the frame, and strands, not a flat colour.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "tests/frames/cpu_frame.h"

namespace relief {
namespace {

struct FrameStats {
  double covered = 0.0;   // the fraction of pixels the relief drew (depth written)
  double contrast = 0.0;  // the mean luminance step between horizontal neighbours the relief drew
  bool finite = true;
};

double luminance(const glm::vec4& c) {
  return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

FrameStats stats_of(const Framebuffer& fb) {
  FrameStats s;
  double steps = 0.0;
  size_t n = 0, pairs = 0;
  for (int y = 0; y < fb.height; ++y)
    for (int x = 0; x < fb.width; ++x) {
      const glm::vec4 c = fb.color.at(x, y);
      for (int k = 0; k < 4; ++k) s.finite &= std::isfinite(c[k]);
      if (fb.depth.at(x, y) <= 0.0f) continue;  // reversed Z: 0 is the cleared background
      ++n;
      if (x + 1 < fb.width && fb.depth.at(x + 1, y) > 0.0f) {
        steps += std::fabs(luminance(fb.color.at(x + 1, y)) - luminance(c));
        ++pairs;
      }
    }
  s.covered = static_cast<double>(n) / (static_cast<double>(fb.width) * fb.height);
  s.contrast = pairs > 0 ? steps / pairs : 0.0;
  return s;
}

TEST(FurScenes, RenderFiniteAndNotBlank) {
  // sphere: about a third of the frame; ground: below a horizon, about half of it
  for (const auto& [name, min_cover] : {std::pair<std::string, double>{"fur", 0.25},
                                        std::pair<std::string, double>{"grass", 0.4}}) {
    Result<Scene> scene = make_builtin_scene(name);
    ASSERT_TRUE(scene.ok()) << scene.status().message();
    ASSERT_EQ(scene->materials.size(), 1u);
    EXPECT_EQ(scene->materials[0].technique, "steep_parallax");
    const std::optional<Framebuffer> fb = test::render_frame(*scene, test::cpu_options(160, 120));
    ASSERT_TRUE(fb.has_value());
    const FrameStats s = stats_of(*fb);
    EXPECT_TRUE(s.finite) << name;
    EXPECT_GT(s.covered, min_cover) << name;
    // A smooth shaded surface changes little from pixel to pixel; strands make a fine texture
    // (at 160x120: fur 0.038, grass 0.0074, its far half averaged by the mips).
    EXPECT_GT(s.contrast, 0.004) << name << ": no strands to see";
    std::printf("%s: %.0f %% covered, mean neighbour step %.4f\n", name.c_str(), 100.0 * s.covered,
                s.contrast);
  }
}

}  // namespace
}  // namespace relief
