// `relief render FILE.gltf|.glb`, `--camera NAME|INDEX` and `relief export` as a user meets them:
// exit codes, one-line errors that name the file and JSON pointer, nothing written on failure.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int code = -1;
  std::string text;  // stdout and stderr
  int lines() const {
    int n = 0;
    for (char c : text) n += c == '\n';
    return n;
  }
};

Outcome relief(const std::string& args) {
  Outcome o;
  FILE* p = popen((std::string(RELIEF_CLI) + " " + args + " 2>&1").c_str(), "r");
  char buf[1024];
  while (p && fgets(buf, sizeof buf, p)) o.text += buf;
  const int status = p ? pclose(p) : -1;
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

class GltfCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(testing::TempDir()) /
        ("gltf_cli_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string at(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
  const std::string shipped_ = std::string(RELIEF_SOURCE_DIR) + "/scenes/plane.gltf";
};

TEST_F(GltfCli, RendersTheShippedSceneWithCameraByNameOrIndex) {
  const Outcome by_index =
      relief("render " + shipped_ + " --size 64x36 --camera 0 -o " + at("i.png"));
  ASSERT_EQ(by_index.code, 0) << by_index.text;
  const Outcome by_name =
      relief("render " + shipped_ + " --size 64x36 --camera 45deg -o " + at("n.png"));
  ASSERT_EQ(by_name.code, 0) << by_name.text;
  EXPECT_EQ(slurp(at("i.png")), slurp(at("n.png")));
  // The built-in plane's light direction differs by at most one float ulp; 8-bit output agrees
  // (with the tone curve a glTF file gets by default).
  ASSERT_EQ(relief("render plane --size 64x36 --tonemap pbr-neutral -o " + at("b.png")).code, 0);
  EXPECT_EQ(slurp(at("i.png")), slurp(at("b.png")));

  const Outcome bad =
      relief("render " + shipped_ + " --size 64x36 --camera side -o " + at("x.png"));
  EXPECT_EQ(bad.code, 2);
  EXPECT_EQ(bad.lines(), 1) << bad.text;
  EXPECT_NE(bad.text.find("no camera 'side' (cameras: 0 '45deg')"), std::string::npos) << bad.text;
  EXPECT_FALSE(fs::exists(at("x.png")));
  EXPECT_EQ(relief("render " + shipped_ + " --camera 1 -o " + at("x.png")).code, 2);
  EXPECT_FALSE(fs::exists(at("x.png")));
}

TEST_F(GltfCli, BadSceneIsOneLineNamingFileAndPointerAndWritesNothing) {
  for (const auto& e : fs::directory_iterator(fs::path(shipped_).parent_path()))
    if (e.path().stem().string().rfind("plane", 0) == 0)
      fs::copy_file(e.path(), dir_ / e.path().filename());
  nlohmann::json j = nlohmann::json::parse(slurp(at("plane.gltf")));
  j["materials"][0]["extensions"]["RELIEF_relief_mapping"]["steps"] = -4;
  std::ofstream(at("plane.gltf")) << j.dump();
  const std::string outputs =
      " -o " + at("out.png") + " --aov depth=" + at("d.exr") + " --stats " + at("s.json");
  const Outcome r = relief("render " + at("plane.gltf") + " --size 32x18" + outputs);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.lines(), 1) << r.text;
  EXPECT_NE(r.text.find(at("plane.gltf") +
                        ": /materials/0/extensions/RELIEF_relief_mapping/steps: -4 is outside"),
            std::string::npos)
      << r.text;
  for (const char* f : {"out.png", "d.exr", "s.json"}) EXPECT_FALSE(fs::exists(at(f))) << f;

  fs::remove(at("plane_bricks_depth.png"));  // a texture file gone
  j["materials"][0]["extensions"]["RELIEF_relief_mapping"].erase("steps");
  std::ofstream(at("plane.gltf")) << j.dump();
  const Outcome m = relief("render " + at("plane.gltf") + " --size 32x18" + outputs);
  EXPECT_EQ(m.code, 1);
  EXPECT_EQ(m.lines(), 1) << m.text;
  EXPECT_NE(m.text.find("/images/1/uri: "), std::string::npos) << m.text;
  EXPECT_NE(m.text.find("plane_bricks_depth.png: no such file"), std::string::npos) << m.text;
  for (const char* f : {"out.png", "d.exr", "s.json"}) EXPECT_FALSE(fs::exists(at(f))) << f;
}

TEST_F(GltfCli, ExportWritesGltfAndGlbThatRender) {
  const Outcome g = relief("export plane -o " + at("p.gltf"));
  ASSERT_EQ(g.code, 0) << g.text;
  for (const char* f : {"p.gltf", "p.bin", "p_bricks_base_color.png", "p_bricks_depth.png"})
    EXPECT_TRUE(fs::exists(at(f))) << f;
  ASSERT_EQ(relief("export plane -o " + at("p.glb")).code, 0);
  ASSERT_EQ(relief("render " + at("p.glb") + " --size 48x27 -o " + at("glb.png")).code, 0);
  ASSERT_EQ(relief("render plane --size 48x27 --tonemap pbr-neutral -o " + at("builtin.png")).code,
            0);
  EXPECT_EQ(slurp(at("glb.png")), slurp(at("builtin.png")));

  // A truncated .glb: one line, input error, no image.
  const std::string bytes = slurp(at("p.glb"));
  std::ofstream(at("cut.glb"), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const Outcome t = relief("render " + at("cut.glb") + " -o " + at("cut.png"));
  EXPECT_EQ(t.code, 1);
  EXPECT_EQ(t.lines(), 1) << t.text;
  EXPECT_NE(t.text.find(at("cut.glb") + ": truncated GLB"), std::string::npos) << t.text;
  EXPECT_FALSE(fs::exists(at("cut.png")));

  EXPECT_EQ(relief("export plane -o " + at("p.obj")).code, 2);
  EXPECT_EQ(relief("export no_such_scene -o " + at("q.gltf")).code, 1);
  EXPECT_FALSE(fs::exists(at("q.gltf")));
  EXPECT_EQ(relief("export plane -o " + at("no_dir/q.gltf")).code, 1);
}

}  // namespace
