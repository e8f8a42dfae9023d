// derived_environment (render/derived_maps.h): baked once per content, then from the memory
// cache. With RELIEF_ENV_DUMP=<folder> it also writes the studio environment, a prefiltered
// level and the split-sum table as PNG and EXR there, and prints the bake time of a 2048x1024
// input (docs/environment.md).
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "render/derived_maps.h"
#include "scene/image_io.h"

namespace relief {
namespace {

TEST(EnvironmentCache, BakedOnceThenFromTheMemoryCache) {
  clear_derived_map_memory_cache();
  EnvironmentBakeOptions o;
  o.specular_size = 32;
  o.specular_samples = 32;
  o.lut_size = 16;
  o.lut_samples = 64;
  const Image img = studio_environment(64, 32);
  Result<DerivedEnvironment> a = derived_environment(img, o);
  ASSERT_TRUE(a.ok()) << a.status().message();
  EXPECT_NE(a->note.find("baked in"), std::string::npos) << a->note;
  Result<DerivedEnvironment> b = derived_environment(img, o);
  ASSERT_TRUE(b.ok());
  EXPECT_EQ(a->maps.get(), b->maps.get());
  EXPECT_NE(b->note.find("memory cache"), std::string::npos) << b->note;
  Image other = img;
  other.at(0, 0).x += 1.0f;  // another content: another bake
  Result<DerivedEnvironment> c = derived_environment(other, o);
  ASSERT_TRUE(c.ok());
  EXPECT_NE(c->maps.get(), a->maps.get());
  EXPECT_FALSE(derived_environment(Image(), o).ok());
}

Image level_image(const Texture& t, int level, float scale) {
  Image out(t.width(level), t.height(level));
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const glm::vec4 v = t.fetch(level, x, y);
      out.at(x, y) = glm::vec4(v.x * scale, v.y * scale, v.z * scale, 1.0f);
    }
  return out;
}

TEST(EnvironmentCache, DumpForLooking) {
  const char* dir = std::getenv("RELIEF_ENV_DUMP");
  if (!dir) GTEST_SKIP() << "set RELIEF_ENV_DUMP=<folder> to write the images";
  const std::string d = dir;
  const Image studio = studio_environment(2048, 1024);
  const auto t0 = std::chrono::steady_clock::now();
  Result<EnvironmentMaps> maps = bake_environment(studio);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(maps.ok());
  std::printf("bake of 2048x1024 (default options): %.0f ms\n", ms);
  Image shown = studio;
  for (glm::vec4& p : shown.pixels) p = glm::vec4(glm::vec3(p) * 0.5f, 1.0f);
  ASSERT_TRUE(write_image(d + "/studio.png", shown).ok());
  ASSERT_TRUE(write_image(d + "/studio.exr", studio).ok());
  for (int k = 0; k < maps->specular.levels(); ++k)
    ASSERT_TRUE(write_image(d + "/specular" + std::to_string(k) + ".png",
                            level_image(maps->specular, k, 0.5f))
                    .ok());
  ASSERT_TRUE(write_image(d + "/brdf_lut.png", level_image(maps->brdf_lut, 0, 1.0f)).ok());
}

}  // namespace
}  // namespace relief
