// The glTF material features on the GL backend against the CPU one (plugins/surface.h
// finish_surface and its twin in gl/shaders/common.glsl): tiny files the test writes
// (tests/materials_fixture.h), 64x64, with the agreement metric of agreement_test.cpp (sRGB RGB
// PSNR >= 35 dB, at most 0.5% of the pixels off by more than 8/255).
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gl/gl_backend.h"
#include "render/compare.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "tests/gl/gl_agreement.h"
#include "tests/gl/gl_test_util.h"
#include "tests/materials_fixture.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

using nlohmann::json;
using test::MaterialDoc;

constexpr int kSize = 64;

const glm::vec4 kQuad[4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}};
const glm::vec4 kGreys[4] = {
    {0.2f, 0.2f, 0.2f, 1}, {0.4f, 0.4f, 0.4f, 1}, {0.6f, 0.6f, 0.6f, 1}, {0.8f, 0.8f, 0.8f, 1}};

// Every feature at once: base colour offset (the main transform), emissive texture rotated with
// KHR_materials_emissive_strength, occlusion on TEXCOORD_1, COLOR_0, normalTexture.scale 2, lit.
MaterialDoc everything(const std::filesystem::path& dir, const json& relief_ext) {
  json tt_base = {{"KHR_texture_transform", {{"offset", {0.25, 0.0}}}}};
  json tt_em = {{"KHR_texture_transform", {{"offset", {0.0, 1.0}}, {"rotation", 1.5707963}}}};
  json m = {{"pbrMetallicRoughness",
             {{"baseColorFactor", {0.8, 0.8, 0.8, 1}},
              {"baseColorTexture", {{"index", 0}, {"extensions", tt_base}}}}},
            {"emissiveTexture", {{"index", 1}, {"extensions", tt_em}}},
            {"emissiveFactor", {0.1, 0.2, 0.1}},
            {"occlusionTexture", {{"index", 2}, {"texCoord", 1}, {"strength", 0.8}}},
            {"normalTexture", {{"index", 3}, {"scale", 2.0}}},
            {"extensions",
             {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1.5}}},
              {"RELIEF_relief_mapping", relief_ext}}}};
  MaterialDoc d = test::material_quad(dir, m, 0.3f, 0.9f);
  test::use_extension(d, "KHR_texture_transform");
  test::use_extension(d, "KHR_materials_emissive_strength");
  d.texture("base", kQuad);
  d.texture("emissive", kGreys);
  d.texture("occlusion", kGreys);
  const glm::vec4 nm(0.65f, 0.4f, 0.9f, 1.0f);
  const glm::vec4 nmap[4] = {nm, nm, nm, nm};
  d.texture("normal", nmap);
  const std::vector<float> uv1 = {1, 0, 0, 0, 0, 1, 1, 1};
  d.primitive()["attributes"]["TEXCOORD_1"] = d.accessor(uv1, 2, test::kFloatType, "VEC2");
  const std::vector<uint16_t> c = {65535, 32768, 32768, 65535, 32768, 65535, 32768, 65535,
                                   32768, 32768, 65535, 65535, 65535, 65535, 65535, 65535};
  d.primitive()["attributes"]["COLOR_0"] = d.accessor(c, 4, test::kUShortType, "VEC4", true);
  return d;
}

