// The glTF material features on the CPU backend (plugins/surface.h finish_surface, sample_albedo,
// sample_normal_map; scene/gltf.cpp read_material): each rendered from a tiny file the test
// writes (tests/materials_fixture.h) and checked against the value the glTF rules give.
#include <cmath>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "tests/materials_fixture.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

using nlohmann::json;
using test::material_quad;
using test::MaterialDoc;

constexpr int kSize = 64;

struct Frame {
  Scene scene;
  Framebuffer fb;
};

Frame render_file(const std::string& path, const std::string& technique = "", AovMask aovs = 0) {
  Frame f;
  Result<Scene> s = load_scene(path);
  EXPECT_TRUE(s.ok()) << s.status().message();
  if (!s.ok()) return f;
  f.scene = std::move(*s);
  RenderOptions opt;
  opt.width = kSize;
  opt.height = kSize;
  opt.technique = technique;
  opt.aovs = aovs;
  // the quads without a light are lit by their ambient colour alone (these tests are about the
  // material terms), not by the studio environment a scene without lights gets by default
  opt.studio_environment = false;
  Result<Plan> plan = make_plan(f.scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return f;
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  Result<RenderResult> r = cpu->render(f.scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  if (r.ok()) f.fb = std::move(r->framebuffer);
  return f;
}

// The pixel showing raw uv (u, v) of the quad.
glm::vec3 at(const Framebuffer& fb, float u, float v) {
  return glm::vec3(fb.color.at(static_cast<int>(u * fb.width), static_cast<int>(v * fb.height)));
}

void expect_near3(glm::vec3 got, glm::vec3 want, float tol, const std::string& what) {
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], tol) << what << " channel " << c;
}

// The linear value texel (x, y) of a loaded 2x2 texture holds (what the sampler returns).
glm::vec4 texel(const Texture& t, int x, int y) {
  return t.fetch(0, x, y);
}

const glm::vec4 kQuad[4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}};
const glm::vec4 kGreys[4] = {
    {0.2f, 0.2f, 0.2f, 1}, {0.4f, 0.4f, 0.4f, 1}, {0.6f, 0.6f, 0.6f, 1}, {0.8f, 0.8f, 0.8f, 1}};
const float kCentres[4][2] = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.25f, 0.75f}, {0.75f, 0.75f}};

TEST(Materials, EmissiveOnlyInTheDarkIsTheEmissiveColour) {
  const auto dir = test::fresh_test_dir("materials_emissive");
  json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
            {"emissiveFactor", {0.2, 0.4, 0.6}},
            {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1.5}}}}}};
  MaterialDoc d = material_quad(dir, m, 0.0f, 0.0f);
  test::use_extension(d, "KHR_materials_emissive_strength");
  const int tex = d.texture("emissive", kGreys);
  Frame plain = render_file(d.write("factor"));
  for (const auto& c : kCentres)
    expect_near3(at(plain.fb, c[0], c[1]), glm::vec3(0.3f, 0.6f, 0.9f), 1e-5f, "factor");
  d.material()["emissiveTexture"] = {{"index", tex}};
  Frame textured = render_file(d.write("textured"));
  ASSERT_TRUE(textured.scene.materials.at(0).emissive_texture);
  const Texture& e = *textured.scene.materials[0].emissive_texture;
  for (int q = 0; q < 4; ++q)
    expect_near3(at(textured.fb, kCentres[q][0], kCentres[q][1]),
                 glm::vec3(0.3f, 0.6f, 0.9f) * glm::vec3(texel(e, q % 2, q / 2)), 1e-5f,
                 "textured quadrant " + std::to_string(q));
  // sRGB: the 0.2 grey is stored as its sRGB code and decoded back
  EXPECT_NEAR(texel(e, 0, 0).x, 0.2f, 0.01f);
}

