// Hostile glTF structure (issue 20): deep hierarchies and JSON, invalid values tinygltf would
// default or drop, and draw counts over the limits. Each case is a file the test writes itself and
// must give one clear line naming the file and the JSON pointer (scene/gltf_validate.h).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "plugins/registry.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/gltf_validate.h"
#include "scene/scene.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// One triangle (0,0,0), (1,0,0), (0,1,0) in a data: URI, under node 0 of scene 0.
json triangle() {
  return json::parse(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "buffers":[{"byteLength":36,
      "uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})");
}

// A node chain 0 -> 1 -> ... -> depth-1 with the mesh on the last node.
json chain(int depth) {
  json j = triangle();
  j["nodes"] = json::array();
  for (int i = 0; i < depth; ++i) {
    json n = json::object();
    if (i + 1 < depth)
      n["children"] = {i + 1};
    else
      n["mesh"] = 0;
    j["nodes"].push_back(n);
  }
  return j;
}

class HostileGltf : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::fresh_test_dir("relief_hostile_gltf"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const json& j, const std::string& name) const {
    std::ofstream(path(name)) << j.dump();
    return path(name);
  }
  std::string write_text(const std::string& text, const std::string& name) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }
  // load_gltf fails with one line "<file>: <pointer>: ...<what>...", under 300 characters.
  void expect_error(const json& j, const std::string& pointer, const std::string& what) {
    const std::string f = write(j, "bad.gltf");
    Result<Scene> r = load_scene(f);
    ASSERT_FALSE(r.ok()) << "loaded: " << j.dump().substr(0, 300);
    const std::string& m = r.status().message();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(f + ": " + pointer + ": ", 0), 0u) << m;
    EXPECT_NE(m.find(what), std::string::npos) << m;
    EXPECT_LT(m.size() - f.size(), 300u) << m;
    EXPECT_EQ(r.status().exit_code(), 1);
  }
  void expect_loads(const json& j) {
    Result<Scene> r = load_scene(write(j, "good.gltf"));
    EXPECT_TRUE(r.ok()) << r.status().message();
  }
  fs::path dir_;
};

// ---- defect 1: deep hierarchies ----

TEST_F(HostileGltf, HierarchyAtTheDepthLimitLoads) {
  Result<Scene> r = load_scene(write(chain(kMaxNodeDepth), "at_limit.gltf"));
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->instances.size(), 1u);
}

TEST_F(HostileGltf, DeepHierarchyIsAnErrorNotACrash) {
  expect_error(chain(kMaxNodeDepth + 1), "/nodes/1024", "1025 levels deep");
  expect_error(chain(7000), "/nodes/1024", "more than the limit of 1024");
  // The same chain listed from its leaf's end: the node numbering does not matter.
  json j = chain(7000);
  json reversed = triangle();
  reversed["nodes"] = json::array();
  for (int i = 0; i < 7000; ++i) {
    json n = json::object();
    if (i > 0)
      n["children"] = {i - 1};
    else
      n["mesh"] = 0;
    reversed["nodes"].push_back(n);
  }
  reversed["scenes"][0]["nodes"] = {6999};
  expect_error(reversed, "/nodes/5975", "1025 levels deep in the hierarchy");
}

// render and export through the CLI, 7,000 and 100,000 deep: a clean exit 1, one line.
TEST_F(HostileGltf, DeepHierarchyFailsCleanlyInRenderAndExport) {
  for (int depth : {7000, 100000}) {
    const std::string f = write(chain(depth), "deep" + std::to_string(depth) + ".gltf");
    const std::string out = path("out.png"), exported = path("out.gltf");
    for (const std::string& cmd :
         {"render " + f + " --size 16x16 -o " + out, "export " + f + " -o " + exported}) {
      const CliRun r = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " " + cmd);
      EXPECT_EQ(r.code, 1) << cmd << "\n" << r.out;
      EXPECT_EQ(lines(r.out), 1) << r.out;
      EXPECT_NE(r.out.find(f + ": /nodes/1024: node is 1025 levels deep"), std::string::npos)
          << r.out;
    }
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(exported));
  }
  // The GL backend loads through the same code.
  const std::string f = path("deep7000.gltf");
  const CliRun gl = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + f +
                              " --backend gl --size 16x16 -o " + path("gl.png"));
  EXPECT_EQ(gl.code, 1) << gl.out;
  EXPECT_NE(gl.out.find("/nodes/1024: node is 1025 levels deep"), std::string::npos) << gl.out;
}

