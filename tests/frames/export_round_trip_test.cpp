// `relief export` of every built-in scene, re-loaded, renders bit-identical to the built-in (CPU,
// small size); animated scenes also at a posed time. The export loads without a warning (our
// own files use nothing relief ignores).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "builtin/builtin.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/animation.h"
#include "scene/gltf.h"
#include "tests/test_dir.h"

#include <nlohmann/json.hpp>

namespace relief {
namespace {

namespace fs = std::filesystem;

Framebuffer render_cpu(const Scene& s, int w, int h) {
  RenderOptions opt;
  opt.width = w;
  opt.height = h;
  Result<Plan> plan = make_plan(s, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(s, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer : Framebuffer{};
}

// Colour pixels whose bits differ (and the depth buffer's bytes).
size_t differing_pixels(const Framebuffer& a, const Framebuffer& b, bool* depth_same) {
  EXPECT_EQ(a.color.pixels.size(), b.color.pixels.size());
  size_t n = 0;
  for (size_t i = 0; i < a.color.pixels.size() && i < b.color.pixels.size(); ++i)
    n += std::memcmp(&a.color.pixels[i], &b.color.pixels[i], sizeof(a.color.pixels[i])) != 0;
  *depth_same = a.depth.values.size() == b.depth.values.size() &&
                std::memcmp(a.depth.values.data(), b.depth.values.data(),
                            a.depth.values.size() * sizeof(a.depth.values[0])) == 0;
  return n;
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const BuiltinSceneInfo& b : builtin_scenes()) names.push_back(b.name);
  return names;
}

class ExportRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(ExportRoundTrip, RendersBitIdenticalToTheBuiltin) {
  const std::string name = GetParam();
  Result<Scene> builtin = make_builtin_scene(name);
  ASSERT_TRUE(builtin.ok()) << builtin.status().message();
  const fs::path dir = test::fresh_test_dir("export_rt");
  for (const char* ext : {".gltf", ".glb"}) {
    const std::string file = (dir / (name + ext)).string();
    SCOPED_TRACE(file);
    Status w = save_gltf(*builtin, file);
    ASSERT_TRUE(w.ok()) << w.message();
    std::vector<GltfIgnored> ignored;
    GltfLoadOptions opt;
    opt.ignored = &ignored;
    opt.strict = true;  // nothing of ours is ignored
    Result<Scene> loaded = load_scene(file, opt);
    ASSERT_TRUE(loaded.ok()) << loaded.status().message();
    EXPECT_TRUE(ignored.empty());
    ASSERT_EQ(loaded->materials.size(), builtin->materials.size());
    for (size_t m = 0; m < builtin->materials.size(); ++m) {
      EXPECT_EQ(loaded->materials[m].technique, builtin->materials[m].technique);
      for (const auto& [slot, tex] : builtin->materials[m].textures)
        EXPECT_TRUE(loaded->materials[m].textures.count(slot)) << "slot " << slot << " lost";
    }
    EXPECT_EQ(static_cast<bool>(loaded->animation), static_cast<bool>(builtin->animation));
    bool depth_same = false;
    const size_t d =
        differing_pixels(render_cpu(*builtin, 96, 64), render_cpu(*loaded, 96, 64), &depth_same);
    EXPECT_EQ(d, 0u) << name << ext << ": colour pixels differ";
    EXPECT_TRUE(depth_same) << name << ext << ": depth differs";
    if (builtin->animation && !builtin->animation->clips.empty()) {
      ASSERT_TRUE(loaded->animation);
      ASSERT_EQ(loaded->animation->clips.size(), builtin->animation->clips.size());
      EXPECT_EQ(loaded->animation->skins.size(), builtin->animation->skins.size());
      EXPECT_EQ(loaded->animation->deformers.size(), builtin->animation->deformers.size());
      const double t = 0.4 * builtin->animation->clips[0].duration;  // mid-bend
      Scene a = *builtin, b = *loaded;
      pose_scene(*builtin->animation, PoseOptions{}, t, a);
      pose_scene(*loaded->animation, PoseOptions{}, t, b);
      const size_t dp = differing_pixels(render_cpu(a, 96, 64), render_cpu(b, 96, 64), &depth_same);
      EXPECT_EQ(dp, 0u) << name << ext << " posed at t = " << t << ": colour pixels differ";
      EXPECT_TRUE(depth_same) << name << ext << " posed: depth differs";
      // and the pose moved something (the animation is not lost in both)
      bool moved_depth = false;
      differing_pixels(render_cpu(*builtin, 96, 64), render_cpu(a, 96, 64), &moved_depth);
      EXPECT_FALSE(moved_depth) << "the animation moves nothing at t = " << t;
    }
  }
}

// The exact float texels of an export (impostor: R32F depth, RGBA16F normals) are checked on load:
// a non-finite float or half anywhere is one error line naming the texture, for every format the
// export uses.
TEST(ExportTexels, NonFiniteExactTexelsAreRefused) {
  Result<Scene> builtin = make_builtin_scene("impostor");
  ASSERT_TRUE(builtin.ok());
  const fs::path dir = test::fresh_test_dir("export_texels");
  const std::string gltf = (dir / "i.gltf").string();
  ASSERT_TRUE(save_gltf(*builtin, gltf).ok());
  std::ifstream in(gltf);
  const nlohmann::json doc = nlohmann::json::parse(in);
  int checked = 0;
  for (size_t t = 0; t < doc["textures"].size(); ++t) {
    const nlohmann::json& tex = doc["textures"][t];
    if (!tex.contains("extensions") || !tex["extensions"].contains("RELIEF_relief_mapping"))
      continue;
    const nlohmann::json& e = tex["extensions"]["RELIEF_relief_mapping"];
    const std::string format = e["format"];
    const nlohmann::json& view = doc["bufferViews"][e["texels"].get<int>()];
    const std::string bin =
        (dir / doc["buffers"][view["buffer"].get<int>()]["uri"].get<std::string>()).string();
    std::ifstream bf(bin, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(bf)), {});
    const std::vector<char> saved = bytes;
    // the last value of the view: +inf as a float or a half (little-endian)
    const size_t end = view.value("byteOffset", size_t{0}) + view["byteLength"].get<size_t>();
    if (format == "R32F") {
      const float inf = INFINITY;
      std::memcpy(&bytes[end - 4], &inf, 4);
    } else {
      bytes[end - 2] = 0x00;
      bytes[end - 1] = 0x7C;
    }
    std::ofstream(bin, std::ios::binary)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    Result<Scene> loaded = load_scene(gltf);
    ASSERT_FALSE(loaded.ok()) << format;
    EXPECT_NE(loaded.status().message().find("is not finite"), std::string::npos)
        << loaded.status().message();
    EXPECT_NE(loaded.status().message().find("/textures/" + std::to_string(t)), std::string::npos)
        << loaded.status().message();
    std::ofstream(bin, std::ios::binary)
        .write(saved.data(), static_cast<std::streamsize>(saved.size()));
    ++checked;
  }
  EXPECT_GE(checked, 2);  // a float and a half format at least
  EXPECT_TRUE(load_scene(gltf).ok());
}

INSTANTIATE_TEST_SUITE_P(Builtins, ExportRoundTrip, ::testing::ValuesIn(builtin_names()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace relief
