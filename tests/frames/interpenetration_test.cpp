// Interpenetration (Policarpo et al. 2005, figure 18): with depth correction, where a sphere
// meets a relief floor is decided by the relief surface, not by the floor's polygon. The boundary
// the `relief` search draws must match the one `exact` draws to within one pixel.
#include <gtest/gtest.h>

#include <vector>

#include "builtin/builtin.h"
#include "render/render.h"
#include "tests/frames/depth_fixture.h"

namespace relief {
namespace {

// Which pixels show a sphere (flat material: no search steps) over the relief.
std::vector<uint8_t> sphere_mask(const Scene& scene, int w, int h) {
  RenderOptions opt;
  opt.width = w;
  opt.height = h;
  opt.aovs = aov_bit(Aov::kSteps);
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(scene, *plan);
  EXPECT_TRUE(r.ok());
  const Framebuffer& fb = r->framebuffer;
  std::vector<uint8_t> mask(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      mask[size_t(y) * w + x] =
          fb.depth.at(x, y) > 0.0f && fb.aov_at(x, y)[kAovOffset[int(Aov::kSteps)]] == 0.0f;
  return mask;
}

TEST(Interpenetration, SphereReliefBoundaryMatchesExactWithinOnePixel) {
  const int w = 240, h = 180;
  Result<Scene> built = make_builtin_scene("interpenetration");
  ASSERT_TRUE(built.ok());
  // Level-0 depth for both: mip-filtered joints are shallower than the texels exact intersects.
  const Scene scene = level0_depth(*built);
  Scene reference = scene;
  for (Material& m : reference.materials)
    if (m.technique == "relief") m.technique = "exact";
  const std::vector<uint8_t> a = sphere_mask(scene, w, h);
  const std::vector<uint8_t> b = sphere_mask(reference, w, h);
  auto at = [&](const std::vector<uint8_t>& m, int x, int y) {
    return m[size_t(std::clamp(y, 0, h - 1)) * w + std::clamp(x, 0, w - 1)];
  };
  int sphere_pixels = 0, differ = 0, far = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      sphere_pixels += at(b, x, y);
      if (at(a, x, y) == at(b, x, y)) continue;
      ++differ;
      // Within one pixel of exact's boundary: some 8-neighbour of exact's mask has a's value.
      bool near = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) near |= at(b, x + dx, y + dy) == at(a, x, y);
      if (!near) {
        ++far;
        ADD_FAILURE() << "pixel " << x << "," << y << " is " << (at(a, x, y) ? "sphere" : "relief")
                      << " with relief, and no neighbour agrees with exact";
      }
    }
  EXPECT_GT(sphere_pixels, w * h / 40);  // the spheres are in view
  EXPECT_EQ(far, 0);
  std::printf("sphere pixels %d, relief vs exact differ on %d (all within one pixel: %s)\n",
              sphere_pixels, differ, far == 0 ? "yes" : "no");
}

// Where the sphere is cut shows the depth correction: without it (polygon depth) the floor's
// polygon at y = 0 would hide the lower cap everywhere; with it, the deep mortar joints let more of
// the sphere show than the polygon would.
TEST(Interpenetration, DepthCorrectionMovesTheBoundary) {
  const int w = 240, h = 180;
  Result<Scene> scene = make_builtin_scene("interpenetration");
  ASSERT_TRUE(scene.ok());
  Scene polygon_depth = *scene;
  for (Material& m : polygon_depth.materials) m.depth_write = false;
  const std::vector<uint8_t> corrected = sphere_mask(*scene, w, h);
  const std::vector<uint8_t> flat = sphere_mask(polygon_depth, w, h);
  int more = 0, fewer = 0;
  for (size_t i = 0; i < corrected.size(); ++i) {
    more += corrected[i] && !flat[i];
    fewer += !corrected[i] && flat[i];
  }
  EXPECT_GT(more, 20) << "depth correction should reveal sphere below the polygon";
  EXPECT_EQ(fewer, 0) << "relief only moves depth farther, so it never hides more sphere";
}

}  // namespace
}  // namespace relief
