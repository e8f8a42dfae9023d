// The export round trip on the GL backend (loading is shared code): the built-ins whose export
// needed new glTF forms (impostor's float back layer, bending's skin and animation), re-loaded,
// render on GL exactly as the built-in does on GL (64x64, one frame each).
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "tests/gl/gl_test_util.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

TEST(ExportRoundTripGl, ImpostorAndBendingRenderAsTheBuiltinsOnGl) {
  RELIEF_REQUIRE_GL();
  Result<std::unique_ptr<Backend>> gl = make_gl_backend();
  ASSERT_TRUE(gl.ok()) << gl.status().message();
  const std::filesystem::path dir = test::fresh_test_dir("export_rt_gl");
  for (const char* name : {"impostor", "bending"}) {
    SCOPED_TRACE(name);
    Result<Scene> builtin = make_builtin_scene(name);
    ASSERT_TRUE(builtin.ok());
    const std::string file = (dir / (std::string(name) + ".glb")).string();
    ASSERT_TRUE(save_gltf(*builtin, file).ok());
    Result<Scene> loaded = load_scene(file);
    ASSERT_TRUE(loaded.ok()) << loaded.status().message();
    RenderOptions opt;
    opt.width = opt.height = 64;
    Framebuffer f[2];
    const Scene* scenes[2] = {&*builtin, &*loaded};
    for (int i = 0; i < 2; ++i) {
      Result<Plan> plan = make_plan(*scenes[i], opt);
      ASSERT_TRUE(plan.ok()) << plan.status().message();
      Result<RenderResult> r = (*gl)->render(*scenes[i], *plan);
      ASSERT_TRUE(r.ok()) << r.status().message();
      f[i] = r->framebuffer;
    }
    ASSERT_EQ(f[0].color.pixels.size(), f[1].color.pixels.size());
    size_t differ = 0;
    for (size_t p = 0; p < f[0].color.pixels.size(); ++p)
      differ += std::memcmp(&f[0].color.pixels[p], &f[1].color.pixels[p],
                            sizeof(f[0].color.pixels[p])) != 0;
    EXPECT_EQ(differ, 0u) << name << ": GL colour pixels differ after the round trip";
  }
}

}  // namespace
}  // namespace relief
