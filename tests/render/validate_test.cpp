// The one validator of techniques and parameters (render/validate.h) and the normal map derived
// from depth (render/derived_maps.h): scene/ loads a file as data, with no registry; load_scene
// checks it with the same one-line messages (file and JSON pointer) the loader gave; the planner
// checks --technique and --param with the same code; the derived normal map is the baker's.
#include "render/validate.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "bake/normal_map.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "scene/gltf.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

const std::string kExt = "/materials/0/extensions/RELIEF_relief_mapping";

// scenes/plane.gltf (one relief material, no normal texture) copied to a fresh folder with its
// RELIEF_relief_mapping object edited by `edit`; returns the new file's path.
template <class Edit>
std::string plane_with(const fs::path& dir, const std::string& name, Edit edit) {
  const fs::path src = fs::path(RELIEF_SOURCE_DIR) / "scenes";
  for (const char* f : {"plane.bin", "plane_bricks_base_color.png", "plane_bricks_depth.png"})
    fs::copy_file(src / f, dir / f, fs::copy_options::overwrite_existing);
  std::ifstream in(src / "plane.gltf");
  json doc = json::parse(in);
  edit(doc["materials"][0]["extensions"]["RELIEF_relief_mapping"]);
  const std::string path = (dir / (name + ".gltf")).string();
  std::ofstream(path) << doc.dump();
  return path;
}

// The file loads as data (load_gltf knows no technique); load_scene, and validate_scene on the
// data, fail with exactly `message` (exit 1).
void expect_invalid(const std::string& file, const std::string& message) {
  Result<Scene> data = load_gltf(file);
  ASSERT_TRUE(data.ok()) << data.status().message();
  Result<Scene> checked = load_scene(file);
  ASSERT_FALSE(checked.ok());
  EXPECT_EQ(checked.status().message(), message);
  EXPECT_EQ(checked.status().exit_code(), 1);
  Status s = validate_scene(*data);
  EXPECT_EQ(s.message(), message);
  EXPECT_EQ(s.exit_code(), 1);
}

RenderOptions tiny_frame() {
  RenderOptions opt;
  opt.width = 32;
  opt.height = 24;
  return opt;
}

class Validate : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::fresh_test_dir("validate"); }
  fs::path dir_;
};

TEST_F(Validate, AnUnknownTechniqueIsDataToTheSceneAndAnErrorToTheValidator) {
  const std::string f = plane_with(dir_, "unknown", [](json& e) { e["technique"] = "nosuch"; });
  Result<Scene> data = load_gltf(f);
  ASSERT_TRUE(data.ok()) << data.status().message();
  EXPECT_EQ(data->materials[0].technique, "nosuch");
  EXPECT_TRUE(data->materials[0].source.pending());
  // Nothing renders it unchecked.
  RenderOptions opt = tiny_frame();
  Result<Plan> plan = make_plan(*data, opt);
  ASSERT_FALSE(plan.ok());
  EXPECT_NE(plan.status().message().find("not validated"), std::string::npos);
  expect_invalid(f, f + ": " + kExt +
                        "/technique: unknown technique 'nosuch' (known: cone, cone_quad, exact, "
                        "flat, normal, parallax, pom, relaxed_cone, relief, relief_dual, "
                        "relief_quadric, shells, steep_parallax)");
}

TEST_F(Validate, BadParameterValuesNameTheirPointer) {
  expect_invalid(plane_with(dir_, "choice", [](json& e) { e["params"]["lod"] = "bogus"; }),
                 (dir_ / "choice.gltf").string() + ": " + kExt +
                     "/params/lod: relief parameter 'lod': expected one of quad|zero|max-mip (or "
                     "its index 0..2), got \"bogus\"");
  expect_invalid(plane_with(dir_, "range", [](json& e) { e["steps"] = 100000; }),
                 (dir_ / "range.gltf").string() + ": " + kExt +
                     "/steps: relief parameter 'steps': 100000 is outside 1..256");
  expect_invalid(plane_with(dir_, "nobody", [](json& e) { e["params"]["nosuchparam"] = 1; }),
                 (dir_ / "nobody.gltf").string() + ": " + kExt +
                     "/params/nosuchparam: no technique has a parameter 'nosuchparam'");
}

TEST_F(Validate, MissingRequiredTextureAndConeKind) {
  expect_invalid(plane_with(dir_, "nodepth", [](json& e) { e.erase("depth_texture"); }),
                 (dir_ / "nodepth.gltf").string() + ": " + kExt +
                     ": technique relief needs a 'depth' texture (depth_texture)");
  expect_invalid(plane_with(dir_, "cone", [](json& e) { e["cone_texture"] = e["depth_texture"]; }),
                 (dir_ / "cone.gltf").string() + ": " + kExt +
                     "/cone_texture: technique relief reads no cone map: give cone_kind");
}