TEST_F(HostileGltf, CyclesAndSecondParentsAreErrors) {
  json cycle = triangle();
  cycle["nodes"] = json::parse(R"([{"mesh":0,"children":[1]},{"children":[2]},{"children":[1]}])");
  expect_error(cycle, "/nodes/2/children/0", "already a child of /nodes/0");
  json loop = triangle();
  loop["nodes"] = json::parse(R"([{"mesh":0},{"children":[2]},{"children":[1]}])");
  expect_error(loop, "/nodes/2/children/0", "node 1 is its own ancestor (a cycle)");
  json self = triangle();
  self["nodes"][0]["children"] = {0};
  expect_error(self, "/nodes/0/children/0", "own child");
  json twice = triangle();
  twice["nodes"] = json::parse(R"([{"children":[1,1]},{"mesh":0}])");
  expect_error(twice, "/nodes/0/children/1", "listed twice");
  json not_root = triangle();
  not_root["nodes"] = json::parse(R"([{"children":[1]},{"mesh":0}])");
  not_root["scenes"][0]["nodes"] = {0, 1};
  expect_error(not_root, "/scenes/0/nodes/1", "not a root");
}

// 100,000 nested arrays in extras: tinygltf converts extras recursively, so the text is refused
// before it is parsed.
TEST_F(HostileGltf, DeepJsonNestingIsRefusedBeforeParsing) {
  std::string text = triangle().dump();
  text.pop_back();  // the closing brace
  text += ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  const std::string f = write_text(text, "nested.gltf");
  Result<Scene> r = load_scene(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message().rfind(f + ": JSON nesting deeper than 512 levels", 0), 0u)
      << r.status().message();
  const CliRun cli = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + f +
                               " --size 16x16 -o " + path("n.png"));
  EXPECT_EQ(cli.code, 1) << cli.out;
  EXPECT_EQ(lines(cli.out), 1) << cli.out;
  // Strings are not structure; nesting at the limit is fine.
  std::string ok = triangle().dump();
  ok.pop_back();
  ok +=
      ",\"extras\":{\"s\":\"[[[[[[[[\\\"[[[[\","
      "\"d\":" +
      std::string(500, '[') + std::string(500, ']') + "}}";
  Result<Scene> fine = load_scene(write_text(ok, "ok.gltf"));
  EXPECT_TRUE(fine.ok()) << fine.status().message();
  EXPECT_TRUE(check_json_nesting(std::string(512, '{'), "x").ok());
  EXPECT_FALSE(check_json_nesting(std::string(513, '{'), "x").ok());
}

// ---- defect 8: invalid values ----

TEST_F(HostileGltf, AssetVersionMustBeTwoPointSomething) {
  for (const char* v : {"1.0", "3.0", "banana", "2", "2.0.1", " 2.0", "-2.0", "2.x"}) {
    json j = triangle();
    j["asset"]["version"] = v;
    expect_error(j, "/asset/version",
                 std::string(v) == "1.0" || std::string(v) == "3.0"
                     ? "is not supported (only glTF 2.x)"
                     : "expected a version like \"2.0\"");
  }
  json num = triangle();
  num["asset"]["version"] = 2.0;
  expect_error(num, "/asset/version", "expected a string");
  json none = triangle();
  none["asset"].erase("version");
  expect_error(none, "/asset", "missing 'version'");
  json min = triangle();
  min["asset"]["minVersion"] = "2.1";
  expect_error(min, "/asset/minVersion", "relief reads glTF 2.0");
  min["asset"]["minVersion"] = "two";
  expect_error(min, "/asset/minVersion", "expected a version");
  json later = triangle();
  later["asset"]["version"] = "2.1";  // a later minor version reads as 2.0
  later["asset"]["minVersion"] = "2.0";
  expect_loads(later);
}