// env: the studio environment's view for a file without lights (the plan must have one).
void expect_agreement(const std::string& path, const std::string& label,
                      const EnvironmentView* env = nullptr) {
  SCOPED_TRACE(label);
  Result<Scene> scene = load_scene(path);
  ASSERT_TRUE(scene.ok()) << scene.status().message();
  RenderOptions opt;
  opt.width = kSize;
  opt.height = kSize;
  if (env) opt.env_view = *env;
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->frame.environment != nullptr, env != nullptr);
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<RenderResult> rc = cpu->render(*scene, *plan);
  ASSERT_TRUE(rc.ok()) << rc.status().message();
  Backend* gl = gl::testing::shared_gl_backend();
  ASSERT_NE(gl, nullptr);
  Result<RenderResult> rg = gl->render(*scene, *plan);
  ASSERT_TRUE(rg.ok()) << rg.status().message();
  const ImageDiff d =
      compare_images(rc->framebuffer.color, rg->framebuffer.color, gl::testing::kThreshold);
  const double off = static_cast<double>(d.over_count) / (kSize * kSize);
  std::printf("[ measure  ] %s: PSNR %.2f dB, max %.1f/255, over 8/255 %.3f%%\n", label.c_str(),
              d.psnr_db, d.max_error * 255.0, 100.0 * off);
  EXPECT_GE(d.psnr_db, gl::testing::kMinPsnr);
  EXPECT_LE(off, gl::testing::kMaxOverFraction);
  // the scene is not black (an all-black pair would agree)
  double sum = 0.0;
  for (const glm::vec4& p : rc->framebuffer.color.pixels) sum += p.x + p.y + p.z;
  EXPECT_GT(sum, 0.1 * kSize * kSize);
}

TEST(GlMaterials, EveryFeatureAgreesWithCpu) {
  RELIEF_REQUIRE_GL();
  const auto dir = test::fresh_test_dir("gl_materials");
  // the normal technique, and the relief shell (a flat depth map: the search lands at depth 0)
  MaterialDoc n = everything(dir, {{"technique", "normal"}});
  expect_agreement(n.write("normal"), "normal");
  MaterialDoc r = everything(
      dir, {{"technique", "relief"}, {"depth_texture", {{"index", 4}}}, {"depth_scale", 0.05}});
  const glm::vec4 zero[4] = {{0, 0, 0, 1}, {0, 0, 0, 1}, {0, 0, 0, 1}, {0, 0, 0, 1}};
  r.texture("depth", zero);
  expect_agreement(r.write("relief"), "relief");
  // unlit with vertex colours, flat
  json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.9, 0.7, 0.5, 1}}}},
            {"extensions", {{"KHR_materials_unlit", json::object()}}}};
  MaterialDoc u = test::material_quad(dir, m, 0.5f, 2.0f);
  test::use_extension(u, "KHR_materials_unlit");
  const std::vector<float> c = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1};
  u.primitive()["attributes"]["COLOR_0"] = u.accessor(c, 4, test::kFloatType, "VEC4");
  expect_agreement(u.write("unlit"), "unlit");
}

