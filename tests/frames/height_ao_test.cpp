// Height-field ambient occlusion in frames (shaders_cpp/height_ao.h through plugins/relief_shell.h;
// docs/effects.md): off it changes nothing, on it darkens the built-in plane's mortar joints in
// the ambient term only, more with strength; a flat depth map renders bit-identical to AO off;
// scalar lanes and every SIMD level agree bit for bit; the planner says what it did (on, off,
// unsupported) and rejects values out of range; the glTF extension's "height_ao" round-trips and
// a value out of range is one error naming its pointer.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/simd.h"
#include "builtin/builtin.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "tests/test_dir.h"

#include <nlohmann/json.hpp>

namespace relief {
namespace {

constexpr int kW = 160, kH = 96;

Scene plane() {
  Result<Scene> s = make_builtin_scene("plane");
  EXPECT_TRUE(s.ok()) << s.status().message();
  return s.ok() ? *s : Scene{};
}

// The options of a small frame with --height-ao `rays` and --height-ao-strength `strength`, each
// unset when negative.
RenderOptions ao_options(int rays, float strength = -1.0f) {
  RenderOptions opt;
  opt.width = kW;
  opt.height = kH;
  if (rays >= 0) opt.height_ao_rays = rays;
  if (!(strength < 0.0f)) opt.height_ao_strength = strength;
  return opt;
}

Image render(const Scene& scene, const RenderOptions& opt) {
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer.color : Image{};
}

bool identical(const Image& a, const Image& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(a.pixels[0])) == 0;
}

double sum_rgb(const Image& im) {
  double s = 0.0;
  for (const glm::vec4& p : im.pixels) {
    EXPECT_TRUE(std::isfinite(p.r) && std::isfinite(p.g) && std::isfinite(p.b));
    s += p.r + p.g + p.b;
  }
  return s;
}

TEST(HeightAoFrames, OffIsTheFrameWithoutIt) {
  const Scene s = plane();
  EXPECT_TRUE(identical(render(s, ao_options(-1)), render(s, ao_options(0))));
}

TEST(HeightAoFrames, FlatDepthMapIsBitIdenticalToOff) {
  for (int size : {64, 1}) {  // a 1x1 map too
    Scene s = plane();
    const std::vector<float> v(size * size, 0.4f);
    s.materials.at(0).textures["depth"] =
        std::make_shared<Texture>(Texture::from_floats(TexFormat::kR32F, size, size, v.data()));
    const Image off = render(s, ao_options(0));
    sum_rgb(off);  // finite
    for (int rays : {1, 8, 16})
      EXPECT_TRUE(identical(off, render(s, ao_options(rays)))) << size << " " << rays;
  }
}

TEST(HeightAoFrames, DarkensTheAmbientTermOnlyMoreWithStrength) {
  Scene s = plane();
  const Image off = render(s, ao_options(0));
  const Image half = render(s, ao_options(8, 0.5f)), full = render(s, ao_options(8, 1.0f));
  size_t darker = 0;
  for (size_t i = 0; i < off.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_LE(full.pixels[i][c], half.pixels[i][c]) << i;
      ASSERT_LE(half.pixels[i][c], off.pixels[i][c]) << i;
    }
    darker += full.pixels[i].g < off.pixels[i].g;
  }
  EXPECT_GT(darker, off.pixels.size() / 50) << "the joints are not darker";
  EXPECT_LT(sum_rgb(full), sum_rgb(half));
  EXPECT_LT(sum_rgb(half), sum_rgb(off));
  // without ambient light there is nothing to occlude: the lights and self-shadow are untouched
  s.ambient = glm::vec3(0.0f);
  EXPECT_TRUE(identical(render(s, ao_options(0)), render(s, ao_options(8))));
}

TEST(HeightAoFrames, ScalarLanesAndEverySimdLevelAreBitIdentical) {
  const SimdLevel saved = simd_level();
  const Scene s = plane();
  for (const char* technique : {"relief", "pom", "steep_parallax", "parallax", "exact"}) {
    RenderOptions opt = ao_options(8);
    opt.technique = technique;
    opt.scalar_lanes = true;
    const Image reference = render(s, opt);
    opt.scalar_lanes = false;
    for (SimdLevel level : simd_levels_supported()) {
      set_simd_level(level);
      EXPECT_TRUE(identical(reference, render(s, opt)))
          << technique << " at " << simd_level_name(level);
    }
    set_simd_level(saved);
  }
}

