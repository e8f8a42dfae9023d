// Inputs the fuzzers (tests/fuzz/) found, kept as regressions: each must be one clear error.
#include <gtest/gtest.h>

#include <string>

#include "render/validate.h"
#include "scene/gltf.h"

namespace relief {
namespace {

// A GLB whose image bufferView reaches past its buffer: tinygltf handed those bytes to our image
// callback unchecked and the copy read past the end of the heap block (AddressSanitizer).
TEST(GltfFuzzRegression, ImageBufferViewOutsideItsBufferIsAnError) {
  const std::string file =
      std::string(RELIEF_SOURCE_DIR) + "/tests/scene/data/fuzz-image-view-outside-buffer.glb";
  Result<Scene> s = load_scene(file);
  ASSERT_FALSE(s.ok());
  const std::string& m = s.status().message();
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_NE(m.find("outside their buffer"), std::string::npos) << m;
  EXPECT_EQ(m.rfind(file, 0), 0u) << m;  // names the file first
}

}  // namespace
}  // namespace relief
