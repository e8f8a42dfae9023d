// Texture limits (docs/errors.md, "Limits"): an image larger than kMaxImageSide on a side or with
// more than kMaxImageTexels texels is refused from its header, with one line naming the file and
// the limit, before any pixel memory is allocated.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scene/image_io.h"
#include "tests/scene/png_header.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

TEST(Limits, TextureSideAndTexelCountAreRefusedFromTheHeader) {
  struct Case {
    uint32_t w, h;
    const char* expect;
  };
  for (const Case& c : {Case{100000, 100000, "16384 on a side"}, Case{16385, 1, "16384 on a side"},
                        Case{16384, 8192, "16777216 texels for a texture"}}) {
    const std::string path =
        tmp("limits_" + std::to_string(c.w) + "x" + std::to_string(c.h) + ".png");
    testing::write_png_header_only(path, c.w, c.h);
    Result<Texture> t = load_texture(path);
    ASSERT_FALSE(t.ok()) << c.w << "x" << c.h;
    const std::string& m = t.status().message();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(path, 0), 0u) << m;  // starts with the file
    EXPECT_NE(m.find(c.expect), std::string::npos) << m;
    EXPECT_EQ(t.status().exit_code(), 1);
    Result<Image> im = read_image(path);
    EXPECT_FALSE(im.ok());
  }
  static_assert(kMaxImageTexels <= static_cast<long long>(kMaxImageSide) * kMaxImageSide);
}

TEST(Limits, TextureAtTheSideLimitIsNotRefusedForItsSize) {
  // 16384 x 1 is inside both limits: the loader gets past the size check and fails on the pixels
  // the header-only file does not have, with a different message.
  const std::string path = tmp("limits_ok_side.png");
  testing::write_png_header_only(path, 16384, 1);
  Result<Texture> t = load_texture(path);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().message().find("than the limit"), std::string::npos) << t.status().message();
}

}  // namespace
}  // namespace relief
