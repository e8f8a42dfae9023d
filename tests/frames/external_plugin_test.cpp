#include <gtest/gtest.h>

#include <fstream>

#include "builtin/builtin.h"
#include "plugins/registry.h"
#include "render/render.h"

namespace relief {
namespace {

const std::string kFixture = std::string(RELIEF_BINARY_DIR) + "/lib/relief_test_plugin.so";

TEST(ExternalPlugin, LoadsAndRenders) {
  PluginRegistry reg;
  ASSERT_TRUE(reg.load(kFixture).ok());
  ASSERT_NE(reg.find("fixture_solid"), nullptr);
  // Through the global registry, as `relief render --plugin` does.
  if (!PluginRegistry::global().find("fixture_solid")) {
    ASSERT_TRUE(PluginRegistry::global().load(kFixture).ok());
  }
  Result<Scene> scene = make_builtin_scene("plane");
  ASSERT_TRUE(scene.ok());
  RenderOptions opt;
  opt.width = 64;
  opt.height = 48;
  opt.technique = "fixture_solid";
  opt.params["red"] = "0.5";
  Result<Plan> plan = make_plan(*scene, opt);
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  auto backend = make_cpu_backend({.threads = 2});
  Result<RenderResult> r = backend->render(*scene, *plan);
  ASSERT_TRUE(r.ok());
  // The bottom row looks at the plane: painted by the plugin.
  const glm::vec4 c = r->framebuffer.color.at(32, 47);
  EXPECT_FLOAT_EQ(c.r, 0.5f);
  EXPECT_FLOAT_EQ(c.g, 0.5f);
  EXPECT_FLOAT_EQ(c.b, 0.75f);
}

TEST(ExternalPlugin, MissingFileIsOneClearError) {
  PluginRegistry reg;
  const Status s = reg.load("/nonexistent/plugin.so");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("/nonexistent/plugin.so"), std::string::npos);
  EXPECT_EQ(s.message().find('\n'), std::string::npos);
}

TEST(ExternalPlugin, MalformedFileIsOneClearError) {
  const std::string path = testing::TempDir() + "/not_a_plugin.so";
  std::ofstream(path) << "this is not an ELF file\n";
  PluginRegistry reg;
  const Status s = reg.load(path);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("cannot load plugin"), std::string::npos) << s.message();
}

TEST(ExternalPlugin, SharedObjectWithoutEntryIsRejected) {
  PluginRegistry reg;
  const Status s = reg.load("libm.so.6");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no relief_plugin_entry"), std::string::npos) << s.message();
}

TEST(ExternalPlugin, DuplicateNameIsRejected) {
  PluginRegistry reg;
  ASSERT_TRUE(reg.load(kFixture).ok());
  EXPECT_FALSE(reg.load(kFixture).ok());
}

TEST(Params, UnknownOutOfRangeAndMalformedValuesNameTheParameter) {
  const PluginDescriptor* normal = PluginRegistry::global().find("normal");
  ASSERT_NE(normal, nullptr);
  auto r1 = resolve_params(*normal, {}, {{"bogus", "1"}});
  ASSERT_FALSE(r1.ok());
  EXPECT_NE(r1.status().message().find("'bogus'"), std::string::npos);
  EXPECT_EQ(r1.status().exit_code(), 2);
  auto r2 = resolve_params(*normal, {}, {{"normal_strength", "99"}});
  ASSERT_FALSE(r2.ok());
  EXPECT_NE(r2.status().message().find("normal_strength"), std::string::npos);
  auto r3 = resolve_params(*normal, {}, {{"normal_strength", "1.5x"}});
  ASSERT_FALSE(r3.ok());
  auto r4 = resolve_params(*normal, {}, {{"normal_strength", "nan"}});
  ASSERT_FALSE(r4.ok());
  auto ok = resolve_params(*normal, {}, {{"normal_strength", "2"}});
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ((*ok)[0], 2.0f);
}

}  // namespace
}  // namespace relief
