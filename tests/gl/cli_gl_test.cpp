// The GL side of the CLI as a user meets it (issue 7): `relief info` lists backends and devices,
// `--gpu N` picks an EGL device (a missing one is a one-line error, no output file), a GL frame's
// statistics carry the GL_TIME_ELAPSED time of every pass (shadow passes included), the wall time
// after glFinish and the first-frame compile time apart, and a broken shader file is a one-line
// error naming the file and line.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/apps/cli_run.h"
#include "tests/gl/gl_test_util.h"

namespace {

namespace fs = std::filesystem;

TEST(GlCli, InfoListsBackendsAndDevices) {
  const CliRun r = run("info");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("cpu"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gl"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("EGL devices"), std::string::npos) << r.out;
}

TEST(GlCli, MissingGpuIsOneLineErrorAndNoFile) {
  const std::string png = tmp("gl_gpu.png");
  fs::remove(png);
  const CliRun r = run("render plane --backend gl --gpu 100000 --size 32x24 -o " + png);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_FALSE(fs::exists(png));
}

TEST(GlCli, StatsCarryGpuTimePerPassAndCompileTimeApart) {
  RELIEF_REQUIRE_GL();
  const std::string png = tmp("gl_room.png"), stats = tmp("gl_room.json");
  const CliRun r = run("render room --backend gl --size 96x72 --stats " + stats + " -o " + png);
  ASSERT_EQ(r.code, 0) << r.out;
  std::ifstream in(stats);
  const nlohmann::json j = nlohmann::json::parse(in);
  // The renderer string is printed and recorded.
  const std::string device = j.at("device");
  EXPECT_FALSE(device.empty());
  EXPECT_NE(r.out.find(device), std::string::npos) << r.out;
  // A fresh process compiles its programs: the first frame's compile time is reported apart.
  EXPECT_GT(j.at("compile_ms").get<double>(), 0.0);
  ASSERT_EQ(j.at("passes").size(), 2u);  // room: the spot light's shadow pass, then main
  EXPECT_EQ(j["passes"][0].at("kind"), "shadow");
  EXPECT_EQ(j["passes"][1].at("kind"), "main");
  for (const nlohmann::json& p : j["passes"]) {
    EXPECT_GT(p.at("ms").get<double>(), 0.0);
    // GL_TIME_ELAPSED in ms, or -1 where the driver's answer cannot be right (see gl_backend.h)
    const double gpu = p.at("gpu_ms").get<double>();
    EXPECT_TRUE(gpu == -1.0 || (gpu > 0.0 && gpu <= p.at("ms").get<double>() * 1.05 + 0.05)) << gpu;
  }
}

// --gl-interpolation (docs/gl-backend.md, "One frame"): gpu, the default, uploads each instance
// once and says so in --stats; cpu-planes uploads nothing to keep and spends geometry_ms on the
// planes every frame; anything else is a usage error with no output.
TEST(GlCli, GlInterpolationModesShowInStatsAndABadOneIsAUsageError) {
  RELIEF_REQUIRE_GL();
  for (const char* mode : {"gpu", "cpu-planes"}) {
    SCOPED_TRACE(mode);
    const std::string png = tmp(std::string("gl_interp_") + mode + ".png");
    const std::string stats = tmp(std::string("gl_interp_") + mode + ".json");
    const CliRun r = run(std::string("render room --backend gl --size 64x48 --gl-interpolation ") +
                         mode + " --stats " + stats + " -o " + png);
    ASSERT_EQ(r.code, 0) << r.out;
    std::ifstream in(stats);
    const nlohmann::json j = nlohmann::json::parse(in);
    const bool gpu = std::string(mode) == "gpu";
    EXPECT_EQ(j.at("geometry_prepared").get<int>() > 0, gpu);
    EXPECT_GT(j.at("geometry_ms").get<double>(), 0.0);
    EXPECT_GE(j.at("other_ms").get<double>(), -1e-3);
  }
  const std::string png = tmp("gl_interp_bad.png");
  fs::remove(png);
  const CliRun bad =
      run("render room --backend gl --size 64x48 --gl-interpolation linear -o " + png);
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_EQ(lines(bad.out), 1) << bad.out;
  EXPECT_NE(bad.out.find("--gl-interpolation"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(png));
  const CliRun bench = run("bench --backend cpu,gl --gl-interpolation linear --fields bricks");
  EXPECT_EQ(bench.code, 2) << bench.out;
  EXPECT_EQ(lines(bench.out), 1) << bench.out;
}

TEST(GlCli, BrokenShaderFileIsOneLineErrorWithFileAndLine) {
  RELIEF_REQUIRE_GL();
  // A shader folder searched first, holding a flat.frag with an error on line 3.
  const fs::path dir = fs::path(testing::TempDir()) / "gl_broken_shaders";
  fs::create_directories(dir);
  {
    std::ofstream f(dir / "flat.frag");
    f << "#version 450 core\n#include \"common.glsl\"\nvoid main() { undeclared_thing = 1.0; }\n";
  }
  const std::string png = tmp("gl_broken.png");
  fs::remove(png);
  const CliRun r = run_shell("RELIEF_GL_SHADER_DIR=" + dir.string() + " " + RELIEF_CLI +
                             " render plane --technique flat --backend gl --size 32x24 -o " + png);
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("flat.frag:3"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(png));
}

}  // namespace
