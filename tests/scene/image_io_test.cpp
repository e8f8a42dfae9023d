// Tests for scene/image_io: round trips through PNG 8/16, EXR and TIFF, texture formats chosen
// from files (made here with OpenImageIO directly), load errors, atomic writes.
#include "scene/image_io.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

double srgb_encode(double c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}
double srgb_decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

class ImageIo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::fresh_test_dir("relief_image_io"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::vector<std::string> listing() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_))
      names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Writes a file with OpenImageIO directly (independent of write_image).
  // `data` holds `data_type` values (the file's type unless given).
  void make_file(const std::string& name, int w, int h, int ch, OIIO::TypeDesc type,
                 const void* data, OIIO::TypeDesc data_type = OIIO::TypeDesc::UNKNOWN) {
    if (data_type == OIIO::TypeDesc::UNKNOWN) data_type = type;
    OIIO::ImageSpec spec(w, h, ch, type);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    auto out = OIIO::ImageOutput::create(path(name));
    ASSERT_TRUE(out) << OIIO::geterror();
    ASSERT_TRUE(out->open(path(name), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(data_type, data)) << out->geterror();
    ASSERT_TRUE(out->close());
  }
  OIIO::ImageSpec file_spec(const std::string& name) {
    auto in = OIIO::ImageInput::open(path(name));
    EXPECT_TRUE(in) << OIIO::geterror();
    return in ? in->spec() : OIIO::ImageSpec();
  }

  fs::path dir_;
};

Image test_image(int w, int h, bool with_alpha) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.at(x, y) = glm::vec4((x + 0.5f) / w, (y + 0.5f) / h, 0.013f * (x + y),
                               with_alpha ? 0.25f + 0.5f * ((x + y) % 2) : 1.0f);
  return img;
}

void expect_one_line_naming(const Status& s, const std::string& path) {
  EXPECT_FALSE(s.ok());
  EXPECT_NE(s.message().find(path), std::string::npos) << s.message();
  EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
}

TEST_F(ImageIo, Png8BitRoundTrip) {
  const Image img = test_image(5, 3, true);
  ASSERT_TRUE(write_image(path("a.png"), img).ok());
  const OIIO::ImageSpec spec = file_spec("a.png");
  EXPECT_EQ(spec.nchannels, 4);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8);
  const Result<Image> back = read_image(path("a.png"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  ASSERT_EQ(back->width, 5);
  ASSERT_EQ(back->height, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const glm::vec4 a = img.at(x, y), b = back->at(x, y);
      // Quantisation happens in sRGB space: half a step there.
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(srgb_encode(b[c]), srgb_encode(a[c]), 0.5 / 255 + 1e-6) << x << "," << y;
      EXPECT_NEAR(b.a, a.a, 0.5 / 255 + 1e-6);  // alpha linear, not premultiplied
    }
  // The stored bytes are sRGB-encoded: 0.5 linear is byte 188.
  Image half(1, 1, glm::vec4(0.5f, 0.0f, 1.0f, 1.0f));
  ASSERT_TRUE(write_image(path("h.png"), half).ok());
  EXPECT_EQ(file_spec("h.png").nchannels, 3);  // opaque: RGB
  const Result<Texture> t = load_texture(path("h.png"));
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->format(), TexFormat::kRGBA8);
  EXPECT_EQ(t->level(0).data[0], 188);
  EXPECT_EQ(t->level(0).data[1], 0);
  EXPECT_EQ(t->level(0).data[2], 255);
  EXPECT_EQ(t->level(0).data[3], 255);
}

TEST_F(ImageIo, PngClampsOutOfRange) {
  Image img(2, 1);
  img.at(0, 0) = glm::vec4(-1.0f, 2.0f, 0.5f, 1.0f);
  img.at(1, 0) = glm::vec4(7.0f, -3.0f, 0.0f, 1.0f);
  ASSERT_TRUE(write_image(path("c.png"), img).ok());
  const Result<Image> back = read_image(path("c.png"));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->at(0, 0).r, 0.0f);
  EXPECT_EQ(back->at(0, 0).g, 1.0f);
  EXPECT_EQ(back->at(1, 0).r, 1.0f);
  EXPECT_EQ(back->at(1, 0).g, 0.0f);
}