// One feature at a time, so a twin that drops one fails by name: each material below differs from
// the plain lit quad only by that feature.
TEST(GlMaterials, EachFeatureAloneAgreesWithCpu) {
  RELIEF_REQUIRE_GL();
  const auto dir = test::fresh_test_dir("gl_materials_each");
  const json base = {{"baseColorFactor", {0.7, 0.7, 0.7, 1}}, {"baseColorTexture", {{"index", 0}}}};
  struct Case {
    const char* name;
    json extra;             // merged into the material
    const char* extension;  // to list in extensionsUsed, or null
    bool color0 = false, uv1 = false;
  };
  const json tt = {{"KHR_texture_transform", {{"offset", {0.25, 0.0}}, {"scale", {2.0, 1.0}}}}};
  const std::vector<Case> cases = {
      {"emissive",
       {{"emissiveFactor", {0.2, 0.1, 0.3}}, {"emissiveTexture", {{"index", 1}}}},
       nullptr},
      {"emissive_strength",
       {{"emissiveFactor", {0.1, 0.1, 0.1}},
        {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3.0}}}}}},
       "KHR_materials_emissive_strength"},
      {"occlusion", {{"occlusionTexture", {{"index", 1}, {"strength", 1.0}}}}, nullptr},
      {"occlusion_uv1",
       {{"occlusionTexture", {{"index", 1}, {"texCoord", 1}}}},
       nullptr,
       false,
       true},
      {"unlit", {{"extensions", {{"KHR_materials_unlit", json::object()}}}}, "KHR_materials_unlit"},
      {"color0", json::object(), nullptr, true},
      {"normal_scale", {{"normalTexture", {{"index", 2}, {"scale", 3.0}}}}, nullptr},
      {"texture_transform",
       {{"emissiveFactor", {0.3, 0.3, 0.3}},
        {"emissiveTexture", {{"index", 1}, {"extensions", tt}}}},
       "KHR_texture_transform"},
  };
  for (const Case& c : cases) {
    json m = {{"pbrMetallicRoughness", base}};
    for (auto it = c.extra.begin(); it != c.extra.end(); ++it) m[it.key()] = it.value();
    MaterialDoc d = test::material_quad(dir, m, 0.4f, 0.8f);
    if (c.extension) test::use_extension(d, c.extension);
    d.texture("base", kQuad);
    d.texture("greys", kGreys);
    const glm::vec4 nm(0.7f, 0.35f, 0.85f, 1.0f);
    const glm::vec4 nmap[4] = {nm, nm, nm, nm};
    d.texture("normal", nmap);
    if (c.uv1) {
      const std::vector<float> uv1 = {1, 0, 0, 0, 0, 1, 1, 1};
      d.primitive()["attributes"]["TEXCOORD_1"] = d.accessor(uv1, 2, test::kFloatType, "VEC2");
    }
    if (c.color0) {
      const std::vector<uint8_t> col = {255, 64, 64, 64, 255, 64, 64, 64, 255, 255, 255, 255};
      d.primitive()["attributes"]["COLOR_0"] = d.accessor(col, 3, test::kUByteType, "VEC3", true);
    }
    expect_agreement(d.write(c.name), c.name);
  }
}

// The occlusion texture under image-based light (a file without lights: the studio environment,
// turned and scaled): it scales the whole indirect term, split-sum specular included, before
// the emissive term; metallic-roughness (the glTF default) and Blinn-Phong, on normal and relief.
TEST(GlMaterials, OcclusionUnderEnvironmentAgreesWithCpu) {
  RELIEF_REQUIRE_GL();
  const auto dir = test::fresh_test_dir("gl_materials_env");
  const EnvironmentView view = environment_view(-50.0f, 1.3f);
  const glm::vec4 zero[4] = {{0, 0, 0, 1}, {0, 0, 0, 1}, {0, 0, 0, 1}, {0, 0, 0, 1}};
  for (bool blinn_phong : {false, true})
    for (const char* technique : {"normal", "relief"}) {
      json ext = {{"technique", technique}};
      if (blinn_phong) ext["shading"] = "blinn_phong";
      if (std::string(technique) == "relief") {
        ext["depth_texture"] = {{"index", 3}};
        ext["depth_scale"] = 0.05;
      }
      json m = {{"pbrMetallicRoughness",
                 {{"baseColorFactor", {0.8, 0.8, 0.8, 1}},
                  {"baseColorTexture", {{"index", 0}}},
                  {"metallicFactor", 0.5},
                  {"roughnessFactor", 0.4}}},
                {"occlusionTexture", {{"index", 1}, {"strength", 0.9}}},
                {"emissiveFactor", {0.05, 0.02, 0.0}},
                {"normalTexture", {{"index", 2}}},
                {"extensions", {{"RELIEF_relief_mapping", ext}}}};
      MaterialDoc d = test::material_quad(dir, m, 0.3f, 0.0f);
      d.texture("base", kQuad);
      d.texture("occlusion", kGreys);
      const glm::vec4 nm(0.65f, 0.4f, 0.9f, 1.0f);
      const glm::vec4 nmap[4] = {nm, nm, nm, nm};
      d.texture("normal", nmap);
      d.texture("depth", zero);
      const std::string name = std::string(technique) + (blinn_phong ? "_blinn_phong" : "_mr");
      expect_agreement(d.write(name), "environment, occlusion, " + name, &view);
    }
}

}  // namespace
}  // namespace relief