TEST(Materials, OcclusionDarkensOnlyTheAmbientTerm) {
  const auto dir = test::fresh_test_dir("materials_occlusion");
  // a dielectric (glTF's default metallicFactor is 1: a metal, whose diffuse term is 0)
  json m = {
      {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}, {"metallicFactor", 0}}}};
  MaterialDoc d = material_quad(dir, m, 0.4f, 0.8f);
  const int tex = d.texture("occlusion", kGreys);
  Frame base = render_file(d.write("none"));
  d.material()["occlusionTexture"] = {{"index", tex}, {"strength", 0.75}};
  Frame occ = render_file(d.write("occluded"));
  ASSERT_TRUE(occ.scene.materials.at(0).occlusion_texture);
  const Texture& o = *occ.scene.materials[0].occlusion_texture;
  for (int q = 0; q < 4; ++q) {
    const float r = texel(o, q % 2, q / 2).x;  // linear: the stored code / 255
    // ambient * (1 + strength (r - 1)) in place of ambient; the light's term unchanged
    const float want = 0.5f * 0.4f * 0.75f * (1.0f - r);
    const glm::vec3 diff =
        at(base.fb, kCentres[q][0], kCentres[q][1]) - at(occ.fb, kCentres[q][0], kCentres[q][1]);
    expect_near3(diff, glm::vec3(want), 1e-5f, "quadrant " + std::to_string(q));
    EXPECT_GT(want, 0.0f);
  }
  // no ambient: occlusion has nothing to darken
  MaterialDoc dark = material_quad(dir, m, 0.0f, 0.8f);
  const int t2 = dark.texture("occlusion", kGreys);
  Frame lit_only = render_file(dark.write("dark_none"));
  dark.material()["occlusionTexture"] = {{"index", t2}};
  Frame lit_occ = render_file(dark.write("dark_occluded"));
  for (const auto& c : kCentres)
    expect_near3(at(lit_occ.fb, c[0], c[1]), at(lit_only.fb, c[0], c[1]), 1e-6f, "no ambient");
  // the light does reach the quad: 0.5 x 0.8 / pi x cos, less the Fresnel, plus the specular
  EXPECT_GT(at(lit_only.fb, 0.5f, 0.5f).x, 0.05f);
}

TEST(Materials, UnlitIgnoresLightsAmbientAndEmissive) {
  const auto dir = test::fresh_test_dir("materials_unlit");
  json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.3, 0.5, 0.7, 1}}}},
            {"emissiveFactor", {1, 1, 1}},
            {"extensions", {{"KHR_materials_unlit", json::object()}}}};
  MaterialDoc d = material_quad(dir, m, 0.5f, 3.0f);
  test::use_extension(d, "KHR_materials_unlit");
  Frame f = render_file(d.write("unlit"));
  EXPECT_TRUE(f.scene.materials.at(0).unlit);
  for (const auto& c : kCentres)
    expect_near3(at(f.fb, c[0], c[1]), glm::vec3(0.3f, 0.5f, 0.7f), 1e-6f, "unlit");
  // the same material lit is brighter (the test can fail)
  d.material().erase("extensions");
  Frame lit = render_file(d.write("lit"));
  EXPECT_GT(at(lit.fb, 0.5f, 0.5f).x, 0.6f);
}

TEST(Materials, VertexColourMultipliesBaseColour) {
  const auto dir = test::fresh_test_dir("materials_color0");
  json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}}},
            {"extensions", {{"KHR_materials_unlit", json::object()}}}};
  // float VEC4: every vertex the same colour, so every pixel shows it
  {
    MaterialDoc d = material_quad(dir, m, 0.0f, 0.0f);
    test::use_extension(d, "KHR_materials_unlit");
    const std::vector<float> c = {0.5f, 0.25f, 1.0f, 0.5f, 0.5f, 0.25f, 1.0f, 0.5f,
                                  0.5f, 0.25f, 1.0f, 0.5f, 0.5f, 0.25f, 1.0f, 0.5f};
    d.primitive()["attributes"]["COLOR_0"] = d.accessor(c, 4, test::kFloatType, "VEC4");
    Frame f = render_file(d.write("vec4"));
    ASSERT_EQ(f.scene.meshes.at(0).colors.size(), f.scene.meshes[0].positions.size());
    for (const auto& p : kCentres)
      expect_near3(at(f.fb, p[0], p[1]), glm::vec3(0.4f, 0.2f, 0.8f), 1e-6f, "vec4 float");
  }
  // normalised ubyte VEC3, varying across the quad: left edge 255, right edge 0 in red
  {
    MaterialDoc d = material_quad(dir, m, 0.0f, 0.0f);
    test::use_extension(d, "KHR_materials_unlit");
    const std::vector<uint8_t> c = {255, 255, 255, 0, 255, 255, 0, 255, 255, 255, 255, 255};
    d.primitive()["attributes"]["COLOR_0"] = d.accessor(c, 3, test::kUByteType, "VEC3", true);
    Frame f = render_file(d.write("vec3_ubyte"));
    for (float u : {0.125f, 0.375f, 0.625f, 0.875f}) {
      const float x = (std::floor(u * kSize) + 0.5f) / kSize;  // the pixel centre's u
      expect_near3(at(f.fb, u, 0.5f), glm::vec3(0.8f * (1.0f - x), 0.8f, 0.8f), 2e-5f,
                   "ubyte at u " + std::to_string(u));
    }
  }
  // lit: the vertex colour scales the lit colour too
  {
    json lit = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1}}}}};
    MaterialDoc d = material_quad(dir, lit, 0.2f, 1.0f);
    Frame white = render_file(d.write("lit_white"));
    const std::vector<float> c = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f,
                                  0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    d.primitive()["attributes"]["COLOR_0"] = d.accessor(c, 3, test::kFloatType, "VEC3");
    Frame grey = render_file(d.write("lit_grey"));
    const glm::vec3 w = at(white.fb, 0.5f, 0.5f), g = at(grey.fb, 0.5f, 0.5f);
    EXPECT_LT(g.x, w.x - 0.1f);
  }
}

