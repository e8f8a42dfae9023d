// The CLI as a user meets it: exit codes, one-line errors, no partial output.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/apps/cli_run.h"

namespace {

TEST(Cli, RenderWritesPngAndStats) {
  const std::string png = tmp("cli_ok.png"), stats = tmp("cli_ok.json");
  std::filesystem::remove(png);
  const CliRun r = run("render plane --size 64x48 --threads 2 -o " + png + " --stats " + stats);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(std::filesystem::exists(png));
  EXPECT_TRUE(std::filesystem::exists(stats));
  EXPECT_NE(r.out.find(png), std::string::npos);  // prints the path and the time
  EXPECT_NE(r.out.find("ms"), std::string::npos);
}

TEST(Cli, UnknownSceneIsOneLineInputError) {
  const std::string png = tmp("cli_scene.png");
  std::filesystem::remove(png);  // a leftover of an earlier run would pass for output
  const CliRun r = run("render no_such_scene -o " + png);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("no_such_scene"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(png));
}

TEST(Cli, BadSizeIsOneLineUsageError) {
  const std::string png = tmp("cli_size.png");
  std::filesystem::remove(png);  // a leftover of an earlier run would pass for output
  for (const char* size : {"0x10", "800", "100000x100000", "20000x10", "axb"}) {
    const CliRun r = run(std::string("render --size ") + size + " -o " + png);
    EXPECT_EQ(r.code, 2) << size << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("--size"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(png));
  }
}

TEST(Cli, UnknownParameterNamesIt) {
  const std::string png = tmp("cli_param.png");
  std::filesystem::remove(png);  // a leftover of an earlier run would pass for output
  const CliRun r = run("render --size 32x32 --param no_such_param=3 -o " + png);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("no_such_param"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(png));
}

TEST(Cli, UnknownTechniqueIsUsageError) {
  const CliRun r = run("render --size 32x32 --technique nope -o " + tmp("cli_tech.png"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
}

TEST(Cli, UnwritableOutputLeavesNothing) {
  const std::string dir = tmp("cli_no_such_dir");
  std::filesystem::remove_all(dir);
  const CliRun r = run("render --size 32x32 -o " + dir + "/x.png");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir));
  // An AOV that cannot be written: the main image must not appear either.
  const std::string png = tmp("cli_partial.png");
  std::filesystem::remove(png);
  const CliRun r2 = run("render --size 32x32 -o " + png + " --aov depth=" + dir + "/d.exr");
  EXPECT_NE(r2.code, 0);
  EXPECT_FALSE(std::filesystem::exists(png)) << r2.out;
}

TEST(Cli, ListsTechniquesAndScenes) {
  const CliRun t = run("techniques");
  EXPECT_EQ(t.code, 0);
  EXPECT_NE(t.out.find("normal:"), std::string::npos);
  EXPECT_NE(t.out.find("normal_strength"), std::string::npos);
  const CliRun s = run("scenes");
  EXPECT_EQ(s.code, 0);
  EXPECT_NE(s.out.find("plane"), std::string::npos);
  EXPECT_EQ(run("render --help").code, 0);
  EXPECT_EQ(run("").code, 2);
}

}  // namespace