std::string reason(const BoundMaterial& b, const std::string& prefix) {
  for (const std::string& r : b.reasons)
    if (r.rfind(prefix, 0) == 0) return r;
  return "(no " + prefix + " line)";
}

TEST(HeightAoFrames, PlannerSaysWhatItDid) {
  Scene s = plane();
  Result<Plan> off = make_plan(s, ao_options(-1));
  ASSERT_TRUE(off.ok());
  EXPECT_EQ(reason(off->materials.at(0), "height_ao"),
            "height_ao: off (not asked by the material)");
  EXPECT_EQ(off->materials.at(0).effects & kEffectHeightAo, 0u);
  RenderOptions opt = ao_options(6, 0.5f);
  opt.height_ao_radius = 0.02f;
  Result<Plan> on = make_plan(s, opt);
  ASSERT_TRUE(on.ok());
  EXPECT_EQ(reason(on->materials.at(0), "height_ao"),
            "height_ao: on (6 rays x 4 steps, radius 0.02 uv, strength 0.5; ambient/environment "
            "light only)");
  EXPECT_EQ(on->materials.at(0).uniforms.height_ao.rays, 6);
  // the material's own request, without the option
  s.materials.at(0).height_ao = {4, 0.03f, 1.0f};
  Result<Plan> own = make_plan(s, ao_options(-1));
  ASSERT_TRUE(own.ok());
  EXPECT_EQ(own->materials.at(0).uniforms.height_ao.rays, 4);
  EXPECT_NE(own->materials.at(0).effects & kEffectHeightAo, 0u);
  // relief_dual and relief_quadric do not support it, and say so
  for (const char* t : {"relief_dual", "relief_quadric"}) {
    RenderOptions o = ao_options(8);
    o.technique = t;
    Result<Plan> p = make_plan(s, o);
    ASSERT_TRUE(p.ok()) << p.status().message();
    EXPECT_EQ(reason(p->materials.at(0), "height_ao"),
              std::string("height_ao: off (not supported by technique ") + t + ")");
    EXPECT_EQ(p->materials.at(0).uniforms.height_ao.rays, 0);
  }
}

TEST(HeightAoFrames, ValuesOutOfRangeAreOneError) {
  const Scene s = plane();
  for (int rays : {-1, 17}) {
    RenderOptions opt = ao_options(0);
    opt.height_ao_rays = rays;
    Result<Plan> p = make_plan(s, opt);
    ASSERT_FALSE(p.ok()) << rays;
    EXPECT_NE(p.status().message().find("height-field AO rays"), std::string::npos)
        << p.status().message();
  }
  RenderOptions opt = ao_options(8);
  opt.height_ao_radius = 2.0f;
  EXPECT_FALSE(make_plan(s, opt).ok());
  opt = ao_options(8, std::nanf(""));
  EXPECT_FALSE(make_plan(s, opt).ok());
  Scene bad = plane();
  bad.materials.at(0).height_ao.strength = 1.5f;
  Result<Plan> p = make_plan(bad, ao_options(-1));
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("strength 1.5 outside [0, 1]"), std::string::npos)
      << p.status().message();
}

TEST(HeightAoFrames, GltfRoundTripAndValidation) {
  Scene s = plane();
  s.materials.at(0).height_ao = {8, 0.03f, 0.75f};
  const std::string file = (test::fresh_test_dir("height_ao") / "plane.gltf").string();
  Status w = save_gltf(s, file);
  ASSERT_TRUE(w.ok()) << w.message();
  Result<Scene> loaded = load_scene(file);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  const HeightAoParams& h = loaded->materials.at(0).height_ao;
  EXPECT_EQ(h.rays, 8);
  EXPECT_EQ(h.radius, 0.03f);
  EXPECT_EQ(h.strength, 0.75f);
  EXPECT_TRUE(identical(render(s, ao_options(-1)), render(*loaded, ao_options(-1))));
  // the same file with rays out of range: one error at the value's pointer
  std::ifstream in(file);
  nlohmann::json doc = nlohmann::json::parse(in);
  doc["materials"][0]["extensions"]["RELIEF_relief_mapping"]["height_ao"]["rays"] = 40;
  const std::string bad = (std::filesystem::path(file).parent_path() / "bad.gltf").string();
  std::ofstream(bad) << doc.dump(1);
  Result<Scene> rejected = load_scene(bad);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(rejected.status().message().find("/extensions/RELIEF_relief_mapping/height_ao/rays"),
            std::string::npos)
      << rejected.status().message();
  EXPECT_NE(rejected.status().message().find("40"), std::string::npos);
}

}  // namespace
}  // namespace relief