TEST(Materials, TexCoord1IsUsedByTheTexturesThatNameIt) {
  const auto dir = test::fresh_test_dir("materials_uv1");
  json m = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}},
            {"extensions", {{"KHR_materials_unlit", json::object()}}}};
  MaterialDoc d = material_quad(dir, m, 0.0f, 0.0f);
  test::use_extension(d, "KHR_materials_unlit");
  d.texture("quadrants", kQuad);
  // TEXCOORD_1 mirrors u
  const std::vector<float> uv1 = {1, 0, 0, 0, 0, 1, 1, 1};
  const std::string no_uv1 = d.write("missing");
  d.primitive()["attributes"]["TEXCOORD_1"] = d.accessor(uv1, 2, test::kFloatType, "VEC2");
  Frame f = render_file(d.write("uv1"));
  const Texture& t = *f.scene.materials.at(0).textures.at("base_color");
  for (int q = 0; q < 4; ++q) {
    const int mx = 1 - q % 2, y = q / 2;  // mirrored
    expect_near3(at(f.fb, kCentres[q][0], kCentres[q][1]), glm::vec3(texel(t, mx, y)), 1e-6f,
                 "quadrant " + std::to_string(q));
  }
  // a texture naming TEXCOORD_1 on a primitive without it: one line naming both
  Result<Scene> bad = load_scene(no_uv1);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("TEXCOORD_1"), std::string::npos) << bad.status().message();
  EXPECT_NE(bad.status().message().find("/materials/0/pbrMetallicRoughness/baseColorTexture"),
            std::string::npos)
      << bad.status().message();
  EXPECT_EQ(bad.status().message().find('\n'), std::string::npos);
}

TEST(Materials, NormalTextureScaleScalesTheMapsXy) {
  const auto dir = test::fresh_test_dir("materials_normal_scale");
  // A constant map tilted along +u; light straight down -z, no specular: diffuse = n.z.
  const glm::vec4 tilt(0.75f, 0.5f, 0.9f, 1.0f);
  const glm::vec4 flat_map[4] = {tilt, tilt, tilt, tilt};
  for (float scale : {1.0f, 2.0f, 0.0f}) {
    json m = {
        {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}},
        {"normalTexture", {{"index", 0}, {"scale", scale}}},
        {"extensions", {{"RELIEF_relief_mapping", {{"technique", "normal"}, {"specular", 0}}}}}};
    MaterialDoc d = material_quad(dir, m, 0.0f, 1.0f);
    d.texture("normal", flat_map);
    Frame f = render_file(d.write("scale_" + std::to_string(static_cast<int>(scale))));
    ASSERT_FALSE(f.scene.materials.empty());
    EXPECT_EQ(f.scene.materials[0].normal_scale, scale);
    const glm::vec4 c = texel(*f.scene.materials[0].textures.at("normal"), 0, 0);
    const glm::vec3 n =
        glm::normalize(glm::vec3((c.x * 2 - 1) * scale, (c.y * 2 - 1) * scale, c.z * 2 - 1));
    for (const auto& p : kCentres)
      expect_near3(at(f.fb, p[0], p[1]), glm::vec3(n.z), 2e-5f, "scale " + std::to_string(scale));
  }
}

