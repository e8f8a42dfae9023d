// A tiled image's tile is decoded into a buffer of its whole size, so a tiny image with huge
// tiles cost seconds and gigabytes (fuzz_image_header found a 20 x 28 EXR with 6560 x 29684
// tiles: 3.4 s, 2 GB). Tiles are checked against kMaxTileValues from the header (issue 20,
// costs without limits).
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scene/image_io.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

bool write_tiled_exr(const fs::path& path, int w, int h, int tile_w, int tile_h, int channels) {
  auto out = OIIO::ImageOutput::create("openexr");
  OIIO::ImageSpec spec(w, h, channels, OIIO::TypeDesc::FLOAT);
  spec.tile_width = tile_w;
  spec.tile_height = tile_h;
  const std::vector<float> pixels(static_cast<size_t>(w) * h * channels, 0.25f);
  return out && out->open(path.string(), spec) &&
         out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()) && out->close();
}

TEST(ImageTileLimit, HugeTilesOnATinyImageAreRefusedFromTheHeader) {
  const fs::path dir = test::fresh_test_dir("relief_tile_limit");
  const fs::path big = dir / "big_tiles.exr";
  ASSERT_TRUE(write_tiled_exr(big, 20, 28, 2048, 1024, 4));  // 8 Mi values a tile
  for (bool texture : {true, false}) {
    const Status s =
        texture ? load_texture(big.string()).status() : read_image(big.string()).status();
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.message().find("tiles of 2048x1024 texels x 4 channels, more than the limit of " +
                               std::to_string(kMaxTileValues)),
              std::string::npos)
        << s.message();
  }
  // Ordinary tiles load, also when they are larger than the image.
  const fs::path ok = dir / "ok_tiles.exr";
  ASSERT_TRUE(write_tiled_exr(ok, 20, 28, 64, 64, 4));
  Result<Texture> t = load_texture(ok.string());
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->width(0), 20);
  EXPECT_EQ(t->fetch(0, 3, 4).x, 0.25f);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace relief