TEST_F(ImageIo, ExrRoundTripIsExact) {
  Image img = test_image(4, 4, true);
  img.at(1, 1) = glm::vec4(-2.5f, 1000.0f, 1e-8f, 0.0f);
  ASSERT_TRUE(write_image(path("a.exr"), img).ok());
  const OIIO::ImageSpec spec = file_spec("a.exr");
  EXPECT_EQ(spec.nchannels, 4);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
  const Result<Image> back = read_image(path("a.exr"));
  ASSERT_TRUE(back.ok()) << back.status().message();
  for (int i = 0; i < 16; ++i) EXPECT_EQ(back->pixels[i], img.pixels[i]) << i;
}

TEST_F(ImageIo, Tiff16BitRoundTrip) {
  const Image img = test_image(6, 2, true);
  for (const char* name : {"a.tif", "b.TIFF"}) {
    ASSERT_TRUE(write_image(path(name), img).ok()) << name;
    const OIIO::ImageSpec spec = file_spec(name);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT16);
    EXPECT_EQ(spec.nchannels, 4);
    const Result<Image> back = read_image(path(name));
    ASSERT_TRUE(back.ok()) << back.status().message();
    for (size_t i = 0; i < img.pixels.size(); ++i)
      for (int c = 0; c < 4; ++c)
        EXPECT_NEAR(back->pixels[i][c], img.pixels[i][c], 0.5 / 65535 + 1e-7);  // linear
  }
}

TEST_F(ImageIo, NonFinitePixelsAreWrittenAsZero) {
  Image img(3, 1, glm::vec4(0.5f));
  img.at(0, 0).r = std::numeric_limits<float>::quiet_NaN();
  img.at(1, 0).g = std::numeric_limits<float>::infinity();
  img.at(2, 0).b = -std::numeric_limits<float>::infinity();
  ASSERT_TRUE(write_image(path("n.exr"), img).ok());
  const Result<Image> back = read_image(path("n.exr"));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->at(0, 0), glm::vec4(0.0f, 0.5f, 0.5f, 0.5f));
  EXPECT_EQ(back->at(1, 0), glm::vec4(0.5f, 0.0f, 0.5f, 0.5f));
  EXPECT_EQ(back->at(2, 0), glm::vec4(0.5f, 0.5f, 0.0f, 0.5f));
  ASSERT_TRUE(write_image(path("n.png"), img).ok());
  const Result<Image> png = read_image(path("n.png"));
  ASSERT_TRUE(png.ok());
  EXPECT_EQ(png->at(0, 0).r, 0.0f);
  EXPECT_EQ(png->at(1, 0).g, 0.0f);
}

