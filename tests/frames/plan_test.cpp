// The effect planner (render/plan.cpp; DESIGN.md, "Effects, and simulating only what a scene calls
// for"): passes and variants hold only what the scene asks for, and --explain / --stats say so.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "builtin/builtin.h"
#include "builtin/builtin_room.h"
#include "plugins/registry.h"
#include "render/render.h"

namespace relief {
namespace {

RenderOptions small_options() {
  RenderOptions opt;
  opt.width = 160;
  opt.height = 120;
  return opt;
}

std::vector<std::string> pass_names(const Plan& p) {
  std::vector<std::string> names;
  for (const PassPlan& pass : p.passes) names.push_back(pass.name);
  return names;
}

Scene room() {
  Result<Scene> s = make_room_scene();
  EXPECT_TRUE(s.ok());
  s->lights[0].shadow_resolution = 256;
  return std::move(s).value();
}

Plan plan_of(const Scene& s, const RenderOptions& opt = small_options()) {
  Result<Plan> p = make_plan(s, opt);
  EXPECT_TRUE(p.ok()) << p.status().message();
  return p.ok() ? std::move(p).value() : Plan{};
}

RenderResult render(const Scene& s, const RenderOptions& opt = small_options()) {
  const Plan p = plan_of(s, opt);
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(s, p);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return std::move(r).value();
}

uint64_t total_shadow_steps(const RenderResult& r) {
  uint64_t n = 0;
  for (const PassStats& p : r.passes) n += p.raster.work.shadow_steps;
  return n;
}

TEST(Plan, EveryBuiltinSceneListsExactlyTheExpectedPasses) {
  // A scene added to builtin_scenes() must be added here with the passes it should plan.
  const std::map<std::string, std::vector<std::string>> expected = {
      {"plane", {"main"}},  // its sun casts no shadows
      {"pattern", {"main"}},
      {"room", {"shadow:spot", "main"}},  // the fill light casts none
      {"bending", {"main"}},              // plane's sun, no shadows
      {"sphere", {"main"}},               // the curved scenes' suns cast none
      {"cylinder", {"main"}},
      {"torus", {"main"}},
      {"teapot", {"main"}},
      {"interpenetration", {"main"}},          // its sun casts none
      {"teatime", {"shadow:spot", "main"}},    // the fill light casts none
      {"impostor", {"main"}},                  // its sun casts none
      {"materials", {"shadow:spot", "main"}},  // the fill light casts none
      {"fur", {"main"}},                       // its sun casts none
      {"grass", {"main"}},                     // its sun casts none
  };
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    Result<Scene> s = make_builtin_scene(info.name);
    ASSERT_TRUE(s.ok()) << info.name;
    const auto it = expected.find(info.name);
    if (it == expected.end()) {
      ADD_FAILURE() << "no expected passes for built-in scene '" << info.name << "'";
      continue;
    }
    EXPECT_EQ(pass_names(plan_of(*s)), it->second) << info.name;
  }
}

// --technique replaces the technique of relief materials only (the plain spheres of
// `interpenetration` stay flat); --param reaches every material whose technique declares the key;
// a key no technique of the scene declares is a usage error.
TEST(Plan, TechniqueAndParamOverridesReachTheMaterialsTheyApplyTo) {
  Result<Scene> s = make_builtin_scene("interpenetration");
  ASSERT_TRUE(s.ok());
  RenderOptions opt = small_options();
  opt.technique = "exact";
  const Plan p = plan_of(*s, opt);
  ASSERT_EQ(p.materials.size(), s->materials.size());
  int relief = 0;
  for (size_t i = 0; i < s->materials.size(); ++i) {
    const bool has_depth = s->materials[i].textures.count("depth") != 0;
    relief += has_depth;
    EXPECT_EQ(std::string(p.materials[i].plugin->name), has_depth ? "exact" : "flat")
        << s->materials[i].name;
  }
  EXPECT_GT(relief, 0);
  EXPECT_LT(relief, static_cast<int>(s->materials.size()));

  opt.technique = "relief";
  opt.params = {{"binary_steps", "3"}};  // relief has it, flat does not
  const Plan q = plan_of(*s, opt);
  const PluginDescriptor& rp = *q.materials[0].plugin;
  ASSERT_EQ(std::string(rp.name), "relief");
  EXPECT_EQ(q.materials[0].uniforms.params[param_index(rp, "binary_steps")], 3.0f);

  opt.params = {{"no_such_parameter", "1"}};
  Result<Plan> bad = make_plan(*s, opt);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().exit_code(), 2);
  EXPECT_NE(bad.status().message().find("'no_such_parameter'"), std::string::npos);
}

