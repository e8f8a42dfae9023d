#include "render/compare.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "scene/image_io.h"

namespace relief {
namespace {

TEST(Compare, IdenticalImagesHaveInfinitePsnr) {
  Image a(8, 4, glm::vec4(0.3f, 0.5f, 0.7f, 1.0f));
  const ImageDiff d = compare_images(a, a, 8.0f / 255.0f);
  EXPECT_EQ(d.rmse, 0.0);
  EXPECT_TRUE(std::isinf(d.psnr_db));
  EXPECT_EQ(d.max_error, 0.0);
  EXPECT_EQ(d.over_count, 0u);
  EXPECT_EQ(d.over_fraction, 0.0);
}

TEST(Compare, KnownLinearDifference) {
  // 4 pixels; one differs by 0.1 in R only: mse = 0.01 / 12.
  Image a(2, 2, glm::vec4(0.5f)), b = a;
  b.at(1, 0).r = 0.6f;
  const ImageDiff d = compare_images(a, b, 0.05f, DiffSpace::kLinear);
  EXPECT_NEAR(d.rmse, std::sqrt(0.01 / 12.0), 1e-7);
  EXPECT_NEAR(d.psnr_db, 10.0 * std::log10(12.0 / 0.01), 1e-4);
  EXPECT_NEAR(d.max_error, 0.1, 1e-6);
  EXPECT_EQ(d.max_x, 1);
  EXPECT_EQ(d.max_y, 0);
  EXPECT_EQ(d.over_count, 1u);
  EXPECT_DOUBLE_EQ(d.over_fraction, 0.25);
  // The threshold is strict: an error equal to it does not count.
  EXPECT_EQ(compare_images(a, b, 0.2f, DiffSpace::kLinear).over_count, 0u);
}

TEST(Compare, AlphaIsIgnored) {
  Image a(3, 3, glm::vec4(0.2f, 0.2f, 0.2f, 1.0f)), b = a;
  b.at(1, 1).a = 0.0f;
  EXPECT_EQ(compare_images(a, b).rmse, 0.0);
}

TEST(Compare, SrgbSpaceMeasuresDisplayCodeValues) {
  // Linear 0 vs the linear value whose sRGB code is 8/255: exactly eight code values apart.
  const float code = 8.0f / 255.0f;
  const float lin = code <= 0.04045f ? code / 12.92f : std::pow((code + 0.055f) / 1.055f, 2.4f);
  Image a(1, 1, glm::vec4(0, 0, 0, 1)), b(1, 1, glm::vec4(lin, 0, 0, 1));
  const ImageDiff d = compare_images(a, b, 7.5f / 255.0f);
  EXPECT_NEAR(d.max_error, code, 1e-6);
  EXPECT_EQ(d.over_count, 1u);
  // Values above 1 clamp in sRGB space but not in linear space.
  Image c(1, 1, glm::vec4(1, 1, 1, 1)), e(1, 1, glm::vec4(3, 3, 3, 1));
  EXPECT_EQ(compare_images(c, e).max_error, 0.0);
  EXPECT_NEAR(compare_images(c, e, 0.1f, DiffSpace::kLinear).max_error, 2.0, 1e-6);
}

TEST(Compare, NonFiniteIsTheWorstError) {
  Image a(2, 1, glm::vec4(0.5f)), b = a;
  b.at(0, 0).g = std::numeric_limits<float>::quiet_NaN();
  const ImageDiff d = compare_images(a, b, 0.5f, DiffSpace::kLinear);
  EXPECT_TRUE(std::isinf(d.max_error));
  EXPECT_EQ(d.over_count, 1u);
  EXPECT_EQ(d.psnr_db, -std::numeric_limits<double>::infinity());
}

TEST(Compare, HeatmapRamp) {
  Image a(4, 1, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f)), b = a;
  const float t = 0.1f;
  b.at(1, 0).r = 0.02f;  // 0.2 t: blue
  b.at(2, 0).r = 0.1f;   // t: green
  b.at(3, 0).r = 0.5f;   // 5 t: red
  const Image h = diff_heatmap(a, b, t, DiffSpace::kLinear);
  EXPECT_EQ(h.at(0, 0), glm::vec4(0, 0, 0, 1));
  EXPECT_GT(h.at(1, 0).b, 0.0f);
  EXPECT_EQ(h.at(1, 0).r, 0.0f);
  EXPECT_NEAR(h.at(2, 0).g, 1.0f, 1e-5f);
  EXPECT_EQ(h.at(3, 0), glm::vec4(1, 0, 0, 1));
}

// `relief compare`: exit 0 within bounds, 1 when a bound fails or the inputs are bad, 2 on usage.
int run_cli(const std::string& args) {
  const std::string cmd = std::string(RELIEF_CLI) + " " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Compare, CliExitCodes) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("relief_compare_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string a = (dir / "a.png").string(), b = (dir / "b.png").string();
  const std::string small = (dir / "small.png").string(), heat = (dir / "heat.png").string();
  Image ia(16, 8, glm::vec4(0.2f, 0.4f, 0.6f, 1.0f)), ib = ia;
  for (int x = 0; x < 16; ++x) ib.at(x, 0) = glm::vec4(1.0f, 0.0f, 0.0f, 1.0f);  // 1/8 of pixels
  ASSERT_TRUE(write_image(a, ia).ok());
  ASSERT_TRUE(write_image(b, ib).ok());
  ASSERT_TRUE(write_image(small, Image(4, 4, glm::vec4(0.5f))).ok());
  EXPECT_EQ(run_cli("compare " + a + " " + a + " --min-psnr 60 --max-rmse 0"), 0);
  EXPECT_EQ(run_cli("compare " + a + " " + b), 0);  // no bounds: report only
  EXPECT_EQ(run_cli("compare " + a + " " + b + " --min-psnr 35"), 1);
  EXPECT_EQ(run_cli("compare " + a + " " + b + " --max-rmse 0.01"), 1);
  EXPECT_EQ(run_cli("compare " + a + " " + b + " --max-over 0.1"), 1);
  EXPECT_EQ(run_cli("compare " + a + " " + b + " --max-over 0.2 --heatmap " + heat), 0);
  EXPECT_TRUE(fs::exists(heat));
  EXPECT_EQ(run_cli("compare " + a + " " + small), 1);  // different sizes: input error
  EXPECT_EQ(run_cli("compare " + a + " " + (dir / "missing.png").string()), 1);
  EXPECT_EQ(run_cli("compare " + a + " " + b + " --threshold -1"), 2);
  EXPECT_EQ(run_cli("compare " + a), 2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace relief
