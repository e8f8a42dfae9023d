// `relief bake` end to end: the built CLI binary (RELIEF_CLI) on files in a temporary folder.
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bake/cone_map.h"
#include "bake/normal_map.h"
#include "scene/image_io.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

class CmdBake : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_test_dir("relief_cmd_bake");
    // A 24x16 depth map in [0, 1] as 32-bit float EXR.
    Plane p(24, 16);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 0.2f);
    for (int y = 0; y < 16; ++y)
      for (int x = 0; x < 24; ++x)
        p.at(x, y) = std::clamp(
            0.5f + 0.4f * std::sin(x * 0.5f) * std::cos(y * 0.4f) + u(rng) - 0.1f, 0.0f, 1.0f);
    depth_ = path("depth.exr");
    ASSERT_TRUE(write_plane(depth_, p).ok());
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs the CLI; returns the exit code and keeps stderr.
  int run(const std::string& args) {
    const std::string err = path("stderr.txt");
    const std::string cmd = std::string(RELIEF_CLI) + " bake " + args + " >/dev/null 2>" + err;
    const int rc = std::system(cmd.c_str());
    std::ifstream f(err);
    std::stringstream ss;
    ss << f.rdbuf();
    stderr_ = ss.str();
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  }
  // Exactly one line, prefixed like every CLI error.
  void expect_one_line_error() const {
    EXPECT_EQ(stderr_.rfind("relief: ", 0), 0u) << stderr_;
    EXPECT_EQ(std::count(stderr_.begin(), stderr_.end(), '\n'), 1) << stderr_;
  }
  bool only_inputs_left() const {
    for (const auto& e : fs::directory_iterator(dir_)) {
      const std::string n = e.path().filename().string();
      if (n != "depth.exr" && n != "stderr.txt") return false;
    }
    return true;
  }

  fs::path dir_;
  std::string depth_;
  std::string stderr_;
};

TEST_F(CmdBake, MissingInputIsInputError) {
  EXPECT_EQ(run(path("nope.png") + " -o " + path("out.exr") + " --cone relaxed"), 1);
  expect_one_line_error();
  EXPECT_TRUE(only_inputs_left());
}

TEST_F(CmdBake, UsageErrorsLeaveNothingBehind) {
  const std::string out = " -o " + path("out.exr");
  for (const std::string& args :
       {depth_ + out,                                        // neither --normal nor --cone
        depth_ + out + " --normal --cone quad",              // both
        depth_ + out + " --cone wide",                       // unknown kind
        depth_ + out + " --normal --depth-scale -1",         // bad scale
        depth_ + out + " --cone relaxed --max-ratio 0",      // bad ratio
        depth_ + out + " --cone relaxed --threads -3",       // bad threads
        depth_ + out + " --normal --bilinear",               // bilinear is for cones
        depth_ + " -o " + path("out.bmp") + " --cone quad",  // unknown extension
        depth_ + " -o " + path("out.png") + " --cone relaxed --max-ratio 2",  // PNG holds [0,1]
        std::string("--cone relaxed") + out}) {                               // no input
    EXPECT_EQ(run(args), 2) << args;
    expect_one_line_error();
    EXPECT_TRUE(only_inputs_left()) << args;
  }
}

