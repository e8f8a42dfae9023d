// Under an orthographic camera every eye ray is parallel, so on a flat, untextured plane lit by a
// directional light the view vector, the half vector and hence the whole Blinn-Phong colour are
// the same for every pixel. (Taking the view vector as normalize(eye - p) breaks this.)
#include <gtest/gtest.h>

#include "builtin/builtin.h"
#include "render/render.h"

namespace relief {
namespace {

TEST(Orthographic, FlatAndNormalShadeAPlaneUniformlyUnderParallelEyeRays) {
  for (const char* technique : {"flat", "normal"}) {
    Result<Scene> scene = make_builtin_scene("plane");
    ASSERT_TRUE(scene.ok());
    for (Material& m : scene->materials) {
      m.textures.clear();  // no colour, no normal map
      m.technique = technique;
    }
    Camera& cam = scene->cameras.at(0);
    cam.orthographic = true;
    cam.ortho_half_height = 0.6f;  // the plane fills the view
    RenderOptions opt;
    opt.width = 64;
    opt.height = 48;
    Result<Plan> plan = make_plan(*scene, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(*scene, *plan);
    ASSERT_TRUE(r.ok());
    const Framebuffer& fb = r->framebuffer;
    int covered = 0;
    glm::vec4 first(0.0f);
    for (int y = 0; y < fb.height; ++y)
      for (int x = 0; x < fb.width; ++x) {
        if (fb.depth.at(x, y) == 0.0f) continue;  // background
        const glm::vec4 c = fb.color.at(x, y);
        if (covered++ == 0) first = c;
        ASSERT_NEAR(c.r, first.r, 1e-5f) << technique << " at " << x << "," << y;
        ASSERT_NEAR(c.g, first.g, 1e-5f) << technique << " at " << x << "," << y;
        ASSERT_NEAR(c.b, first.b, 1e-5f) << technique << " at " << x << "," << y;
      }
    EXPECT_GT(covered, fb.width * fb.height / 2) << technique;
  }
}

}  // namespace
}  // namespace relief
