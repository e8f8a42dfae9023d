// `relief render --height-ao RAYS` (and --height-ao-radius, --height-ao-strength): height-field
// ambient occlusion over every relief material, said by --explain, its values checked (usage
// errors, exit 2), the image darker than without.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/apps/cli_run.h"

namespace {

// `relief render plane --explain FLAGS`: its output, after checking it succeeded.
std::string explain(const std::string& flags) {
  const CliRun r = run("render plane --size 64x48 --threads 2 --explain " + flags + " -o " +
                       tmp("hfao_explain.png"));
  EXPECT_EQ(r.code, 0) << flags << ": " << r.out;
  return r.out;
}

TEST(HeightAoCli, ExplainSaysOnAndWithWhat) {
  const std::string on = explain("--height-ao 8 --height-ao-radius 0.03 --height-ao-strength 0.5");
  EXPECT_NE(on.find("height_ao: on (8 rays x 4 steps, radius 0.03 uv, strength 0.5"),
            std::string::npos)
      << on;
  const std::string off = explain("");
  EXPECT_NE(off.find("height_ao: off (not asked by the material)"), std::string::npos) << off;
  const std::string quadric = explain("--height-ao 8 --technique relief_quadric");
  EXPECT_NE(quadric.find("height_ao: off (not supported by technique relief_quadric)"),
            std::string::npos)
      << quadric;
}

TEST(HeightAoCli, ValuesOutOfRangeAreUsageErrors) {
  for (const char* flags :
       {"--height-ao 17", "--height-ao -1", "--height-ao 8 --height-ao-radius 3",
        "--height-ao 8 --height-ao-strength 2"}) {
    const std::string png = tmp("hfao_bad.png");
    std::filesystem::remove(png);
    const CliRun r = run(std::string("render plane --size 64x48 ") + flags + " -o " + png);
    EXPECT_EQ(r.code, 2) << flags << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("--height-ao"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(png));
  }
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(HeightAoCli, OnChangesTheImage) {
  const std::string on = tmp("hfao_on.png"), off = tmp("hfao_off.png"), zero = tmp("hfao_0.png");
  ASSERT_EQ(run("render plane --size 96x64 --threads 2 --height-ao 8 -o " + on).code, 0);
  ASSERT_EQ(run("render plane --size 96x64 --threads 2 -o " + off).code, 0);
  ASSERT_EQ(run("render plane --size 96x64 --threads 2 --height-ao 0 -o " + zero).code, 0);
  EXPECT_NE(file_bytes(on), file_bytes(off));
  EXPECT_EQ(file_bytes(zero), file_bytes(off));
  EXPECT_FALSE(file_bytes(off).empty());
}

}  // namespace
