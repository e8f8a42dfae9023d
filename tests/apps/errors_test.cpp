// Errors as docs/errors.md lists them: one line naming the file, JSON pointer or parameter;
// usage errors (CLI11 parse errors included) exit 2, input errors 1; nothing is written on
// failure; out-of-memory-sized requests (a 100000 x 100000 target or texture) are refused from
// their size, never attempted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/apps/cli_run.h"
#include "tests/scene/png_header.h"

namespace {

namespace fs = std::filesystem;

// Expects `args` to fail with `code`, one line on stderr holding `expect`, and `output` absent.
void expect_error(const std::string& args, int code, const std::string& expect,
                  const std::string& output) {
  fs::remove(output);
  const CliRun r = run(args);
  EXPECT_EQ(r.code, code) << args << "\n" << r.out;
  EXPECT_EQ(lines(r.out), 1) << args << "\n" << r.out;
  EXPECT_EQ(r.out.rfind("relief: ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find(expect), std::string::npos) << args << "\n" << r.out;
  EXPECT_FALSE(fs::exists(output)) << args;
}

TEST(Errors, ParseErrorsAreUsageErrors) {
  const std::string png = tmp("err_parse.png");
  expect_error("render --threads abc -o " + png, 2, "--threads", png);
  expect_error("render --no-such-flag -o " + png, 2, "--no-such-flag", png);
  expect_error("render plane", 2, "--output", png);
  expect_error("no_such_command", 2, "no_such_command", png);
  expect_error("render --tile-size 7 -o " + png, 2, "--tile-size", png);
  expect_error("render --backend vulkan -o " + png, 2, "--backend", png);
  expect_error("render --aov bogus=x.exr -o " + png, 2, "bogus", png);
  expect_error("render --param depth_scale -o " + png, 2, "key=value", png);
}

TEST(Errors, ParameterLimitsNameTheParameterAndRange) {
  const std::string png = tmp("err_steps.png");
  expect_error("render --size 16x16 --technique relief --param steps=257 -o " + png, 2,
               "'steps': 257 is outside 1..256", png);
  expect_error("render --size 16x16 --technique relief --param steps=2.5 -o " + png, 2,
               "'steps': expected an integer in 1..256", png);
  expect_error("render --size 16x16 --technique relief --param depth_scale=1e300 -o " + png, 2,
               "'depth_scale': 1e300 is outside", png);
}

TEST(Errors, HugeTargetIsRefusedNotAttempted) {
  const std::string png = tmp("err_huge.png");
  expect_error("render --size 100000x100000 -o " + png, 2, "--size", png);
  expect_error("render --size 16384x16384 -o " + png, 2, "67108864 pixels", png);
}

// A glTF scene whose base colour texture claims 100000 x 100000 texels (a header-only PNG).
TEST(Errors, HugeTextureInGltfIsRefusedNamingTheFile) {
  const fs::path dir = tmp("err_gltf");
  fs::create_directories(dir);
  relief::testing::write_png_header_only((dir / "huge.png").string(), 100000, 100000);
  // one triangle: positions (0,0,0) (1,0,0) (0,1,0) as a data URI
  const std::string gltf = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
    "nodes":[{"mesh":0}],"meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
    "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
    "textures":[{"source":0}],"images":[{"uri":"huge.png"}],
    "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3",
                  "min":[0,0,0],"max":[1,1,0]}],
    "bufferViews":[{"buffer":0,"byteLength":36}],
    "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
  std::ofstream((dir / "huge.gltf").string()) << gltf;
  const std::string png = tmp("err_gltf.png");
  expect_error("render " + (dir / "huge.gltf").string() + " --size 16x16 -o " + png, 1,
               "huge.png: image is 100000x100000, larger than the limit of 16384", png);
}

TEST(Errors, InputErrorsExitOne) {
  const std::string png = tmp("err_input.png");
  expect_error("render " + tmp("no_such.gltf") + " -o " + png, 1, "no_such.gltf", png);
  const std::string bad = tmp("err_bad.gltf");
  std::ofstream(bad) << "{ not json";
  expect_error("render " + bad + " -o " + png, 1, "err_bad.gltf", png);
  expect_error("compare " + tmp("no_a.png") + " " + tmp("no_b.png"), 1, "no_a.png", png);
}

}  // namespace
