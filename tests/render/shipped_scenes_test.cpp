// The example files in scenes/ are the built-in scenes written by `relief export`: each must render
// like the built-in it was made from, so a change to a built-in that is not re-exported fails here.
#include <gtest/gtest.h>

#include <filesystem>

#include "render/compare.h"
#include "render/render.h"
#include "scene/builtin.h"
#include "scene/gltf.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

Image render_scene(const Scene& scene) {
  RenderOptions opt;
  opt.width = 200;
  opt.height = 150;
  opt.threads = 2;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = make_cpu_backend(opt.threads)->render(scene, *plan, opt);
  EXPECT_TRUE(r.ok());
  return r->framebuffer.color;
}

TEST(ShippedScenes, EachRendersLikeTheBuiltinItWasExportedFrom) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(RELIEF_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".gltf") continue;
    const std::string name = entry.path().stem().string();
    Result<Scene> builtin = make_builtin_scene(name);
    if (!builtin.ok()) continue;  // a scene that only exists as a file
    Result<Scene> shipped = load_gltf(entry.path().string());
    ASSERT_TRUE(shipped.ok()) << shipped.status().message();
    // Not bit for bit: camera and light orientations go through quaternions in the file, which
    // moves directions by about one float ulp and shading by about 1e-6.
    const ImageDiff d = compare_images(render_scene(*builtin), render_scene(*shipped), 2.0f / 255.0f);
    EXPECT_GE(d.psnr_db, 60.0) << name;
    EXPECT_LE(d.over_fraction, 5e-4) << name << ": " << d.over_count << " pixels over 2/255";
    ++checked;
  }
  EXPECT_GE(checked, 3);  // plane, pattern, room at least
}

}  // namespace
}  // namespace relief