TEST_F(HostileGltf, ExtensionsRequiredMustBeAnArrayOfUsedSupportedNames) {
  json j = triangle();
  j["extensionsUsed"] = {"KHR_materials_clearcoat"};
  j["extensionsRequired"] = "KHR_materials_clearcoat";
  expect_error(j, "/extensionsRequired", "expected an array of extension names");
  j["extensionsRequired"] = {"KHR_materials_clearcoat"};
  expect_error(j, "/extensionsRequired/0", "is not supported");
  j["extensionsRequired"] = {"KHR_texture_transform"};
  expect_error(j, "/extensionsRequired/0", "is not in extensionsUsed");
  j["extensionsRequired"] = {7};
  expect_error(j, "/extensionsRequired/0", "expected an extension name");
  j["extensionsUsed"] = "KHR_texture_transform";
  j.erase("extensionsRequired");
  expect_error(j, "/extensionsUsed", "expected an array");
  j["extensionsUsed"] = {"KHR_texture_transform", "KHR_texture_transform"};
  expect_error(j, "/extensionsUsed/1", "listed twice");
  j["extensionsUsed"] = {"KHR_texture_transform", "KHR_materials_clearcoat"};
  j["extensionsRequired"] = {"KHR_texture_transform"};
  expect_loads(j);  // a used extension we lack is a warning
}

// The warning for a used extension relief lacks comes only with a scene that loads: an error
// stays the one line the CLI prints.
TEST_F(HostileGltf, UnsupportedUsedExtensionWarnsOnlyWhenTheSceneLoads) {
  json j = triangle();
  j["extensionsUsed"] = {"KHR_materials_clearcoat"};
  j["samplers"] = {{{"wrapS", "REPEAT"}}};
  const std::string bad = write(j, "bad.gltf");
  const CliRun r = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + bad +
                             " --size 8x8 -o " + path("bad.png"));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find(bad + ": /samplers/0/wrapS: expected a wrap mode"), std::string::npos)
      << r.out;
  j.erase("samplers");
  const std::string good = write(j, "good.gltf");
  const CliRun g = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + good +
                             " --size 8x8 -o " + path("good.png"));
  EXPECT_EQ(g.code, 0) << g.out;
  EXPECT_NE(g.out.find("relief: warning: " + good +
                       ": /extensionsUsed/0: extension KHR_materials_clearcoat is not supported, "
                       "ignored"),
            std::string::npos)
      << g.out;
}

// Material parameters go through the same rules as --param (plugins/registry.h).
TEST_F(HostileGltf, EnumAndBoolParamsAreCheckedLikeTheCli) {
  const std::string p = "/materials/0/extensions/RELIEF_relief_mapping/params/";
  auto with = [](const json& params) {
    json j = triangle();
    j["materials"] = {
        {{"extensions", {{"RELIEF_relief_mapping", {{"technique", "flat"}, {"params", params}}}}}}};
    j["meshes"][0]["primitives"][0]["material"] = 0;
    return j;
  };
  expect_error(with({{"distance", 7}}), p + "distance",
               "relief_quadric parameter 'distance': expected one of approximate|accurate");
  expect_error(with({{"distance", 0.5}}), p + "distance", "expected one of");
  expect_error(with({{"distance", "exact"}}), p + "distance", "got \"exact\"");
  expect_error(with({{"offset_limiting", 0.5}}), p + "offset_limiting",
               "parallax parameter 'offset_limiting': expected true or false, got 0.5");
  expect_error(with({{"offset_limiting", "yes"}}), p + "offset_limiting", "expected true or false");
  expect_error(with({{"depth_scale", true}}), p + "depth_scale", "expected a number, got true");
  expect_error(with({{"depth_scale", {1}}}), p + "depth_scale", "expected a number");
  for (const json& ok : {json{{"distance", "accurate"}}, json{{"distance", 1}},
                         json{{"offset_limiting", false}}, json{{"offset_limiting", 1}}}) {
    Result<Scene> r = load_scene(write(with(ok), "good.gltf"));
    ASSERT_TRUE(r.ok()) << ok.dump() << ": " << r.status().message();
    const auto& params = r->materials[0].params;
    const std::string key = ok.begin().key();
    ASSERT_TRUE(params.count(key)) << key;
    EXPECT_EQ(params.at(key), key == "distance" ? 1.0f : (ok.begin()->is_boolean() ? 0.0f : 1.0f));
  }
}

