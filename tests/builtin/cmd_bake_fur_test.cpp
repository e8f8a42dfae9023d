// `relief bake --fur` end to end: the built CLI (RELIEF_CLI) writes the three maps of the field
// bake/fur_field.h makes, or one error line and nothing.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "bake/fur_field.h"
#include "scene/image_io.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

// Each test's own folder, removed after it; the files in it are what a run left behind.
class CmdBakeFur : public ::testing::Test {
 protected:
  ~CmdBakeFur() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  size_t files() const {
    return static_cast<size_t>(std::distance(fs::directory_iterator(dir_), {}));
  }
  const fs::path dir_ = test::fresh_test_dir("relief_cmd_bake_fur");
};

TEST_F(CmdBakeFur, WritesTheThreeMapsOfTheField) {
  const CliRun r = run("bake --fur grass -o " + path("g") + " --size 64 --seed 9 --jitter 0.2");
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* suffix : {"_depth.png", "_base_color.png", "_normal.png"})
    EXPECT_TRUE(fs::exists(path(std::string("g") + suffix))) << suffix;
  EXPECT_EQ(files(), 3u);

  FurFieldOptions o = fur_field_defaults(FurKind::kGrass);
  o.size = 64;
  o.seed = 9;
  o.jitter = 0.2f;
  const Result<FurField> want = make_fur_field(o);
  ASSERT_TRUE(want.ok());
  TextureLoadOptions lo;
  lo.first_channel_only = true;
  const Result<Texture> depth = load_texture(path("g_depth.png"), lo);
  ASSERT_TRUE(depth.ok()) << depth.status().message();
  ASSERT_EQ(depth->format(), TexFormat::kR16);  // 16-bit grey
  ASSERT_EQ(depth->width(0), 64);
  float worst = 0.0f;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      worst = std::max(worst, std::fabs(depth->fetch_r(0, x, y) - want->depth[y * 64 + x]));
  EXPECT_LE(worst, 0.5f / 65535.0f + 1e-7f);

  // The normal PNG holds the bytes of the wrapped normal map.
  const Result<Texture> normal = load_texture(path("g_normal.png"));
  ASSERT_TRUE(normal.ok()) << normal.status().message();
  const Texture n = fur_normal_texture(fur_depth_texture(*want), 0.06f);
  EXPECT_EQ(normal->level(0).data.size(), n.level(0).data.size());
  EXPECT_TRUE(normal->level(0).data == n.level(0).data);
}

TEST_F(CmdBakeFur, BadValuesAreOneLineErrorsAndWriteNothing) {
  const std::string out = " -o " + path("f");
  for (const std::string& args : {
           std::string("--fur cat") + out,               // unknown kind
           std::string("--fur fur --size 0") + out,      // size
           std::string("--fur fur --size 5000") + out,   //
           std::string("--fur fur --density -1") + out,  // density
           std::string("--fur fur --radius 0") + out,    // radius
           std::string("--fur fur --radius nan") + out,  //
           std::string("--fur fur --jitter 2") + out,    // jitter
           std::string("--fur fur --seed x") + out,      // seed
           std::string("--fur fur --seed -1") + out,     //
           std::string("--fur fur --seed 18446744073709551616") + out,
           std::string("--fur fur --depth-scale 0") + out,  // normal map scale
           std::string("--fur fur --normal") + out,         // another bake
           std::string("in.png --fur fur") + out,           // an input image
           std::string("--density 100") + out + ".png",     // --fur only
       }) {
    const CliRun r = run("bake " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.out;
    EXPECT_EQ(r.out.rfind("relief: ", 0), 0u) << args << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << args << ": " << r.out;
    EXPECT_EQ(files(), 0u) << args;
  }
  // an output folder that does not exist: an input error, before anything is made
  const CliRun r = run("bake --fur fur -o " + path("nodir/f"));
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_EQ(files(), 0u);
}

}  // namespace
}  // namespace relief