TEST_F(CmdBake, BadImagesAreOneLineInputErrors) {
  // a colour image where one channel is expected
  Image colour(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) colour.at(x, y) = glm::vec4(x / 8.0f, y / 8.0f, 0.5f, 1.0f);
  ASSERT_TRUE(write_image(path("colour.png"), colour).ok());
  // an empty file (no image, 0 x 0) and one wider than the 16384 limit
  { std::ofstream(path("empty.png")); }
  ASSERT_TRUE(write_plane(path("huge.exr"), Plane(16385, 1)).ok());
  for (const char* in : {"colour.png", "empty.png", "huge.exr"}) {
    EXPECT_EQ(run(path(in) + " -o " + path("out.exr") + " --cone relaxed"), 1) << in;
    expect_one_line_error();
    EXPECT_FALSE(fs::exists(path("out.exr"))) << in;
  }
  EXPECT_NE(stderr_.find("limit"), std::string::npos) << stderr_;
  // grey stored as RGB is a depth map
  Image grey(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      grey.at(x, y) = glm::vec4((x + y) / 16.0f, (x + y) / 16.0f, (x + y) / 16.0f, 1.0f);
  ASSERT_TRUE(write_image(path("grey.png"), grey).ok());
  EXPECT_EQ(run(path("grey.png") + " -o " + path("out.exr") + " --cone relaxed"), 0) << stderr_;
}

TEST_F(CmdBake, UnwritableOutputIsInputError) {
  EXPECT_EQ(run(depth_ + " -o " + path("no_such_dir/out.exr") + " --cone conservative"), 1);
  expect_one_line_error();
  EXPECT_TRUE(only_inputs_left());
}

TEST_F(CmdBake, RelaxedExrMatchesLibrary) {
  ASSERT_EQ(run(depth_ + " -o " + path("cone.exr") + " --cone relaxed --wrap --threads 2"), 0)
      << stderr_;
  Result<Texture> depth = load_texture(depth_, {.first_channel_only = true});
  ASSERT_TRUE(depth.ok());
  ConeBakeOptions o;
  o.kind = ConeKind::kRelaxed;
  o.wrap = true;
  ConeRatios want = bake_cone_ratios(depth.value(), o);
  Result<Texture> got = load_texture(path("cone.exr"), {.first_channel_only = true});
  ASSERT_TRUE(got.ok()) << got.status().message();
  ASSERT_EQ(got->width(), 24);
  ASSERT_EQ(got->height(), 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x) EXPECT_EQ(got->fetch_r(0, x, y), want.at(x, y));
}

TEST_F(CmdBake, QuadPngStoresRoundedDownBytes) {
  ASSERT_EQ(run(depth_ + " -o " + path("quad.png") + " --cone quad"), 0) << stderr_;
  Result<Texture> depth = load_texture(depth_, {.first_channel_only = true});
  ConeBakeOptions o;
  o.kind = ConeKind::kQuad;
  ConeRatios want = bake_cone_ratios(depth.value(), o);
  Result<Texture> got = load_texture(path("quad.png"));  // linear: bytes as they are
  ASSERT_TRUE(got.ok()) << got.status().message();
  ASSERT_EQ(got->format(), TexFormat::kRGBA8);
  const MipLevel& l = got->level(0);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 24; ++x)
      for (int c = 0; c < 4; ++c)
        EXPECT_EQ(l.data[(y * 24 + x) * 4 + c],
                  static_cast<int>(std::floor(want.at(x, y, c) * 255.0f)));
}

TEST_F(CmdBake, NormalPngHasTheTextureBytes) {
  ASSERT_EQ(run(depth_ + " -o " + path("n.png") + " --normal --depth-scale 0.05"), 0) << stderr_;
  Result<Texture> depth = load_texture(depth_, {.first_channel_only = true});
  Texture want = normal_map_from_depth(depth.value(), 0.05f, false);
  Result<Texture> got = load_texture(path("n.png"));
  ASSERT_TRUE(got.ok()) << got.status().message();
  ASSERT_EQ(got->format(), TexFormat::kRGBA8);
  EXPECT_EQ(got->level(0).data, want.level(0).data);
}

TEST_F(CmdBake, NormalConventionDirectXFlipsGreen) {
  ASSERT_EQ(run(depth_ + " -o " + path("dx.png") + " --normal --normal-convention directx"), 0)
      << stderr_;
  Result<Texture> depth = load_texture(depth_, {.first_channel_only = true});
  const Texture want =
      normal_map_from_depth(depth.value(), 0.1f, false, NormalConvention::kDirectX);
  Result<Texture> got = load_texture(path("dx.png"));
  ASSERT_TRUE(got.ok()) << got.status().message();
  EXPECT_EQ(got->level(0).data, want.level(0).data);
  // the default is the glTF one, and the two differ (in green only)
  ASSERT_EQ(run(depth_ + " -o " + path("gl.png") + " --normal --normal-convention gltf"), 0);
  Result<Texture> gl = load_texture(path("gl.png"));
  ASSERT_TRUE(gl.ok());
  EXPECT_EQ(gl->level(0).data, normal_map_from_depth(depth.value(), 0.1f, false).level(0).data);
  EXPECT_NE(gl->level(0).data, got->level(0).data);
  EXPECT_EQ(run(depth_ + " -o " + path("c.exr") + " --cone relaxed --normal-convention directx"),
            2);
  expect_one_line_error();
  EXPECT_NE(stderr_.find("--normal-convention"), std::string::npos) << stderr_;
  EXPECT_EQ(run(depth_ + " -o " + path("x.png") + " --normal --normal-convention opengl"), 2);
}

TEST_F(CmdBake, HeightFlagInvertsTheInput) {
  // A height map h baked with --height equals the depth map 1 - h baked without it.
  Plane hmap(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) hmap.at(x, y) = (x * 7 + y * 3) % 8 / 8.0f;
  Plane dmap = hmap;
  for (float& v : dmap.values) v = 1.0f - v;
  ASSERT_TRUE(write_plane(path("h.exr"), hmap).ok());
  ASSERT_TRUE(write_plane(path("d.exr"), dmap).ok());
  ASSERT_EQ(run(path("h.exr") + " --height -o " + path("a.exr") + " --cone conservative"), 0);
  ASSERT_EQ(run(path("d.exr") + " -o " + path("b.exr") + " --cone conservative"), 0);
  Result<Texture> a = load_texture(path("a.exr")), b = load_texture(path("b.exr"));
  ASSERT_TRUE(a.ok() && b.ok());
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(a->fetch_r(0, x, y), b->fetch_r(0, x, y));
}

}  // namespace
}  // namespace relief