TEST_F(ImageIo, PlaneRoundTrips) {
  Plane p(4, 3);
  for (int i = 0; i < 12; ++i) p.values[i] = 0.07f * i;
  ASSERT_TRUE(write_plane(path("d.exr"), p).ok());
  EXPECT_EQ(file_spec("d.exr").nchannels, 1);
  const Result<Texture> exr = load_texture(path("d.exr"));
  ASSERT_TRUE(exr.ok()) << exr.status().message();
  EXPECT_EQ(exr->format(), TexFormat::kR32F);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(exr->fetch_r(0, i % 4, i / 4), p.values[i]);

  ASSERT_TRUE(write_plane(path("d.tif"), p).ok());
  const Result<Texture> tif = load_texture(path("d.tif"));
  ASSERT_TRUE(tif.ok()) << tif.status().message();
  EXPECT_EQ(tif->format(), TexFormat::kR32F);
  EXPECT_EQ(tif->fetch_r(0, 3, 2), p.values[11]);

  // PNG: 16-bit grey; values inside [0, 1] are kept as they are.
  ASSERT_TRUE(write_plane(path("d.png"), p).ok());
  const OIIO::ImageSpec spec = file_spec("d.png");
  EXPECT_EQ(spec.nchannels, 1);
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT16);
  const Result<Texture> png = load_texture(path("d.png"));
  ASSERT_TRUE(png.ok()) << png.status().message();
  EXPECT_EQ(png->format(), TexFormat::kR16);
  for (int i = 0; i < 12; ++i)
    EXPECT_NEAR(png->fetch_r(0, i % 4, i / 4), p.values[i], 0.5 / 65535 + 1e-7);
  const Result<Image> grey = read_image(path("d.png"));
  ASSERT_TRUE(grey.ok());
  EXPECT_NEAR(grey->at(1, 0).g, p.values[1], 1e-4);  // 16-bit: linear, grey in r, g, b
  EXPECT_EQ(grey->at(1, 0).a, 1.0f);
}

TEST_F(ImageIo, PlanePngNormalisesLargeRanges) {
  Plane p(3, 1);
  p.values = {0.0f, 16.0f, 64.0f};  // e.g. search steps
  ASSERT_TRUE(write_plane(path("s.png"), p).ok());
  const Result<Texture> t = load_texture(path("s.png"));
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->fetch_r(0, 0, 0), 0.0f);
  EXPECT_NEAR(t->fetch_r(0, 1, 0), 0.25f, 1e-5);
  EXPECT_EQ(t->fetch_r(0, 2, 0), 1.0f);
}

