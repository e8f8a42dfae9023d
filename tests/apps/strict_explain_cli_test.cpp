// `--strict` and `--explain` for what relief ignores in a glTF file (scene/gltf_extensions.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// One triangle (data-URI buffer), material 0 with clearcoat, material 1 plain; both used.
std::string write_scene(const fs::path& dir) {
  // 3 positions (float VEC3), then indices 0 1 2 (ushort) padded.
  const std::string b64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
  json j = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", 44}, {"uri", "data:application/octet-stream;base64," + b64}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 36}},
        {{"buffer", 0}, {"byteOffset", 36}, {"byteLength", 6}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", 3},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}},
        {{"bufferView", 1}, {"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 0}},
           {{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"material", 1}}}}}}},
      {"materials",
       {{{"name", "coated"}, {"extensions", {{"KHR_materials_clearcoat", json::object()}}}},
        {{"name", "plain"}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0},
      {"extensionsUsed", {"KHR_materials_clearcoat"}}};
  const std::string path = (dir / "coated.gltf").string();
  std::ofstream(path) << j.dump(1);
  return path;
}

TEST(StrictCli, IgnoredExtensionWarnsOnceAndStrictRefusesWithoutOutput) {
  const fs::path dir = relief::test::fresh_test_dir("strict_cli");
  const std::string scene = write_scene(dir);
  const std::string png = (dir / "out.png").string();
  const CliRun w = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + scene +
                             " --size 16x16 -o " + png);
  EXPECT_EQ(w.code, 0) << w.out;
  EXPECT_NE(w.out.find("relief: warning: " + scene +
                       ": /materials/0/extensions/KHR_materials_clearcoat: extension "
                       "KHR_materials_clearcoat is not supported, ignored"),
            std::string::npos)
      << w.out;
  size_t n = 0;
  for (size_t p = w.out.find("KHR_materials_clearcoat is not"); p != std::string::npos;
       p = w.out.find("KHR_materials_clearcoat is not", p + 1))
    ++n;
  EXPECT_EQ(n, 1u) << "one line per extension:\n" << w.out;
  EXPECT_TRUE(fs::exists(png));
  fs::remove(png);

  for (const std::string& cmd :
       {"render " + scene + " --size 16x16 -o " + png + " --strict",
        "export " + scene + " -o " + (dir / "e.gltf").string() + " --strict"}) {
    const CliRun s = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " " + cmd);
    EXPECT_EQ(s.code, 1) << cmd << "\n" << s.out;
    EXPECT_EQ(lines(s.out), 1) << s.out;
    EXPECT_EQ(
        s.out.rfind("relief: " + scene + ": /materials/0/extensions/KHR_materials_clearcoat", 0),
        0u)
        << s.out;
    EXPECT_NE(s.out.find("(--strict)"), std::string::npos) << s.out;
  }
  EXPECT_FALSE(fs::exists(png));
  EXPECT_FALSE(fs::exists(dir / "e.gltf"));
}

TEST(ExplainCli, ListsWhatEachMaterialIgnores) {
  const fs::path dir = relief::test::fresh_test_dir("explain_cli");
  const std::string scene = write_scene(dir);
  const CliRun r = run_shell("timeout 20 " + std::string(RELIEF_CLI) + " render " + scene +
                             " --size 16x16 --explain -o " + (dir / "x.png").string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("material 0 'coated': KHR_materials_clearcoat "
                       "(/materials/0/extensions/KHR_materials_clearcoat)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("material 1 'plain': nothing"), std::string::npos) << r.out;
}

}  // namespace