// A slot the chosen parameters do not read is neither required nor baked (reads_texture):
// relief_quadric bakes its relaxed cone map for search=relaxed_cone only, and --explain says so.
TEST(Plan, DerivedMapsAreBakedOnlyForTheParametersThatReadThem) {
  Result<Scene> s = make_builtin_scene("sphere");
  ASSERT_TRUE(s.ok());
  RenderOptions opt = small_options();
  opt.technique = "relief_quadric";
  const auto cone_slot = [](const BoundMaterial& m) {
    return texture_slot_index(*m.plugin, "cone_relaxed");
  };
  const auto says = [](const BoundMaterial& m, const std::string& text) {
    for (const std::string& r : m.reasons)
      if (r.find(text) != std::string::npos) return true;
    return false;
  };
  const Plan linear = plan_of(*s, opt);
  ASSERT_FALSE(linear.materials.empty());
  const BoundMaterial& l = linear.materials[0];
  ASSERT_GE(cone_slot(l), 0);
  EXPECT_EQ(l.uniforms.textures[cone_slot(l)], nullptr);
  EXPECT_TRUE(says(l, "cone_relaxed: not baked"));

  opt.params = {{"search", "relaxed_cone"}};
  const Plan relaxed = plan_of(*s, opt);
  const BoundMaterial& r = relaxed.materials[0];
  ASSERT_NE(r.uniforms.textures[cone_slot(r)], nullptr);
  EXPECT_EQ(r.uniforms.textures[cone_slot(r)]->width(),
            r.uniforms.textures[texture_slot_index(*r.plugin, "depth")]->width());
  EXPECT_FALSE(says(r, "cone_relaxed: not baked"));
  EXPECT_TRUE(says(r, "cone_relaxed: relaxed cone map"));

  // lod=max-mip's chain: derived only when that mode is chosen, with the depth map's size
  const auto max_mip_slot = [](const BoundMaterial& m) {
    return texture_slot_index(*m.plugin, "depth_max_mip");
  };
  ASSERT_GE(max_mip_slot(l), 0);
  EXPECT_EQ(l.uniforms.textures[max_mip_slot(l)], nullptr);
  EXPECT_TRUE(says(l, "depth_max_mip: not baked"));
  opt.params = {{"lod", "max-mip"}};
  const Plan mm = plan_of(*s, opt);
  const BoundMaterial& b = mm.materials[0];
  const Texture* chain = b.uniforms.textures[max_mip_slot(b)];
  ASSERT_NE(chain, nullptr);
  const Texture* depth = b.uniforms.textures[texture_slot_index(*b.plugin, "depth")];
  EXPECT_EQ(chain->width(), depth->width());
  EXPECT_GT(chain->levels(), 1);
  EXPECT_TRUE(says(b, "depth_max_mip: max-mip chain"));
  EXPECT_TRUE(says(b, "cone_relaxed: not baked"));
}

TEST(Plan, RoomPlansReliefCastersAndReceivers) {
  const Scene s = room();
  const Plan p = plan_of(s);
  ASSERT_EQ(p.passes.size(), 2u);
  EXPECT_EQ(p.passes[0].kind, PassPlan::Kind::kShadow);
  EXPECT_EQ(p.passes[0].light, 0);
  EXPECT_EQ(p.passes[0].instances.size(), s.instances.size());
  EXPECT_EQ(p.passes[0].shadow.faces, 1);
  EXPECT_FALSE(p.passes[0].shadow.orthographic);
  for (const BoundMaterial& b : p.materials) {
    EXPECT_TRUE(b.effects & kEffectReceiveShadow);
    EXPECT_TRUE(b.shadow_caster);
    EXPECT_EQ(b.shadow_effects, kEffectShadowPass);
  }
  ASSERT_EQ(p.skipped.size(), 1u);
  EXPECT_NE(p.skipped[0].find("'fill'"), std::string::npos);
  EXPECT_NE(p.skipped[0].find("casts_shadows is off"), std::string::npos);
  const std::string text = p.explain();
  for (const char* needle : {"shadow:spot: light 'spot' (spot): casts shadows",
                             "receive_shadow: on", "not planned:", "corrected depth"})
    EXPECT_NE(text.find(needle), std::string::npos) << needle << "\n" << text;
}

TEST(Plan, SwitchingOffSelfShadowZeroesShadowSteps) {
  Scene s = room();
  EXPECT_GT(total_shadow_steps(render(s)), 0u);
  // for the frame
  RenderOptions opt = small_options();
  opt.self_shadow = false;
  const Plan p = plan_of(s, opt);
  for (const BoundMaterial& b : p.materials) EXPECT_FALSE(b.effects & kEffectSelfShadow);
  EXPECT_NE(p.explain().find("self_shadow: off (switched off for this frame)"), std::string::npos);
  EXPECT_EQ(total_shadow_steps(render(s, opt)), 0u);
  // in the materials
  for (Material& m : s.materials) m.self_shadow = false;
  const RenderResult r = render(s);
  EXPECT_EQ(total_shadow_steps(r), 0u);
  EXPECT_GT(r.passes.back().raster.work.search_steps, 0u);
}

TEST(Plan, RemovingTheLightsCastsShadowsRemovesTheShadowPass) {
  Scene s = room();
  s.lights[0].casts_shadows = false;
  const Plan p = plan_of(s);
  EXPECT_EQ(pass_names(p), std::vector<std::string>{"main"});
  for (const BoundMaterial& b : p.materials) {
    EXPECT_FALSE(b.effects & kEffectReceiveShadow);
    EXPECT_FALSE(b.shadow_caster);
  }
  EXPECT_EQ(render(s).passes.size(), 1u);
}