TEST_F(ImageIo, LoadTextureChoosesFormatFromTheFile) {
  const uint8_t grey8[] = {0, 64, 128, 255};
  const uint8_t ga8[] = {10, 20, 30, 40, 50, 60, 70, 80};
  const uint8_t rgb8[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  const uint8_t rgba8[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  const uint16_t grey16[] = {0, 1000, 40000, 65535};
  const uint16_t rgb16[] = {0, 65535, 32768, 65535, 0, 0, 1, 2, 3, 4, 5, 6};
  const float f1[] = {-1.5f, 0.25f, 3.0f, 1e-3f};
  const float f4[] = {0.5f, 1.5f, -2.0f, 0.75f, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};
  make_file("g8.png", 2, 2, 1, OIIO::TypeDesc::UINT8, grey8);
  make_file("ga8.png", 2, 2, 2, OIIO::TypeDesc::UINT8, ga8);
  make_file("rgb8.png", 2, 2, 3, OIIO::TypeDesc::UINT8, rgb8);
  make_file("rgba8.png", 2, 2, 4, OIIO::TypeDesc::UINT8, rgba8);
  make_file("g16.png", 2, 2, 1, OIIO::TypeDesc::UINT16, grey16);
  make_file("rgb16.tif", 2, 2, 3, OIIO::TypeDesc::UINT16, rgb16);
  make_file("f1.exr", 2, 2, 1, OIIO::TypeDesc::FLOAT, f1);
  make_file("h1.exr", 2, 2, 1, OIIO::TypeDesc::HALF, f1, OIIO::TypeDesc::FLOAT);
  make_file("h4.exr", 2, 2, 4, OIIO::TypeDesc::HALF, f4, OIIO::TypeDesc::FLOAT);

  auto load = [&](const std::string& name, TextureLoadOptions o = {}) {
    Result<Texture> t = load_texture(path(name), o);
    EXPECT_TRUE(t.ok()) << name << ": " << t.status().message();
    return t.ok() ? std::move(t).value() : Texture();
  };
  Texture t = load("g8.png");
  EXPECT_EQ(t.format(), TexFormat::kR8);
  EXPECT_EQ(t.level(0).data, std::vector<uint8_t>(grey8, grey8 + 4));
  t = load("ga8.png");
  EXPECT_EQ(t.format(), TexFormat::kRG8);
  EXPECT_EQ(t.level(0).data, std::vector<uint8_t>(ga8, ga8 + 8));
  t = load("rgb8.png");
  EXPECT_EQ(t.format(), TexFormat::kRGBA8);
  EXPECT_EQ(t.level(0).data,
            (std::vector<uint8_t>{1, 2, 3, 255, 4, 5, 6, 255, 7, 8, 9, 255, 10, 11, 12, 255}));
  t = load("rgba8.png");
  EXPECT_EQ(t.format(), TexFormat::kRGBA8);
  EXPECT_EQ(t.level(0).data, std::vector<uint8_t>(rgba8, rgba8 + 16));  // alpha not premultiplied
  t = load("g16.png");
  EXPECT_EQ(t.format(), TexFormat::kR16);
  EXPECT_EQ(t.fetch_r(0, 1, 0), 1000.0f / 65535.0f);
  EXPECT_EQ(t.fetch_r(0, 1, 1), 1.0f);
  t = load("rgb16.tif");
  EXPECT_EQ(t.format(), TexFormat::kRGBA16F);
  EXPECT_EQ(t.fetch(0, 0, 0),
            glm::vec4(0.0f, 1.0f, 0.5f, 1.0f));  // 32768/65535 rounds to 0.5 in half
  t = load("f1.exr");
  EXPECT_EQ(t.format(), TexFormat::kR32F);
  EXPECT_EQ(t.fetch_r(0, 0, 0), -1.5f);
  EXPECT_EQ(t.fetch_r(0, 1, 1), 1e-3f);
  t = load("h1.exr");
  EXPECT_EQ(t.format(), TexFormat::kR16F);
  EXPECT_EQ(t.fetch_r(0, 1, 0), 0.25f);
  t = load("h4.exr");
  EXPECT_EQ(t.format(), TexFormat::kRGBA16F);
  EXPECT_EQ(t.fetch(0, 0, 0), glm::vec4(0.5f, 1.5f, -2.0f, 0.75f));
  EXPECT_EQ(t.fetch(0, 1, 1), glm::vec4(2.0f));

  // first_channel_only keeps channel 0 at the file's depth.
  TextureLoadOptions first;
  first.first_channel_only = true;
  t = load("rgb8.png", first);
  EXPECT_EQ(t.format(), TexFormat::kR8);
  EXPECT_EQ(t.level(0).data, (std::vector<uint8_t>{1, 4, 7, 10}));
  t = load("rgb16.tif", first);
  EXPECT_EQ(t.format(), TexFormat::kR16);
  EXPECT_EQ(t.fetch_r(0, 0, 0), 0.0f);
  EXPECT_EQ(t.fetch_r(0, 1, 0), 1.0f);
  t = load("h4.exr", first);
  EXPECT_EQ(t.format(), TexFormat::kR16F);
  EXPECT_EQ(t.fetch_r(0, 0, 0), 0.5f);
}

TEST_F(ImageIo, LoadTextureSrgb) {
  const uint8_t rgba8[] = {188, 0, 255, 128};
  make_file("c.png", 1, 1, 4, OIIO::TypeDesc::UINT8, rgba8);
  TextureLoadOptions o;
  o.color_space = ColorSpace::kSRGB;
  const Result<Texture> t = load_texture(path("c.png"), o);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->color_space(), ColorSpace::kSRGB);
  EXPECT_EQ(t->level(0).data, std::vector<uint8_t>(rgba8, rgba8 + 4));  // bytes kept
  const glm::vec4 c = t->fetch(0, 0, 0);
  EXPECT_NEAR(c.r, srgb_decode(188 / 255.0), 1e-6);
  EXPECT_EQ(c.g, 0.0f);
  EXPECT_EQ(c.b, 1.0f);
  EXPECT_NEAR(c.a, 128 / 255.0, 1e-7);  // alpha linear
  // A 16-bit colour file is decoded at load.
  const uint16_t rgb16[] = {32768, 0, 65535};
  make_file("c16.png", 1, 1, 3, OIIO::TypeDesc::UINT16, rgb16);
  const Result<Texture> t16 = load_texture(path("c16.png"), o);
  ASSERT_TRUE(t16.ok());
  EXPECT_EQ(t16->format(), TexFormat::kRGBA16F);
  EXPECT_NEAR(t16->fetch(0, 0, 0).r, srgb_decode(32768 / 65535.0), 1e-3);
  EXPECT_EQ(t16->fetch(0, 0, 0).a, 1.0f);
  // read_image decodes 8-bit files from sRGB.
  const Result<Image> img = read_image(path("c.png"));
  ASSERT_TRUE(img.ok());
  EXPECT_NEAR(img->at(0, 0).r, srgb_decode(188 / 255.0), 1e-6);
  EXPECT_NEAR(img->at(0, 0).a, 128 / 255.0, 1e-6);
}

TEST_F(ImageIo, HeightToDepth) {
  const uint8_t h8[] = {0, 1, 200, 255};
  const uint16_t h16[] = {0, 1, 40000, 65535};
  const float hf[] = {0.0f, 0.25f, 0.75f, 1.0f};
  make_file("h8.png", 4, 1, 1, OIIO::TypeDesc::UINT8, h8);
  make_file("h16.png", 4, 1, 1, OIIO::TypeDesc::UINT16, h16);
  make_file("hf.exr", 4, 1, 1, OIIO::TypeDesc::FLOAT, hf);
  TextureLoadOptions o;
  o.height_to_depth = true;
  const Result<Texture> d8 = load_texture(path("h8.png"), o);
  ASSERT_TRUE(d8.ok());
  EXPECT_EQ(d8->level(0).data, (std::vector<uint8_t>{255, 254, 55, 0}));
  const Result<Texture> d16 = load_texture(path("h16.png"), o);
  ASSERT_TRUE(d16.ok());
  EXPECT_EQ(d16->fetch_r(0, 0, 0), 1.0f);
  EXPECT_EQ(d16->fetch_r(0, 2, 0), (65535 - 40000) / 65535.0f);
  EXPECT_EQ(d16->fetch_r(0, 3, 0), 0.0f);
  const Result<Texture> df = load_texture(path("hf.exr"), o);
  ASSERT_TRUE(df.ok());
  for (int i = 0; i < 4; ++i) EXPECT_EQ(df->fetch_r(0, i, 0), 1.0f - hf[i]);
  // Only channel 0 of a colour file is converted.
  const uint8_t rgba[] = {10, 20, 30, 40};
  make_file("n.png", 1, 1, 4, OIIO::TypeDesc::UINT8, rgba);
  const Result<Texture> n = load_texture(path("n.png"), o);
  ASSERT_TRUE(n.ok());
  EXPECT_EQ(n->level(0).data, (std::vector<uint8_t>{245, 20, 30, 40}));
  // sRGB with height_to_depth is refused.
  o.color_space = ColorSpace::kSRGB;
  const Result<Texture> bad = load_texture(path("h8.png"), o);
  expect_one_line_naming(bad.status(), path("h8.png"));
}

TEST_F(ImageIo, JpegLoads) {
  std::vector<uint8_t> px(16 * 16 * 3);
  for (size_t i = 0; i < px.size(); i += 3) {
    px[i] = 200;
    px[i + 1] = 100;
    px[i + 2] = 50;
  }
  make_file("a.jpg", 16, 16, 3, OIIO::TypeDesc::UINT8, px.data());
  const Result<Texture> t = load_texture(path("a.jpg"));
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->format(), TexFormat::kRGBA8);
  EXPECT_NEAR(t->level(0).data[0], 200, 3);
  EXPECT_NEAR(t->level(0).data[1], 100, 3);
  EXPECT_EQ(t->level(0).data[3], 255);
  const Result<Image> img = read_image(path("a.jpg"));
  ASSERT_TRUE(img.ok());
  EXPECT_NEAR(img->at(3, 3).r, srgb_decode(200 / 255.0), 0.02);
}

