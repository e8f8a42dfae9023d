// `relief bake --dual MESH.gltf -o PREFIX` end to end (dual-depth relief textures, Policarpo,
// Oliveira and Comba, I3D 2005, section 3.1): the CLI's four maps hold what bake_dual_depth
// computes from the loaded scene; errors are one line with nothing left behind.
#include <algorithm>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "bake/dual_depth_maps.h"
#include "builtin/builtin_curved.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

class DualBake : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_test_dir("relief_dual_bake");
    Result<Scene> s = make_curved_scene("sphere");
    ASSERT_TRUE(s.ok());
    mesh_ = path("sphere.gltf");
    ASSERT_TRUE(save_gltf(*s, mesh_).ok());
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_)) inputs_ += 1;
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  // `relief bake ARGS`: the exit code; what it printed (stdout and stderr) goes to out_.
  int bake(const std::string& args) {
    const CliRun r = run("bake " + args);
    out_ = r.out;
    return r.code;
  }
  int files() const {
    return static_cast<int>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  void expect_one_line_error() const {
    EXPECT_EQ(out_.rfind("relief: ", 0), 0u) << out_;
    EXPECT_EQ(lines(out_), 1) << out_;
  }

  fs::path dir_;
  std::string mesh_, out_;
  int inputs_ = 0;
};

TEST_F(DualBake, WritesTheLayersTheLibraryBakes) {
  ASSERT_EQ(bake("--dual " + mesh_ + " -o " + path("sph") + " --size 32 --threads 2"), 0) << out_;
  Result<Scene> s = load_scene(mesh_);
  ASSERT_TRUE(s.ok());
  const Mesh& m = s->meshes.at(0);
  const DualDepthMaps want = bake_dual_depth(m.positions, m.normals, m.indices, 32, 1.0f, 1);
  Result<Image> front = read_image(path("sph_front.exr"));
  Result<Image> back = read_image(path("sph_back.exr"));
  Result<Image> fn = read_image(path("sph_front_normal.exr"));
  Result<Image> bn = read_image(path("sph_back_normal.exr"));
  ASSERT_TRUE(front.ok() && back.ok() && fn.ok() && bn.ok());
  ASSERT_EQ(front->width, 32);
  int present = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const size_t i = static_cast<size_t>(y) * 32 + x;
      EXPECT_EQ(front->at(x, y).r, want.front[i]) << x << "," << y;
      EXPECT_EQ(back->at(x, y).r, want.back[i]) << x << "," << y;
      EXPECT_NEAR(fn->at(x, y).b, want.front_normal[i].z * 0.5f + 0.5f, 1e-6f);
      EXPECT_NEAR(bn->at(x, y).b, want.back_normal[i].z * 0.5f + 0.5f, 1e-6f);
      // green toward the image top (-v, world -y on the quad): the glTF convention
      EXPECT_NEAR(fn->at(x, y).g, -want.front_normal[i].y * 0.5f + 0.5f, 1e-6f);
      EXPECT_NEAR(bn->at(x, y).g, -want.back_normal[i].y * 0.5f + 0.5f, 1e-6f);
      present += want.front[i] <= want.back[i] ? 1 : 0;
    }
  EXPECT_GT(present, 32 * 32 / 2);  // the sphere fills most of its box
}

TEST_F(DualBake, ErrorsAreOneLineAndLeaveNothing) {
  EXPECT_EQ(bake("--dual " + path("nope.gltf") + " -o " + path("x")), 1);
  expect_one_line_error();
  EXPECT_EQ(bake("--dual " + mesh_ + " -o " + path("x") + " --size 0"), 2);
  expect_one_line_error();
  EXPECT_EQ(bake("--dual " + mesh_ + " -o " + path("x") + " --grow 0.5"), 2);
  expect_one_line_error();
  EXPECT_EQ(bake("--dual " + mesh_ + " -o " + path("no_dir/x")), 1);
  expect_one_line_error();
  EXPECT_EQ(files(), inputs_);
}

}  // namespace
}  // namespace relief