// The same rules hold for values that come as floats (Material::params from any source).
TEST_F(HostileGltf, EnumAndBoolOverridesMustBeIndicesOrZeroOne) {
  const PluginDescriptor* quadric = PluginRegistry::global().find("relief_quadric");
  const PluginDescriptor* parallax = PluginRegistry::global().find("parallax");
  ASSERT_TRUE(quadric && parallax);
  EXPECT_FALSE(resolve_params(*quadric, {{"distance", 7.0f}}, {}).ok());
  EXPECT_FALSE(resolve_params(*quadric, {{"distance", 0.5f}}, {}).ok());
  EXPECT_TRUE(resolve_params(*quadric, {{"distance", 1.0f}}, {}).ok());
  EXPECT_FALSE(resolve_params(*parallax, {{"offset_limiting", 0.5f}}, {}).ok());
  EXPECT_TRUE(resolve_params(*parallax, {{"offset_limiting", 0.0f}}, {}).ok());
  // --param keeps its text rules: a choice name, not an index.
  EXPECT_FALSE(resolve_params(*quadric, {}, {{"distance", "7"}}).ok());
  EXPECT_TRUE(resolve_params(*quadric, {}, {{"distance", "accurate"}}).ok());
}

// A .glb's JSON chunk is validated like a .gltf's text.
TEST_F(HostileGltf, GlbJsonChunkIsValidatedToo) {
  auto glb = [&](const json& j, const std::string& name) {
    std::string chunk = j.dump();
    while (chunk.size() % 4) chunk += ' ';
    const uint32_t header[5] = {0x46546C67u, 2, static_cast<uint32_t>(20 + chunk.size()),
                                static_cast<uint32_t>(chunk.size()), 0x4E4F534Au};
    std::ofstream f(path(name), std::ios::binary);
    f.write(reinterpret_cast<const char*>(header), sizeof header);
    f << chunk;
    return path(name);
  };
  ASSERT_TRUE(load_scene(glb(triangle(), "ok.glb")).ok());
  json v = triangle();
  v["asset"]["version"] = "3.0";
  Result<Scene> r = load_scene(glb(v, "v3.glb"));
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(),
            path("v3.glb") + ": /asset/version: glTF 3.0 is not supported (only glTF 2.x)");
  Result<Scene> deep = load_scene(glb(chain(7000), "deep.glb"));
  ASSERT_FALSE(deep.ok());
  EXPECT_NE(deep.status().message().find(": /nodes/1024: node is 1025 levels deep"),
            std::string::npos)
      << deep.status().message();
}

TEST_F(HostileGltf, SamplerValuesMustBeGlEnums) {
  auto with = [](const json& sampler) {
    json j = triangle();
    j["samplers"] = json::array({sampler});  // not {sampler}: clang copies the object
    return j;
  };
  expect_error(with({{"wrapS", "REPEAT"}}), "/samplers/0/wrapS", "expected a wrap mode");
  expect_error(with({{"wrapT", 12345}}), "/samplers/0/wrapT", "unknown wrap mode 12345");
  expect_error(with({{"minFilter", -1}}), "/samplers/0/minFilter", "unknown filter -1");
  expect_error(with({{"magFilter", 9987}}), "/samplers/0/magFilter", "unknown filter 9987");
  expect_error(with({{"magFilter", 9728.5}}), "/samplers/0/magFilter", "expected a filter");
  json tex = triangle();
  tex["samplers"] = json::array({json::object()});
  tex["images"] = {{{"bufferView", 0}, {"mimeType", "image/png"}}};
  tex["textures"] = {{{"sampler", "0"}, {"source", 0}}};
  expect_error(tex, "/textures/0/sampler", "expected an index into /samplers (0..0), got \"0\"");
  tex["textures"] = {{{"sampler", 0}, {"source", 1}}};
  expect_error(tex, "/textures/0/source", "expected an index into /images (0..0), got 1");
}