// KHR_texture_transform (offset, rotation, scale) as glTF defines it, then a nearest, clamped
// 2x2 lookup: the texel index the sampler reads at raw uv.
glm::ivec2 texel_index(glm::vec2 uv, glm::vec2 offset, float rotation, glm::vec2 scale) {
  const float c = std::cos(rotation), s = std::sin(rotation);
  const float u = scale.x * uv.x, v = scale.y * uv.y;
  const glm::vec2 t(c * u + s * v + offset.x, -s * u + c * v + offset.y);
  return glm::clamp(glm::ivec2(glm::floor(t * 2.0f)), glm::ivec2(0), glm::ivec2(1));
}

TEST(Materials, EachTextureHasItsOwnTextureTransform) {
  const auto dir = test::fresh_test_dir("materials_transform");
  // base colour (the main texture: the uv varying) offset by (0.5, 0); emissive rotated a quarter
  // turn and offset by (0, 1); occlusion untransformed. Ambient 1, no light: base x occlusion +
  // emissive.
  const glm::vec2 base_off(0.5f, 0.0f), em_off(0.0f, 1.0f);
  const float em_rot = 1.5707963267948966f;
  json tt_base = {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}};
  json tt_em = {{"KHR_texture_transform", {{"offset", {0.0, 1.0}}, {"rotation", em_rot}}}};
  json m = {{"pbrMetallicRoughness",
             {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
              {"baseColorTexture", {{"index", 0}, {"extensions", tt_base}}}}},
            {"emissiveTexture", {{"index", 1}, {"extensions", tt_em}}},
            {"emissiveFactor", {0.25, 0.25, 0.25}},
            {"occlusionTexture", {{"index", 2}}}};
  MaterialDoc d = material_quad(dir, m, 1.0f, 0.0f);
  test::use_extension(d, "KHR_texture_transform");
  d.texture("base", kQuad);
  d.texture("emissive", kGreys);
  const glm::vec4 occ[4] = {
      {1, 1, 1, 1}, {0.5f, 0.5f, 0.5f, 1}, {0.25f, 0.25f, 0.25f, 1}, {0, 0, 0, 1}};
  d.texture("occlusion", occ);
  Frame f = render_file(d.write("transforms"));
  ASSERT_FALSE(f.scene.materials.empty());
  const Material& mat = f.scene.materials[0];
  const Texture& b = *mat.textures.at("base_color");
  const Texture& e = *mat.emissive_texture;
  const Texture& o = *mat.occlusion_texture;
  for (float u : {0.2f, 0.3f, 0.7f, 0.8f})
    for (float v : {0.2f, 0.3f, 0.7f, 0.8f}) {
      const glm::ivec2 bi = texel_index({u, v}, base_off, 0.0f, glm::vec2(1));
      const glm::ivec2 ei = texel_index({u, v}, em_off, em_rot, glm::vec2(1));
      const glm::ivec2 oi = texel_index({u, v}, glm::vec2(0), 0.0f, glm::vec2(1));
      const glm::vec3 want = 0.5f * glm::vec3(texel(b, bi.x, bi.y)) * texel(o, oi.x, oi.y).x +
                             0.25f * glm::vec3(texel(e, ei.x, ei.y));
      expect_near3(at(f.fb, u, v), want, 2e-5f,
                   "uv (" + std::to_string(u) + ", " + std::to_string(v) + ")");
    }
  // the offset moved the base colour only: at u 0.25 it shows the right column, the occlusion
  // its left one
  EXPECT_EQ(texel_index({0.25f, 0.25f}, base_off, 0.0f, glm::vec2(1)).x, 1);
}

