// load_environment (scene/image_io.h): Radiance .hdr and OpenEXR equirectangular maps, the 2:1
// rule, invalid texels and one-line errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "scene/image_io.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

// A flat (not run-length encoded) Radiance RGBE file of w x h texels, value(x, y) in each channel.
template <class Value>
void write_hdr(const std::string& path, int w, int h, Value value) {
  std::ofstream f(path, std::ios::binary);
  f << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " << h << " +X " << w << "\n";
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int e = 0;
      const double m = std::frexp(value(x, y), &e);  // value = m 2^e, m in [0.5, 1)
      const unsigned char b = static_cast<unsigned char>(m * 256.0);
      const unsigned char rgbe[4] = {b, b, b, static_cast<unsigned char>(e + 128)};
      f.write(reinterpret_cast<const char*>(rgbe), 4);
    }
}

TEST(EnvironmentIo, HdrRoundTrip) {
  const std::string path = tmp("env_round_trip.hdr");
  const auto value = [](int x, int y) { return std::ldexp(1.0, (x + y) % 7 - 3); };  // 1/8..8
  write_hdr(path, 16, 8, value);
  long long replaced = -1;
  Result<Image> img = load_environment(path, &replaced);
  ASSERT_TRUE(img.ok()) << img.status().message();
  EXPECT_EQ(img->width, 16);
  EXPECT_EQ(img->height, 8);
  EXPECT_EQ(replaced, 0);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) {
      EXPECT_NEAR(img->at(x, y).x, value(x, y), value(x, y) / 128.0) << x << " " << y;
      EXPECT_EQ(img->at(x, y).x, img->at(x, y).z);
      EXPECT_EQ(img->at(x, y).w, 1.0f);
    }
}

TEST(EnvironmentIo, ExrRoundTripAndNegativeTexelsReplaced) {
  Image src(32, 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      src.at(x, y) = glm::vec4(0.1f * x, 100.0f + y, 0.001f * (x + y), 1.0f);
  src.at(5, 6) = glm::vec4(-1.0f, 2.0f, 3.0f, 1.0f);
  const std::string path = tmp("env_round_trip.exr");
  ASSERT_TRUE(write_image(path, src).ok());
  long long replaced = -1;
  Result<Image> img = load_environment(path, &replaced);
  ASSERT_TRUE(img.ok()) << img.status().message();
  EXPECT_EQ(replaced, 1);
  EXPECT_EQ(img->at(5, 6), glm::vec4(0.0f, 2.0f, 3.0f, 1.0f));
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x)
      if (x != 5 || y != 6) {
        EXPECT_EQ(img->at(x, y), src.at(x, y)) << x << " " << y;
      }
}

// Each error is one line that starts with the path.
void expect_one_line_error(const std::string& path, const std::string& says) {
  Result<Image> img = load_environment(path);
  ASSERT_FALSE(img.ok());
  const std::string& m = img.status().message();
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_EQ(m.rfind(path, 0), 0u) << m;
  EXPECT_NE(m.find(says), std::string::npos) << m;
}

TEST(EnvironmentIo, BadFilesAreOneLineErrors) {
  expect_one_line_error(tmp("env_missing.hdr"), "");
  const std::string text = tmp("env_text.hdr");
  std::ofstream(text) << "not an image\n";
  expect_one_line_error(text, "cannot read image");
  const std::string square = tmp("env_square.exr");
  ASSERT_TRUE(write_image(square, Image(16, 16, glm::vec4(1.0f))).ok());
  expect_one_line_error(square, "twice as wide as high");
  const std::string huge = tmp("env_huge.hdr");  // header only: refused before any texel
  std::ofstream(huge, std::ios::binary)
      << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n";
  expect_one_line_error(huge, "limit");
}

}  // namespace
}  // namespace relief