TEST_F(HostileGltf, AccessorValuesAreChecked) {
  auto with = [](const char* key, const json& v) {
    json j = triangle();
    j["accessors"][0][key] = v;
    return j;
  };
  expect_error(with("byteOffset", -4), "/accessors/0/byteOffset", "expected an integer >= 0");
  expect_error(with("byteOffset", 2), "/accessors/0/byteOffset", "not aligned");
  expect_error(with("count", 0), "/accessors/0/count", "accessor has no elements");
  expect_error(with("count", "3"), "/accessors/0/count", "expected an integer >= 1");
  expect_error(with("count", 1e30), "/accessors/0/count", "expected an integer");
  expect_error(with("count", 4), "/accessors/0", "need 48 bytes; buffer view 0 has 36");
  expect_error(with("componentType", 5124), "/accessors/0/componentType",
               "unknown component type 5124");
  expect_error(with("type", "VEC5"), "/accessors/0/type", "expected one of SCALAR");
  expect_error(with("normalized", true), "/accessors/0/normalized", "cannot be normalized");
  expect_error(with("normalized", 1), "/accessors/0/normalized", "expected true or false");
  expect_error(with("min", json::array({0, 0})), "/accessors/0/min", "expected an array of 3");
  expect_error(with("bufferView", -1), "/accessors/0/bufferView", "expected an index");
  json j = triangle();
  j["accessors"][0].erase("componentType");
  expect_error(j, "/accessors/0", "missing 'componentType'");
}

TEST_F(HostileGltf, BufferViewsAndBuffersAreChecked) {
  auto with = [](const char* key, const json& v) {
    json j = triangle();
    j["bufferViews"][0][key] = v;
    return j;
  };
  expect_error(with("byteStride", 3), "/bufferViews/0/byteStride", "4..252");
  expect_error(with("byteStride", 256), "/bufferViews/0/byteStride", "4..252");
  expect_error(with("byteStride", 6), "/bufferViews/0/byteStride", "a multiple of 4");
  expect_error(with("byteLength", 0), "/bufferViews/0/byteLength", "expected an integer >= 1");
  expect_error(with("byteOffset", -1), "/bufferViews/0/byteOffset", "expected an integer >= 0");
  expect_error(with("byteOffset", 4), "/bufferViews/0", "lie outside their buffer (buffer 0");
  expect_error(with("buffer", 1), "/bufferViews/0/buffer", "expected an index into /buffers");
  expect_error(with("target", 1), "/bufferViews/0/target", "unknown buffer view target 1");
  json b = triangle();
  b["buffers"][0]["byteLength"] = -36;
  expect_error(b, "/buffers/0/byteLength", "expected an integer >= 1");
}

