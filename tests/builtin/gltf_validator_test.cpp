// Every built-in scene's export (.gltf and .glb) through the Khronos glTF validator
// (tests/tools/validate-gltf.js): 0 errors and 0 warnings. Runs where node and the npm module
// gltf-validator are found (GLTF_VALIDATOR_DIR, default /opt/gltf-validator/node_modules; install:
// scripts/install-gltf-validator.sh); elsewhere the test is skipped and says so.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "builtin/builtin.h"
#include "scene/gltf.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

std::string validator_dir() {
  const char* d = std::getenv("GLTF_VALIDATOR_DIR");
  return d && *d ? d : "/opt/gltf-validator/node_modules";
}

// stdout and stderr of `cmd`, and its exit status.
int run(const std::string& cmd, std::string* out) {
  out->clear();
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out->append(buf, n);
  const int st = ::pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(KhronosValidator, EveryExportHasNoErrorAndNoWarning) {
  std::string out;
  const bool node = run("command -v node", &out) == 0;
  const bool module = fs::exists(validator_dir() + "/gltf-validator/package.json");
  if (!node || !module) {
    std::printf("\n*** skipped: gltf-validator not found (node %s, module %s under %s) ***\n\n",
                node ? "found" : "missing", module ? "found" : "missing", validator_dir().c_str());
    GTEST_SKIP() << "gltf-validator not found";
  }
  const std::string script = std::string(RELIEF_SOURCE_DIR) + "/tests/tools/validate-gltf.js";
  const fs::path dir = test::fresh_test_dir("khronos_validator");
  for (const BuiltinSceneInfo& b : builtin_scenes()) {
    Result<Scene> s = make_builtin_scene(b.name);
    ASSERT_TRUE(s.ok()) << s.status().message();
    for (const char* ext : {".gltf", ".glb"}) {
      const std::string file = (dir / (b.name + ext)).string();
      Status w = save_gltf(*s, file);
      ASSERT_TRUE(w.ok()) << w.message();
      const int rc = run("GLTF_VALIDATOR_DIR='" + validator_dir() + "' timeout 60 node '" + script +
                             "' '" + file + "'",
                         &out);
      std::printf("%s", out.c_str());
      EXPECT_EQ(rc, 0) << out;
    }
  }
}

}  // namespace
}  // namespace relief