TEST(Plan, NoShadowPassWithoutCasterOrVisibleReceiver) {
  {
    Scene s = room();
    for (Material& m : s.materials) m.casts_shadow = false;
    EXPECT_EQ(pass_names(plan_of(s)), std::vector<std::string>{"main"});
    EXPECT_NE(plan_of(s).explain().find("no material casts shadows"), std::string::npos);
  }
  {
    Scene s = room();
    for (Material& m : s.materials) m.receives_shadow = false;
    EXPECT_EQ(pass_names(plan_of(s)), std::vector<std::string>{"main"});
  }
  {
    Scene s = room();  // the camera looks away from everything
    s.cameras[0].position = glm::vec3(0.0f, 2.0f, 9.0f);
    s.cameras[0].target = glm::vec3(0.0f, 2.0f, 20.0f);
    const Plan p = plan_of(s);
    EXPECT_EQ(pass_names(p), std::vector<std::string>{"main"});
    EXPECT_NE(p.explain().find("nothing visible receives shadows"), std::string::npos);
  }
  {
    RenderOptions opt = small_options();
    opt.shadows = false;
    EXPECT_EQ(pass_names(plan_of(room(), opt)), std::vector<std::string>{"main"});
  }
}

TEST(Plan, CastersWithoutAShadowPassVariantWritePolygonDepth) {
  Scene s = room();
  s.materials[2].technique = "flat";  // the columns
  const Plan p = plan_of(s);
  ASSERT_EQ(p.passes.size(), 2u);
  EXPECT_TRUE(p.materials[2].shadow_caster);
  EXPECT_EQ(p.materials[2].shadow_effects, 0u);
  EXPECT_TRUE(p.materials[2].effects & kEffectReceiveShadow);  // flat receives
  EXPECT_NE(p.explain().find("polygon depth: flat has no shadow-pass variant"), std::string::npos);
  EXPECT_EQ(render(s).passes.size(), 2u);
}

TEST(Plan, DirectionalAndPointLightsFitTheirViews) {
  Scene s = room();
  s.lights[1].casts_shadows = true;  // the directional fill
  s.lights[1].shadow_resolution = 128;
  Plan p = plan_of(s);
  ASSERT_EQ(pass_names(p), (std::vector<std::string>{"shadow:spot", "shadow:fill", "main"}));
  EXPECT_TRUE(p.passes[1].shadow.orthographic);
  s.lights[0].type = LightType::kPoint;
  p = plan_of(s);
  EXPECT_EQ(p.passes[0].shadow.faces, 6);
  const RenderResult r = render(s);
  ASSERT_EQ(r.passes.size(), 3u);
  EXPECT_EQ(r.passes[0].faces, 6);
  EXPECT_GT(r.passes[1].raster.work.fragments, 0u);
}

TEST(Plan, BadShadowSettingsAndResolutionAreErrors) {
  RenderOptions opt = small_options();
  opt.shadow.pcf_radius = 9;
  EXPECT_FALSE(make_plan(room(), opt).ok());
  opt = small_options();
  opt.shadow.depth_bias = -1.0f;
  EXPECT_FALSE(make_plan(room(), opt).ok());
  Scene s = room();
  s.lights[0].shadow_resolution = 0;
  Result<Plan> p = make_plan(s, small_options());
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.status().message().find("shadow_resolution"), std::string::npos);
}

// `relief render --explain --stats`: the plan on stdout, per-pass counters in the JSON.
TEST(Plan, CliExplainAndStatsListThePasses) {
  const std::string dir = std::string(RELIEF_BINARY_DIR) + "/plan_test_out";
  std::filesystem::create_directories(dir);
  const std::string json = dir + "/room.json";
  const std::string cmd = std::string(RELIEF_CLI) + " render room --size 96x72 --threads 2 -o " +
                          dir + "/room.png --explain --stats " + json + " 2>&1";
  FILE* f = popen(cmd.c_str(), "r");
  ASSERT_NE(f, nullptr);
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, f)) out += buf;
  ASSERT_EQ(pclose(f), 0) << out;
  EXPECT_NE(out.find("shadow:spot: light 'spot'"), std::string::npos) << out;
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["passes"].size(), 2u);
  const auto& shadow = j["passes"][0];
  EXPECT_EQ(shadow["kind"], "shadow");
  EXPECT_EQ(shadow["resolution"], 1024);
  for (const char* k : {"fragments_shaded", "texture_fetches", "search_steps", "ms"})
    EXPECT_GT(shadow[k].get<double>(), 0.0) << k;
  EXPECT_EQ(shadow["shadow_steps"], 0);  // the shadow-pass variant traces no self-shadow rays
  const auto& main = j["passes"][1];
  EXPECT_EQ(main["kind"], "main");
  EXPECT_GT(main["shadow_steps"].get<double>(), 0.0);
  EXPECT_TRUE(j["plan"]["passes"].contains("shadow:spot"));
}

}  // namespace
}  // namespace relief