TEST_F(HostileGltf, SceneMeshAndPrimitiveValuesAreChecked) {
  json j = triangle();
  j["scene"] = -1;
  expect_error(j, "/scene", "expected an index into /scenes (0..0), got -1");
  j["scene"] = 1;
  expect_error(j, "/scene", "got 1");
  json m = triangle();
  m["meshes"][0]["primitives"] = json::array();
  expect_error(m, "/meshes/0/primitives", "a mesh needs a non-empty array of primitives");
  m["meshes"][0].erase("primitives");
  expect_error(m, "/meshes/0", "missing 'primitives'");
  json p = triangle();
  p["meshes"][0]["primitives"][0]["mode"] = 7;
  expect_error(p, "/meshes/0/primitives/0/mode", "expected an integer in 0..6");
  p["meshes"][0]["primitives"][0]["mode"] = "TRIANGLES";
  expect_error(p, "/meshes/0/primitives/0/mode", "expected an integer");
  json a = triangle();
  a["meshes"][0]["primitives"][0]["attributes"] = json::object();
  expect_error(a, "/meshes/0/primitives/0/attributes", "expected at least one attribute");
  a["meshes"][0]["primitives"][0]["attributes"] = {{"POSITION", 3}};
  expect_error(a, "/meshes/0/primitives/0/attributes/POSITION", "index into /accessors");
  json n = triangle();
  n["nodes"][0]["mesh"] = "0";
  expect_error(n, "/nodes/0/mesh", "expected an index into /meshes");
  n["nodes"][0]["mesh"] = 0;
  n["nodes"][0]["rotation"] = {0, 0, 2, 1};
  expect_error(n, "/nodes/0/rotation/2", "expected a number in [-1");
  json c = triangle();
  c["cameras"] = {{{"type", "fisheye"}}};
  expect_error(c, "/cameras/0/type", "expected one of perspective, orthographic");
  c["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", "wide"}, {"znear", 0.1}}}}};
  expect_error(c, "/cameras/0/perspective/yfov", "expected a number > 0");
  json s = triangle();
  s["skins"] = {{{"joints", json::array()}}};
  expect_error(s, "/skins/0/joints", "a skin needs at least one joint");
}

TEST_F(HostileGltf, NodeMatrixMustBeAffineFiniteAndInvertible) {
  auto with = [](const json& m) {
    json j = triangle();
    j["nodes"][0]["matrix"] = m;
    return j;
  };
  json projective = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, -1, 0, 0, 0, 1};
  expect_error(with(projective), "/nodes/0/matrix", "not affine");
  json singular = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  expect_error(with(singular), "/nodes/0/matrix", "singular");
  json both = triangle();
  both["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  both["nodes"][0]["scale"] = {2, 2, 2};
  expect_error(both, "/nodes/0/matrix", "not both");
  expect_error(with(json::array({1, 0, 0})), "/nodes/0/matrix", "expected an array of 16");
  // Non-finite: JSON has no NaN, and 1e999 is a JSON error (number overflow).
  std::string text = with({12345, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}).dump();
  text.replace(text.find("12345"), 5, "1e999");
  Result<Scene> r = load_scene(write_text(text, "inf.gltf"));
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("number overflow"), std::string::npos)
      << r.status().message();
  EXPECT_EQ(r.status().message().find('\n'), std::string::npos) << r.status().message();
  expect_loads(with({2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1}));
}

// ---- defect 10: draw counts before decoding ----

TEST_F(HostileGltf, TooManyInstancesAreRefusedFromTheJson) {
  json j = triangle();
  j["nodes"] = json::array();
  j["scenes"][0]["nodes"] = json::array();
  const int n = static_cast<int>(kMaxSceneInstances) + 1;
  for (int i = 0; i < n; ++i) {
    j["nodes"].push_back({{"mesh", 0}});
    j["scenes"][0]["nodes"].push_back(i);
  }
  expect_error(j, "/scenes/0",
               "65537 mesh instances (node and primitive pairs), more than the "
               "limit of 65536");
}

TEST_F(HostileGltf, TooManyTrianglesAreRefusedBeforeDecoding) {
  // 1024 unindexed triangles, drawn by 8193 nodes: 8,389,632 > 8,388,608.
  const int vertices = 3 * 1024;
  {
    std::ofstream bin(path("tris.bin"), std::ios::binary);
    const std::string zeros(static_cast<size_t>(vertices) * 12, '\0');
    bin << zeros;
  }
  json j = triangle();
  j["buffers"] = {{{"uri", "tris.bin"}, {"byteLength", vertices * 12}}};
  j["bufferViews"][0]["byteLength"] = vertices * 12;
  j["accessors"][0]["count"] = vertices;
  j["nodes"] = json::array();
  j["scenes"][0]["nodes"] = json::array();
  for (int i = 0; i < 8193; ++i) {
    j["nodes"].push_back({{"mesh", 0}});
    j["scenes"][0]["nodes"].push_back(i);
  }
  const auto start = std::chrono::steady_clock::now();
  expect_error(j, "/scenes/0",
               "8389632 triangles to draw (instances counted), more than the "
               "limit of 8388608");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  // One index accessor of 8 Mi + 1 triangles does not fit the file: refused by its extent.
  json big = triangle();
  big["accessors"].push_back({{"bufferView", 0},
                              {"componentType", 5125},
                              {"count", 3 * ((1 << 23) + 1)},
                              {"type", "SCALAR"}});
  big["meshes"][0]["primitives"][0]["indices"] = 1;
  expect_error(big, "/accessors/1", "bytes; buffer view 0 has 36");
}

