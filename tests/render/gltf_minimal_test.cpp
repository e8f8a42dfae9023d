// A minimal glTF 2.0 file (one triangle, no extensions, no material) loads: tinygltf hands over
// "null" for absent extensions, which once read as "/extensions: malformed extension JSON"
// (found while writing tests/apps/errors_test.cpp; the fuzz seeds all had extensions).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "render/validate.h"
#include "scene/gltf.h"

namespace relief {
namespace {

TEST(GltfMinimal, FileWithoutExtensionsLoads) {
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "gltf_minimal.gltf").string();
  std::ofstream(path) << R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  Result<Scene> s = load_scene(path);
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->meshes.size(), 1u);
  EXPECT_EQ(s->meshes[0].indices.size(), 3u);
  EXPECT_EQ(s->materials.size(), 1u);  // the default flat material
}

}  // namespace
}  // namespace relief
