// Golden images: every built-in scene x every registered technique (and each scene with its own
// techniques), rendered on the CPU backend at 128x96, hashed (64-bit FNV-1a of the colour and
// depth planes) and compared with tests/frames/golden_images.txt. A refactoring that must not
// change output (issue 25: structure, not images) keeps every line; a change that means to alter
// images says so in its commit and rewrites the file with
//   RELIEF_UPDATE_GOLDEN=1 build/bin/test_render --gtest_filter='Golden.*'
// The hashes are those of this repository's Release build with g++ (the CI's compiler): other
// compilers and the sanitizer builds contract and round floating point differently (and would
// spend minutes baking cone maps under ASan), so there the test is skipped and says so.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "builtin/builtin.h"
#include "plugins/registry.h"
#include "render/render.h"
#include "tests/sanitized.h"

namespace relief {
namespace {

#if defined(__GNUC__) && !defined(__clang__) && defined(NDEBUG)
constexpr bool kGoldenCompiler = !test::kSanitizedBuild;
#else
constexpr bool kGoldenCompiler = false;
#endif

const char* golden_path() {
  return RELIEF_SOURCE_DIR "/tests/frames/golden_images.txt";
}

uint64_t fnv1a(uint64_t h, const void* data, size_t n) {
  const auto* b = static_cast<const uint8_t*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  return h;
}

std::string hash_of(const Framebuffer& fb) {
  uint64_t h = 1469598103934665603ull;
  h = fnv1a(h, fb.color.pixels.data(), fb.color.pixels.size() * sizeof(fb.color.pixels[0]));
  h = fnv1a(h, fb.depth.values.data(), fb.depth.values.size() * sizeof(fb.depth.values[0]));
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

// "scene technique" -> hash; technique "-" is the scene's own techniques.
std::map<std::string, std::string> read_golden() {
  std::map<std::string, std::string> out;
  std::ifstream in(golden_path());
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string scene, technique, hash;
    if (ls >> scene >> technique >> hash) out[scene + " " + technique] = hash;
  }
  return out;
}

TEST(Golden, EveryBuiltinSceneAndTechniqueRendersItsRecordedImage) {
  if (!kGoldenCompiler) GTEST_SKIP() << "golden hashes are those of the Release g++ build";
  const std::map<std::string, std::string> golden = read_golden();
  const bool update = std::getenv("RELIEF_UPDATE_GOLDEN") != nullptr;
  if (!update) {
    ASSERT_FALSE(golden.empty()) << golden_path() << " is missing or empty";
  }
  std::map<std::string, std::string> now;
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    Result<Scene> scene = make_builtin_scene(info.name);
    ASSERT_TRUE(scene.ok()) << scene.status().message();
    std::vector<std::string> techniques = {""};
    for (const PluginDescriptor* p : PluginRegistry::global().all()) techniques.push_back(p->name);
    for (const std::string& t : techniques) {
      const std::string key = info.name + " " + (t.empty() ? "-" : t);
      RenderOptions opt;
      opt.width = 128;
      opt.height = 96;
      opt.technique = t;
      Result<Plan> plan = make_plan(*scene, opt);
      if (!plan.ok()) {  // e.g. relief_dual on a scene without a back layer: not listed
        EXPECT_EQ(golden.count(key), 0u)
            << key << " is listed but no longer plans: " << plan.status().message();
        continue;
      }
      Result<RenderResult> r = cpu->render(*scene, *plan);
      ASSERT_TRUE(r.ok()) << key << ": " << r.status().message();
      now[key] = hash_of(r->framebuffer);
    }
  }
  if (update) {
    std::ofstream out(golden_path());
    out << "# scene technique hash (tests/frames/golden_test.cpp; '-' = the scene's own "
           "techniques)\n";
    for (const auto& [key, hash] : now) out << key << " " << hash << "\n";
    std::printf("[ golden   ] wrote %zu hashes to %s\n", now.size(), golden_path());
    return;
  }
  for (const auto& [key, hash] : golden) {
    auto it = now.find(key);
    ASSERT_NE(it, now.end()) << key << " is listed but was not rendered";
    EXPECT_EQ(it->second, hash) << key << ": the image changed";
  }
  for (const auto& [key, hash] : now)
    EXPECT_EQ(golden.count(key), 1u)
        << key << " renders but is not listed (RELIEF_UPDATE_GOLDEN=1)";
}

}  // namespace
}  // namespace relief