TEST_F(ImageIo, LoadErrors) {
  const std::string missing = path("missing.png");
  Result<Texture> t = load_texture(missing);
  expect_one_line_naming(t.status(), missing);
  EXPECT_NE(t.status().message().find("no such file"), std::string::npos);
  expect_one_line_naming(read_image(missing).status(), missing);

  const std::string garbage = path("garbage.png");
  std::ofstream(garbage) << "this is not an image\n";
  expect_one_line_naming(load_texture(garbage).status(), garbage);
  expect_one_line_naming(read_image(garbage).status(), garbage);

  // A truncated file: valid header, missing data. (EXR: OIIO 2.4's PNG reader leaks a string
  // when libpng aborts mid-file, which an ASan build would report.)
  ASSERT_TRUE(write_image(path("full.exr"), test_image(64, 64, false)).ok());
  {
    std::ifstream in(path("full.exr"), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path("cut.exr"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  expect_one_line_naming(load_texture(path("cut.exr")).status(), path("cut.exr"));
  expect_one_line_naming(read_image(path("cut.exr")).status(), path("cut.exr"));

  fs::create_directories(path("adir.png"));
  expect_one_line_naming(load_texture(path("adir.png")).status(), path("adir.png"));

  // Larger than 16384 on a side is refused with a message.
  std::vector<uint8_t> wide(kMaxImageSide + 1, 7);
  make_file("wide.png", kMaxImageSide + 1, 1, 1, OIIO::TypeDesc::UINT8, wide.data());
  const Status s = load_texture(path("wide.png")).status();
  expect_one_line_naming(s, path("wide.png"));
  EXPECT_NE(s.message().find("16384"), std::string::npos) << s.message();
  expect_one_line_naming(read_image(path("wide.png")).status(), path("wide.png"));
}

TEST_F(ImageIo, FailedWritesLeaveNoFile) {
  const Image img = test_image(4, 4, false);
  // A directory that does not exist.
  const std::string nodir = path("no/such/dir/out.png");
  expect_one_line_naming(write_image(nodir, img), nodir);
  EXPECT_FALSE(fs::exists(nodir));
  // Unknown extension.
  const std::string unknown = path("out.xyz");
  const Status u = write_image(unknown, img);
  expect_one_line_naming(u, unknown);
  expect_one_line_naming(write_plane(unknown, Plane(2, 2)), unknown);
  // The target is a directory: the temporary must be removed.
  fs::create_directories(path("taken.png"));
  expect_one_line_naming(write_image(path("taken.png"), img), path("taken.png"));
  expect_one_line_naming(write_plane(path("taken.png"), Plane(2, 2)), path("taken.png"));
  // An empty image.
  expect_one_line_naming(write_image(path("empty.png"), Image()), path("empty.png"));
  EXPECT_EQ(listing(), std::vector<std::string>{"taken.png"});
}

TEST_F(ImageIo, WritesReplaceAtomicallyAndLeaveNoTemporary) {
  ASSERT_TRUE(write_image(path("o.exr"), Image(2, 2, glm::vec4(1.0f))).ok());
  ASSERT_TRUE(write_image(path("o.exr"), Image(3, 1, glm::vec4(0.25f))).ok());
  ASSERT_TRUE(write_image(path("o.png"), Image(3, 1, glm::vec4(0.25f))).ok());
  ASSERT_TRUE(write_plane(path("p.exr"), Plane(3, 1, 0.5f)).ok());
  EXPECT_EQ(listing(), (std::vector<std::string>{"o.exr", "o.png", "p.exr"}));
  const Result<Image> back = read_image(path("o.exr"));
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->width, 3);
  EXPECT_EQ(back->at(2, 0), glm::vec4(0.25f));
}

}  // namespace
}  // namespace relief
