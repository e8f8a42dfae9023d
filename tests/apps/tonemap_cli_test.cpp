// `relief render --tonemap` (apps/cmd_render.cpp, rasterizer/tone_map.h): the curve maps 8-bit
// outputs only, a glTF file defaults to pbr-neutral and a built-in scene to none.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "rasterizer/tone_map.h"
#include "scene/image_io.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

const std::string kGltf = std::string(RELIEF_SOURCE_DIR) + "/scenes/plane.gltf";
const std::string kSize = " --size 40x30 --threads 2 ";

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

Image read(const fs::path& p) {
  Result<Image> im = read_image(p.string());
  EXPECT_TRUE(im.ok()) << p << ": " << (im.ok() ? "" : im.status().message());
  return im.ok() ? *im : Image();
}

// Renders `scene ARGS -o DIR/NAME --stats DIR/NAME.json`; the statistics.
nlohmann::json render(const fs::path& dir, const std::string& scene, const std::string& args,
                      const std::string& name) {
  const CliRun r = run("render " + scene + kSize + args + " -o " + (dir / name).string() +
                       " --stats " + (dir / (name + ".json")).string());
  EXPECT_EQ(r.code, 0) << r.out;
  return nlohmann::json::parse(slurp(dir / (name + ".json")), nullptr, false);
}

double srgb(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

TEST(TonemapCli, BadValueIsOneUsageLineAndNoOutput) {
  const fs::path dir = test::fresh_test_dir("tonemap_bad");
  for (const char* bad : {"bogus", "ACES", "''"}) {
    const CliRun r = run("render plane --size 16x12 --tonemap " + std::string(bad) + " -o " +
                         (dir / "x.png").string());
    EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("--tonemap: expected none, aces or pbr-neutral"), std::string::npos)
        << r.out;
    EXPECT_TRUE(fs::is_empty(dir)) << bad;
  }
}

TEST(TonemapCli, GltfFileDefaultsToPbrNeutralBuiltinToNone) {
  const fs::path dir = test::fresh_test_dir("tonemap_default");
  const nlohmann::json file = render(dir, kGltf, "", "file.png");
  const nlohmann::json builtin = render(dir, "plane", "", "builtin.png");
  EXPECT_EQ(file["tonemap"], "pbr-neutral");
  EXPECT_EQ(file["tonemap_applied"], true);
  EXPECT_EQ(builtin["tonemap"], "none");
  EXPECT_EQ(builtin["tonemap_applied"], false);
  // scenes/plane.gltf is the built-in plane exported: with the same curve, the same bytes.
  render(dir, kGltf, "--tonemap none", "file_none.png");
  render(dir, "plane", "--tonemap pbr-neutral", "builtin_neutral.png");
  render(dir, "plane", "--tonemap none", "builtin_none.png");
  EXPECT_EQ(slurp(dir / "file_none.png"), slurp(dir / "builtin.png"));
  EXPECT_EQ(slurp(dir / "builtin_none.png"), slurp(dir / "builtin.png"));
  EXPECT_EQ(slurp(dir / "builtin_neutral.png"), slurp(dir / "file.png"));
  EXPECT_NE(slurp(dir / "file.png"), slurp(dir / "builtin.png"));
}

TEST(TonemapCli, PngIsTheCurveOfTheLinearFrameAndExrStaysLinear) {
  const fs::path dir = test::fresh_test_dir("tonemap_png");
  const nlohmann::json lin = render(dir, "plane", "--exposure 1.5", "lin.exr");
  const nlohmann::json aces_exr = render(dir, "plane", "--exposure 1.5 --tonemap aces", "a.exr");
  EXPECT_EQ(aces_exr["tonemap"], "aces");
  EXPECT_EQ(aces_exr["tonemap_applied"], false);
  const Image linear = read(dir / "lin.exr");
  EXPECT_EQ(read(dir / "a.exr").pixels, linear.pixels);  // .exr: --tonemap changes nothing

  for (ToneCurve curve : {ToneCurve::kAcesHill, ToneCurve::kPbrNeutral}) {
    const std::string name = std::string(tone_curve_name(curve)) + ".png";
    render(dir, "plane", std::string("--exposure 1.5 --tonemap ") + tone_curve_name(curve), name);
    const Image png = read(dir / name);
    ASSERT_EQ(png.pixels.size(), linear.pixels.size());
    size_t compressed = 0;  // pixels over 1 before the curve
    for (size_t i = 0; i < png.pixels.size(); ++i) {
      const glm::vec3 want = tone_map(curve, glm::vec3(linear.pixels[i]));  // opaque frame
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(srgb(png.pixels[i][c]), srgb(want[c]), 0.6 / 255.0) << name << " " << i;
      compressed += linear.pixels[i].r > 1.0f;
    }
    EXPECT_GT(compressed, 0u) << "the test frame should reach the shoulder";
  }
}

TEST(TonemapCli, ExplainSaysWhichCurveAndWhy) {
  const fs::path dir = test::fresh_test_dir("tonemap_explain");
  const std::string png = " -o " + (dir / "x.png").string(),
                    exr = " -o " + (dir / "x.exr").string();
  CliRun r = run("render " + kGltf + kSize + "--explain" + png);
  EXPECT_NE(r.out.find("tone curve pbr-neutral (the default for a glTF file"), std::string::npos)
      << r.out;
  r = run("render plane" + kSize + "--explain" + png);
  EXPECT_NE(r.out.find("tone curve none (the default for a built-in scene"), std::string::npos)
      << r.out;
  r = run("render plane" + kSize + "--explain --tonemap aces" + exr);
  EXPECT_NE(r.out.find("no tone curve: " + (dir / "x.exr").string() + " is a linear file"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("aces (asked by --tonemap) applies to 8-bit outputs only"),
            std::string::npos)
      << r.out;
}

}  // namespace
}  // namespace relief
