// Depth maps hold [0, 1]. A float file with values outside it (one huge texel, NaN, negatives) is
// clamped at load with one warning that counts the texels, in `relief bake` and `relief render`
// alike, and no bake loop runs a step per unit of depth (issue 20, defect 3: an 8x8 EXR with one
// 1e30 texel made `bake --cone relaxed` loop for ever).
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake/cone_map.h"
#include "scene/image_io.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

struct CliResult {
  int code;
  std::string err;
};

// Runs `relief ARGS` under a 60 s timeout (a hang fails as exit 124), keeping stderr.
CliResult relief(const fs::path& dir, const std::string& args) {
  const std::string err = (dir / "stderr.txt").string();
  const std::string cmd =
      "timeout 60 " + std::string(RELIEF_CLI) + " " + args + " >/dev/null 2>" + err;
  const int rc = std::system(cmd.c_str());
  std::ifstream f(err);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

// Writes a one-channel float EXR as it is (write_plane writes non-finite values as 0).
bool write_raw_exr(const fs::path& path, const Plane& p) {
  auto out = OIIO::ImageOutput::create("openexr");
  OIIO::ImageSpec spec(p.width, p.height, 1, OIIO::TypeDesc::FLOAT);
  return out && out->open(path.string(), spec) &&
         out->write_image(OIIO::TypeDesc::FLOAT, p.values.data()) && out->close();
}

// An 8x8 depth map in [0, 1] with `bad` values planted at the first texels.
Plane field_with(std::initializer_list<float> bad) {
  Plane p(8, 8);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) p.at(x, y) = 0.1f * static_cast<float>((x + 2 * y) % 8);
  int i = 0;
  for (float v : bad) {
    p.at(3 + i % 4, 2 + i / 4) = v;
    ++i;
  }
  return p;
}

TEST(DepthRange, BakeRelaxedEndsOnAHugeTexel) {
  const fs::path dir = test::fresh_test_dir("relief_depth_range");
  ASSERT_TRUE(write_plane((dir / "d.exr").string(), field_with({1e30f})).ok());
  const CliResult r = relief(dir, "bake " + (dir / "d.exr").string() + " -o " +
                                      (dir / "cone.exr").string() + " --cone relaxed --threads 1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 of 64 depth texels"), std::string::npos) << r.err;
  Result<Texture> cone = load_texture((dir / "cone.exr").string());
  ASSERT_TRUE(cone.ok()) << cone.status().message();
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_TRUE(std::isfinite(cone->fetch_r(0, x, y)));
  fs::remove_all(dir);
}

TEST(DepthRange, BakeCountsEveryOutOfRangeTexelOnce) {
  const fs::path dir = test::fresh_test_dir("relief_depth_range");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  ASSERT_TRUE(write_raw_exr(dir / "d.exr", field_with({nan, -5.0f, inf, 1.5f})));
  for (const char* kind : {"relaxed", "conservative", "quad"}) {
    const CliResult r = relief(dir, "bake " + (dir / "d.exr").string() + " -o " +
                                        (dir / "cone.exr").string() + " --cone " + kind);
    ASSERT_EQ(r.code, 0) << kind << ": " << r.err;
    EXPECT_NE(r.err.find("4 of 64 depth texels"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;  // one warning line
  }
  fs::remove_all(dir);
}

TEST(DepthRange, InRangeFilesLoadWithoutWarning) {
  const fs::path dir = test::fresh_test_dir("relief_depth_range");
  ASSERT_TRUE(write_plane((dir / "d.exr").string(), field_with({0.0f, 1.0f})).ok());
  const CliResult r = relief(dir, "bake " + (dir / "d.exr").string() + " -o " +
                                      (dir / "cone.exr").string() + " --cone relaxed");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

TEST(DepthRange, LoaderClampsAndKeepsInRangeTexels) {
  const fs::path dir = test::fresh_test_dir("relief_depth_range");
  const Plane p = field_with({1e30f, -1e30f, std::numeric_limits<float>::quiet_NaN()});
  ASSERT_TRUE(write_raw_exr(dir / "d.exr", p));
  TextureLoadOptions lo;
  lo.first_channel_only = true;
  lo.unit_range = true;
  Result<Texture> t = load_texture((dir / "d.exr").string(), lo);
  ASSERT_TRUE(t.ok()) << t.status().message();
  EXPECT_EQ(t->fetch_r(0, 3, 2), 1.0f);
  EXPECT_EQ(t->fetch_r(0, 4, 2), 0.0f);
  EXPECT_EQ(t->fetch_r(0, 5, 2), 0.0f);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      if (y != 2 || x < 3 || x > 5) {
        EXPECT_EQ(t->fetch_r(0, x, y), p.at(x, y));
      }
  fs::remove_all(dir);
}

// A depth texture made in code (not through a loader) with a huge texel: the bakers clamp it
// themselves and give what the clamped map gives.
TEST(DepthRange, BakersClampATextureMadeInCode) {
  const Plane bad = field_with({1e30f, -3.0f});
  Plane good = bad;
  good.at(3, 2) = 1.0f;
  good.at(4, 2) = 0.0f;
  const auto tex = [](const Plane& p) {
    return Texture::from_floats(TexFormat::kR32F, p.width, p.height, p.values.data());
  };
  for (ConeKind kind : {ConeKind::kRelaxed, ConeKind::kConservative, ConeKind::kQuad}) {
    ConeBakeOptions o;
    o.kind = kind;
    o.threads = 1;
    const ConeRatios a = bake_cone_ratios(tex(bad), o);
    const ConeRatios b = bake_cone_ratios(tex(good), o);
    ASSERT_EQ(a.values.size(), b.values.size());
    for (size_t i = 0; i < a.values.size(); ++i)
      EXPECT_EQ(a.values[i], b.values[i]) << cone_kind_name(kind) << " " << i;
  }
}

// The render path reads the depth map through the same clamp: a glTF whose relief material's
// depth map is that EXR renders (exit 0, one warning) instead of hanging or writing NaN.
TEST(DepthRange, RenderOfAGltfWithAHugeDepthTexel) {
  const fs::path dir = test::fresh_test_dir("relief_depth_range");
  const fs::path scene = dir / "plane.gltf";
  CliResult r = relief(dir, "export plane -o " + scene.string());
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_TRUE(write_plane((dir / "d.exr").string(), field_with({1e30f, -1.0f})).ok());
  nlohmann::json doc;
  std::ifstream(scene) >> doc;
  bool replaced = false;
  for (auto& img : doc["images"])
    if (img["uri"].get<std::string>().find("depth") != std::string::npos) {
      img["uri"] = "d.exr";
      replaced = true;
    }
  ASSERT_TRUE(replaced);
  std::ofstream(scene) << doc.dump();
  for (const char* technique : {"relief", "relaxed_cone", "cone", "exact"}) {
    r = relief(dir, "render " + scene.string() + " --size 64x48 --technique " + technique + " -o " +
                        (dir / "out.exr").string());
    ASSERT_EQ(r.code, 0) << technique << ": " << r.err;
    EXPECT_NE(r.err.find("2 of 64 depth texels"), std::string::npos) << r.err;
    Result<Image> img = read_image((dir / "out.exr").string());
    ASSERT_TRUE(img.ok());
    for (const auto& px : img->pixels)
      ASSERT_TRUE(std::isfinite(px.r) && std::isfinite(px.g) && std::isfinite(px.b));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace relief