// A zero scale on the main texture (the uv varying's) leaves no inverse to map another texture's
// own transform from: one error line naming the main texture, not a NaN uv in the image.
TEST(Materials, SingularMainTextureTransformIsRefused) {
  const auto dir = test::fresh_test_dir("materials_singular");
  json tt_base = {{"KHR_texture_transform", {{"scale", {0.0, 1.0}}}}};
  json tt_em = {{"KHR_texture_transform", {{"offset", {0.0, 1.0}}}}};
  json m = {
      {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", tt_base}}}}},
      {"emissiveTexture", {{"index", 1}, {"extensions", tt_em}}},
      {"emissiveFactor", {0.25, 0.25, 0.25}}};
  MaterialDoc d = material_quad(dir, m, 1.0f, 0.0f);
  test::use_extension(d, "KHR_texture_transform");
  d.texture("base", kQuad);
  d.texture("emissive", kGreys);
  Result<Scene> s = load_scene(d.write("singular"));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.status().message().find("singular"), std::string::npos) << s.status().message();
  EXPECT_NE(s.status().message().find("/materials/0/pbrMetallicRoughness/baseColorTexture"),
            std::string::npos)
      << s.status().message();
}

TEST(Materials, ExportKeepsTheMaterialFeatures) {
  const auto dir = test::fresh_test_dir("materials_export");
  json tt_em = {{"KHR_texture_transform", {{"offset", {0.0, 1.0}}, {"rotation", 1.5707963}}}};
  json m = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
            {"emissiveTexture", {{"index", 1}, {"extensions", tt_em}}},
            {"emissiveFactor", {0.5, 0.25, 0.125}},
            {"occlusionTexture", {{"index", 2}, {"texCoord", 1}, {"strength", 0.5}}},
            {"normalTexture", {{"index", 3}, {"scale", 1.5}}},
            {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2.0}}}}}};
  MaterialDoc d = material_quad(dir, m, 0.3f, 1.0f);
  test::use_extension(d, "KHR_texture_transform");
  test::use_extension(d, "KHR_materials_emissive_strength");
  d.texture("base", kQuad);
  d.texture("emissive", kGreys);
  d.texture("occlusion", kGreys);
  const glm::vec4 nm(0.6f, 0.45f, 0.9f, 1.0f);
  const glm::vec4 nmap[4] = {nm, nm, nm, nm};
  d.texture("normal", nmap);
  const std::vector<float> uv1 = {1, 0, 0, 0, 0, 1, 1, 1};
  d.primitive()["attributes"]["TEXCOORD_1"] = d.accessor(uv1, 2, test::kFloatType, "VEC2");
  const std::vector<float> c = {1, 0.5f, 0.5f, 1, 0.5f, 1, 0.5f, 1, 0.5f, 0.5f, 1, 1, 1, 1, 1, 1};
  d.primitive()["attributes"]["COLOR_0"] = d.accessor(c, 4, test::kFloatType, "VEC4");
  const std::string src = d.write("source");
  Frame a = render_file(src);
  const std::string out = (dir / "exported.gltf").string();
  ASSERT_TRUE(save_gltf(a.scene, out).ok());
  Frame b = render_file(out);
  ASSERT_FALSE(b.scene.materials.empty());
  const Material& ma = a.scene.materials[0];
  const Material& mb = b.scene.materials[0];
  EXPECT_EQ(mb.emissive, ma.emissive);
  EXPECT_EQ(mb.emissive_strength, 2.0f);
  EXPECT_EQ(mb.occlusion_strength, 0.5f);
  EXPECT_EQ(mb.occlusion_uv.set, 1);
  EXPECT_EQ(mb.normal_scale, 1.5f);
  EXPECT_FALSE(mb.emissive_uv.identity);
  EXPECT_EQ(b.scene.meshes.at(0).colors.size(), b.scene.meshes[0].positions.size());
  EXPECT_EQ(b.scene.meshes.at(0).uvs1.size(), b.scene.meshes[0].positions.size());
  double max_diff = 0.0;
  for (size_t i = 0; i < a.fb.color.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k)
      max_diff = std::max(max_diff, static_cast<double>(std::abs(a.fb.color.pixels[i][k] -
                                                                 b.fb.color.pixels[i][k])));
  EXPECT_LT(max_diff, 1e-5) << "the re-loaded export renders differently";
  // unlit round-trips too
  d.material()["extensions"]["KHR_materials_unlit"] = json::object();
  test::use_extension(d, "KHR_materials_unlit");
  Frame u = render_file(d.write("unlit"));
  ASSERT_TRUE(save_gltf(u.scene, (dir / "unlit_out.gltf").string()).ok());
  Result<Scene> ur = load_scene((dir / "unlit_out.gltf").string());
  ASSERT_TRUE(ur.ok()) << ur.status().message();
  EXPECT_TRUE(ur->materials.at(0).unlit);
}

}  // namespace
}  // namespace relief