TEST_F(Validate, ParametersAreTypedOnceByTheirDeclaringTechnique) {
  const std::string f = plane_with(dir_, "typed", [](json& e) {
    e["params"]["lod"] = "max-mip";        // relief's enum: its choice index
    e["params"]["distance"] = "accurate";  // relief_quadric's, kept for --technique
    e["cone_texture"] = e["depth_texture"];
    e["technique"] = "cone";
  });
  Result<Scene> s = load_scene(f);
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Material& m = s->materials[0];
  EXPECT_FALSE(m.source.pending());
  EXPECT_EQ(m.params.at("lod"), 2.0f);
  EXPECT_EQ(m.params.at("distance"), 1.0f);
  EXPECT_EQ(m.params.at("depth_scale"), 0.06f);
  EXPECT_TRUE(m.textures.count("cone_conservative"));  // the cone technique's kind
  EXPECT_EQ(validate_scene(*s).message(), "");         // already resolved: nothing left
}

TEST_F(Validate, OptionsGoThroughTheSameChecks) {
  Result<Scene> s = load_scene(plane_with(dir_, "plain", [](json&) {}));
  ASSERT_TRUE(s.ok()) << s.status().message();
  RenderOptions opt = tiny_frame();
  opt.technique = "nosuch";
  Result<Plan> p = make_plan(*s, opt);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.status().message(), "unknown technique 'nosuch' (see `relief techniques`)");
  EXPECT_EQ(p.status().exit_code(), 2);
  opt.technique = "pom";
  opt.params["steps"] = "abc";
  p = make_plan(*s, opt);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.status().message(),
            "material 'bricks': pom parameter 'steps': expected a number, got 'abc'");
  EXPECT_EQ(p.status().exit_code(), 2);
  // parsed once, kept: the same answer again
  const PluginDescriptor* pom = *find_technique("pom", ValueOrigin::option());
  EXPECT_EQ(param_option(*pom, "steps", "abc").status().message(), p.status().message().substr(19));
  Result<float> v = param_option(*pom, "steps", "12");
  ASSERT_TRUE(v.ok());
  EXPECT_EQ(*v, 12.0f);
}

TEST_F(Validate, TheDerivedNormalMapIsTheBakersBitForBit) {
  Result<Scene> s = load_scene(plane_with(dir_, "normal", [](json&) {}));
  ASSERT_TRUE(s.ok()) << s.status().message();
  Material& m = s->materials[0];
  ASSERT_FALSE(m.textures.count("normal"));
  ASSERT_TRUE(derives_normal_map(m, "normal"));
  const bool wrap = m.sampler.wrap_u == Wrap::kRepeat && m.sampler.wrap_v == Wrap::kRepeat;
  // the material's depth_scale, then its technique's default (relief: 0.05)
  for (const bool own_scale : {true, false}) {
    if (!own_scale) m.params.erase("depth_scale");
    SCOPED_TRACE(own_scale ? "own depth_scale" : "technique's default");
    const Texture want =
        normal_map_from_depth(*m.textures.at("depth"), own_scale ? 0.06f : 0.05f, wrap);
    clear_derived_map_memory_cache();
    for (int round = 0; round < 2; ++round) {  // baked, then from the memory cache
      Result<TexturePtr> got = derived_normal_map(m);
      ASSERT_TRUE(got.ok()) << got.status().message();
      const Texture& t = **got;
      ASSERT_EQ(t.format(), want.format());
      ASSERT_EQ(t.levels(), want.levels());
      EXPECT_EQ(t.color_space(), want.color_space());
      for (int l = 0; l < want.levels(); ++l) EXPECT_EQ(t.level(l).data, want.level(l).data) << l;
    }
  }
  // The planner binds it where the technique reads "normal", and --explain says where it came
  // from; a material that does not ask for it gets none.
  RenderOptions opt = tiny_frame();
  Result<Plan> p = make_plan(*s, opt);
  ASSERT_TRUE(p.ok()) << p.status().message();
  EXPECT_NE(p->explain().find("normal: normal map 512x512"), std::string::npos) << p->explain();
  m.normal_from_depth = false;
  EXPECT_FALSE(derives_normal_map(m, "normal"));
}

// `relief export` leaves out a normal map equal to the derived one, and the file asks for it.
TEST_F(Validate, DerivableNormalMapsAreDroppedForExport) {
  Result<Scene> s = load_scene(plane_with(dir_, "export", [](json&) {}));
  ASSERT_TRUE(s.ok()) << s.status().message();
  Material& m = s->materials[0];
  Result<TexturePtr> derived = derived_normal_map(m);
  ASSERT_TRUE(derived.ok());
  m.textures["normal"] = *derived;
  m.normal_from_depth = false;
  Scene other = *s;
  drop_derivable_normal_maps(*s);
  EXPECT_FALSE(s->materials[0].textures.count("normal"));
  EXPECT_TRUE(s->materials[0].normal_from_depth);
  other.materials[0].normal_scale = 0.5f;  // not the derived map's use: kept
  drop_derivable_normal_maps(other);
  EXPECT_TRUE(other.materials[0].textures.count("normal"));
}

}  // namespace
}  // namespace relief