// Morphed (and skinned) instances each hold their own copies of the mesh: counted before loading.
TEST_F(HostileGltf, TooManyDeformedVertexCopiesAreRefused) {
  const int vertices = 3 * 1024;
  {
    std::ofstream bin(path("morph.bin"), std::ios::binary);
    bin << std::string(static_cast<size_t>(vertices) * 12, '\0');
    const uint32_t idx[3] = {0, 1, 2};
    bin.write(reinterpret_cast<const char*>(idx), sizeof idx);
  }
  json j = triangle();
  j["buffers"] = {{{"uri", "morph.bin"}, {"byteLength", vertices * 12 + 12}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteLength", vertices * 12}},
                      {{"buffer", 0}, {"byteOffset", vertices * 12}, {"byteLength", 12}}};
  j["accessors"][0]["count"] = vertices;
  j["accessors"].push_back(
      {{"bufferView", 1}, {"componentType", 5125}, {"count", 3}, {"type", "SCALAR"}});
  j["meshes"][0]["primitives"][0]["indices"] = 1;
  j["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", 0}}};
  j["nodes"] = json::array();
  j["scenes"][0]["nodes"] = json::array();
  // 2731 instances x 3072 vertices x 3 (posed, rest, one target) = 25,168,896 > 25,165,824.
  for (int i = 0; i < 2731; ++i) {
    j["nodes"].push_back({{"mesh", 0}});
    j["scenes"][0]["nodes"].push_back(i);
  }
  expect_error(j, "/scenes/0", "25168896 vertices to hold");
  // The same count of plain instances shares one mesh.
  j["meshes"][0]["primitives"][0].erase("targets");
  const std::string f = write(j, "shared.gltf");
  Result<Scene> r = load_scene(f);
  ASSERT_TRUE(r.ok()) << r.status().message();
  EXPECT_EQ(r->meshes.size(), 1u);
  EXPECT_EQ(r->instances.size(), 2731u);
}

// Keys and names come from the file: a pointer escapes '~' and '/' (RFC 6901) and control bytes.
TEST_F(HostileGltf, KeysWithControlBytesStayOnOneLine) {
  json j = triangle();
  j["meshes"][0]["primitives"][0]["attributes"]["A\nB/C~"] = 9;
  expect_error(j, "/meshes/0/primitives/0/attributes/A\\x0aB~1C~0", "index into /accessors");
  json e = triangle();
  e["materials"] = {{{"extensions", {{"RELIEF_relief_mapping", {{"bad\rkey", 1}}}}}}};
  expect_error(e, "/materials/0/extensions/RELIEF_relief_mapping/bad\\x0dkey", "unknown property");
  json t = triangle();
  t["materials"] = {
      {{"extensions",
        {{"RELIEF_relief_mapping", {{"technique", "x\ny" + std::string(400, 'z')}}}}}}};
  expect_error(t, "/materials/0/extensions/RELIEF_relief_mapping/technique", "x\\x0ay");
}

// ---- the shipped scenes stay validator-clean ----

TEST_F(HostileGltf, ShippedScenesPassTheValidator) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(RELIEF_SOURCE_DIR) / "scenes")) {
    if (e.path().extension() != ".gltf") continue;
    std::ifstream f(e.path());
    const json doc = json::parse(f);
    const Status s = validate_gltf_document(doc, e.path().string());
    EXPECT_TRUE(s.ok()) << s.message();
    ++n;
  }
  EXPECT_GT(n, 0);
}

}  // namespace
}  // namespace relief
