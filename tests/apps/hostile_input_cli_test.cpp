// Hostile input files through the CLI (issue 20; docs/errors.md "Only regular files", "The scene
// folder rule"): render (cpu and gl), export and bake refuse FIFOs, devices and URIs that leave
// the scene's folder with one short line and exit 1, and nothing blocks. Every command runs under
// `timeout 20`, so a regression that hangs fails (exit 124) instead of stalling the suite.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

CliRun relief_t(const std::string& args, const std::string& env = "") {
  return run_shell(env + (env.empty() ? "" : " ") + "timeout 20 " + std::string(RELIEF_CLI) + " " +
                   args);
}

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// Exit 1 and exactly one line, `relief: ...`, under 300 characters, holding `what`.
void expect_input_error(const CliRun& r, const std::string& what) {
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_EQ(r.out.rfind("relief: ", 0), 0u) << r.out;
  EXPECT_LT(r.out.size(), 300u) << r.out.substr(0, 400);
  EXPECT_NE(r.out.find(what), std::string::npos) << r.out.substr(0, 400);
}

// A side x side grey 8-bit PNG (side <= 64); bad_crc: its IDAT chunk has a wrong CRC, which
// libpng reports on stderr by itself.
void write_grey_png(const fs::path& p, int side, bool bad_crc) {
  auto be32 = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  auto crc = [](const std::string& b) {
    uint32_t c = 0xFFFFFFFFu;
    for (unsigned char x : b) {
      c ^= x;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return c ^ 0xFFFFFFFFu;
  };
  auto chunk = [&](const std::string& type, const std::string& data, bool bad) {
    return be32(static_cast<uint32_t>(data.size())) + type + data +
           be32(crc(type + data) ^ (bad ? 0x5a5a5a5au : 0u));
  };
  const std::string ihdr = be32(side) + be32(side) + std::string{8, 0, 0, 0, 0};
  std::string raw;
  for (int y = 0; y < side; ++y) raw += std::string(1, '\0') + std::string(side, '\x80');
  uint32_t a = 1, b = 0;  // adler32
  for (unsigned char x : raw) {
    a = (a + x) % 65521;
    b = (b + a) % 65521;
  }
  const uint16_t n = static_cast<uint16_t>(raw.size());
  std::string z = {
      '\x78', '\x01', '\x01', char(n & 255), char(n >> 8), char(~n & 255), char((~n >> 8) & 255)};
  z += raw + be32((b << 16) | a);
  std::ofstream(p, std::ios::binary) << "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr, false) +
                                            chunk("IDAT", z, bad_crc) + chunk("IEND", "", false);
}

class HostileCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = relief::test::fresh_test_dir("hostile_cli");
    scene_ = dir_ / "scene";
    fs::create_directories(scene_);
    const CliRun e = run("export plane -o " + q(scene_ / "p.gltf"));
    ASSERT_EQ(e.code, 0) << e.out;
    std::ifstream f(scene_ / "p.gltf");
    doc_ = json::parse(f);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const json& j) {
    std::ofstream(scene_ / name) << j.dump();
    return scene_ / name;
  }
  fs::path with_image_uri(const std::string& name, const std::string& uri, int image = 0) {
    json j = doc_;
    j["images"][image]["uri"] = uri;
    return write(name, j);
  }
  fs::path with_buffer_uri(const std::string& name, const std::string& uri) {
    json j = doc_;
    j["buffers"][0]["uri"] = uri;
    return write(name, j);
  }
  std::string render(const fs::path& scene, const std::string& extra = "") {
    return "render " + q(scene) + " -o " + q(dir_ / "out.png") + " --size 64x48 " + extra;
  }
  fs::path dir_, scene_;
  json doc_;
};

TEST_F(HostileCli, FifoImageUriIsRefused) {
  ASSERT_EQ(::mkfifo((scene_ / "fifo.png").c_str(), 0600), 0);
  const fs::path s = with_image_uri("f.gltf", "fifo.png");
  expect_input_error(relief_t(render(s)), "/images/0/uri: ");
  expect_input_error(relief_t(render(s)), "fifo.png: not a regular file (a FIFO)");
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
}

TEST_F(HostileCli, FifoImageUriIsRefusedOnTheGlBackend) {
  ASSERT_EQ(::mkfifo((scene_ / "fifo.png").c_str(), 0600), 0);
  expect_input_error(relief_t(render(with_image_uri("f.gltf", "fifo.png"), "--backend gl")),
                     "fifo.png: not a regular file (a FIFO)");
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
}

TEST_F(HostileCli, FifoBufferUriAndFifoSceneFileAreRefused) {
  ASSERT_EQ(::mkfifo((scene_ / "fifo.bin").c_str(), 0600), 0);
  expect_input_error(relief_t(render(with_buffer_uri("b.gltf", "fifo.bin"))),
                     "fifo.bin: not a regular file (a FIFO)");
  ASSERT_EQ(::mkfifo((scene_ / "s.gltf").c_str(), 0600), 0);
  expect_input_error(relief_t(render(scene_ / "s.gltf")), "s.gltf: not a regular file (a FIFO)");
  expect_input_error(relief_t("export " + q(scene_ / "s.gltf") + " -o " + q(dir_ / "e.gltf")),
                     "not a regular file (a FIFO)");
}

TEST_F(HostileCli, DeviceImagesAreRefused) {
  fs::create_symlink("/dev/zero", scene_ / "zero.png");
  fs::create_symlink("/dev/urandom", scene_ / "random.png");
  const fs::path z = with_image_uri("z.gltf", "zero.png");
  expect_input_error(relief_t(render(z)), "leads outside the scene's folder");
  expect_input_error(relief_t(render(z, "--allow-outside-scene-dir")),
                     "zero.png: not a regular file (a character device)");
  expect_input_error(
      relief_t(render(with_image_uri("r.gltf", "random.png", 1), "--allow-outside-scene-dir")),
      "random.png: not a regular file (a character device)");
}

TEST_F(HostileCli, DotDotUrisAreRefusedAndTheOptionAllowsThem) {
  fs::copy_file(scene_ / "p.bin", dir_ / "outside.bin");
  fs::copy_file(scene_ / "p_bricks_base_color.png", dir_ / "outside.png");
  const fs::path b = with_buffer_uri("b.gltf", "../outside.bin");
  const fs::path i = with_image_uri("i.gltf", "../outside.png");
  expect_input_error(relief_t(render(b)), "/buffers/0/uri: '../outside.bin': leads outside");
  expect_input_error(relief_t(render(i)), "/images/0/uri: '../outside.png': leads outside");
  const CliRun ok_b = relief_t(render(b, "--allow-outside-scene-dir"));
  EXPECT_EQ(ok_b.code, 0) << ok_b.out;
  const CliRun ok_i = relief_t(render(i, "--allow-outside-scene-dir"));
  EXPECT_EQ(ok_i.code, 0) << ok_i.out;
  const CliRun gl = relief_t(render(i, "--backend gl"));
  expect_input_error(gl, "leads outside the scene's folder");
}

TEST_F(HostileCli, ExportDoesNotCopyASystemFileIntoItsBin) {
  const fs::path s = with_buffer_uri("pw.gltf", "../../../../../../../../../etc/passwd");
  const CliRun r = relief_t("export " + q(s) + " -o " + q(dir_ / "e.gltf"));
  expect_input_error(r, "leads outside the scene's folder");
  EXPECT_FALSE(fs::exists(dir_ / "e.gltf"));
  EXPECT_FALSE(fs::exists(dir_ / "e.bin"));
  // With the option the size differs from byteLength, and the size of /etc/passwd is not told.
  const CliRun a =
      relief_t("export " + q(s) + " -o " + q(dir_ / "e.gltf") + " --allow-outside-scene-dir");
  expect_input_error(a, "file size differs from byteLength");
  EXPECT_EQ(a.out.find(std::to_string(fs::file_size("/etc/passwd")) + " bytes"), std::string::npos)
      << a.out;
  // And `../` with the option: export works.
  fs::copy_file(scene_ / "p.bin", dir_ / "outside.bin");
  const CliRun ok = relief_t("export " + q(with_buffer_uri("o.gltf", "../outside.bin")) + " -o " +
                             q(dir_ / "e.gltf") + " --allow-outside-scene-dir");
  EXPECT_EQ(ok.code, 0) << ok.out;
}

TEST_F(HostileCli, AbsoluteSchemePercentDirectoryAndControlUrisAreOneLine) {
  fs::copy_file(scene_ / "p_bricks_base_color.png", dir_ / "outside.png");
  fs::create_directories(scene_ / "sub");
  expect_input_error(relief_t(render(with_image_uri("a.gltf", "/etc/passwd"))),
                     "an absolute path (URIs are relative to the scene's folder");
  expect_input_error(relief_t(render(with_image_uri("f.gltf", "file:///etc/passwd"))),
                     "URI schemes are not allowed");
  expect_input_error(relief_t(render(with_buffer_uri("fb.gltf", "file:///etc/passwd"))),
                     "URI schemes are not allowed");
  expect_input_error(relief_t(render(with_image_uri("p.gltf", "%2e%2e/outside.png"))),
                     "leads outside the scene's folder");
  expect_input_error(relief_t(render(with_image_uri("d.gltf", "sub"))), "sub: is a directory");
  expect_input_error(relief_t(render(with_buffer_uri("db.gltf", "sub"))), "sub: is a directory");
  const CliRun nul = relief_t(render(with_image_uri("n.gltf", "a%00b.png")));
  expect_input_error(nul, "NUL or control character");
  const CliRun ctl = relief_t(render(with_image_uri("c.gltf", "a\x1b[2J\nb.png")));
  expect_input_error(ctl, "\\x1b[2J\\x0ab.png");
  EXPECT_EQ(ctl.out.find('\x1b'), std::string::npos);
  fs::create_symlink(dir_ / "outside.png", scene_ / "link.png");
  expect_input_error(relief_t(render(with_image_uri("l.gltf", "link.png"))),
                     "'link.png': leads outside the scene's folder");
}

TEST_F(HostileCli, DataUriWithWrongByteLengthIsOneShortLine) {
  const std::string uri = "data:application/octet-stream;base64," + std::string(1300000, 'A');
  const CliRun r = relief_t(render(with_buffer_uri("big.gltf", uri)));
  expect_input_error(r, "/buffers/0/uri: data URI holds 975000 bytes, byteLength is");
}

TEST_F(HostileCli, BakeRefusesDevicesAndFifos) {
  expect_input_error(relief_t("bake /dev/zero --normal -o " + q(dir_ / "n.png")),
                     "/dev/zero: not a regular file (a character device)");
  expect_input_error(relief_t("bake /dev/urandom --cone relaxed -o " + q(dir_ / "n.png")),
                     "/dev/urandom: not a regular file (a character device)");
  ASSERT_EQ(::mkfifo((dir_ / "fifo.png").c_str(), 0600), 0);
  expect_input_error(relief_t("bake " + q(dir_ / "fifo.png") + " --normal -o " + q(dir_ / "n.png")),
                     "fifo.png: not a regular file (a FIFO)");
  EXPECT_FALSE(fs::exists(dir_ / "n.png"));
  ASSERT_EQ(::mkfifo((dir_ / "mesh.gltf").c_str(), 0600), 0);
  expect_input_error(relief_t("bake --dual " + q(dir_ / "mesh.gltf") + " -o " + q(dir_ / "d")),
                     "mesh.gltf: not a regular file (a FIFO)");
}

TEST_F(HostileCli, CompareAndPluginRefuseFifos) {
  ASSERT_EQ(::mkfifo((dir_ / "a.png").c_str(), 0600), 0);
  expect_input_error(relief_t("compare " + q(dir_ / "a.png") + " " + q(dir_ / "a.png")),
                     "a.png: not a regular file (a FIFO)");
  expect_input_error(relief_t("compare /dev/zero /dev/zero"),
                     "/dev/zero: not a regular file (a character device)");
  ASSERT_EQ(::mkfifo((dir_ / "p.so").c_str(), 0600), 0);
  expect_input_error(relief_t("render plane --plugin " + q(dir_ / "p.so") + " -o " +
                              q(dir_ / "out.png") + " --size 8x8"),
                     "p.so: not a regular file (a FIFO)");
}

TEST_F(HostileCli, FifoInPlaceOfAConeMapCacheFileIsIgnored) {
  // A tiny depth map, so the cone map bakes in no time.
  write_grey_png(scene_ / "small.png", 8, false);
  const fs::path scene = with_image_uri("small.gltf", "small.png", 1);
  const fs::path cache = dir_ / "cache";
  fs::create_directories(cache);
  const std::string env = "RELIEF_CACHE_DIR=" + q(cache);
  const std::string args = render(scene, "--technique cone");
  const CliRun first = relief_t(args, env);
  ASSERT_EQ(first.code, 0) << first.out;
  int replaced = 0;
  for (const auto& e : fs::directory_iterator(cache)) {
    fs::remove(e.path());
    ASSERT_EQ(::mkfifo(e.path().c_str(), 0600), 0);
    ++replaced;
  }
  ASSERT_GT(replaced, 0);
  const CliRun second = relief_t(args, env);
  EXPECT_EQ(second.code, 0) << second.out;  // not 124: nothing waited on the FIFO
  EXPECT_NE(second.out.find("not a regular file (a FIFO), cone-map cache file ignored"),
            std::string::npos)
      << second.out;
}

TEST_F(HostileCli, LibpngMessagesDoNotReachStderr) {
  write_grey_png(dir_ / "crc.png", 4, true);
  const CliRun r = relief_t("bake " + q(dir_ / "crc.png") + " --normal -o " + q(dir_ / "n.png"));
  expect_input_error(r, "crc.png: cannot decode image: ");
  EXPECT_EQ(r.out.find("libpng"), std::string::npos) << r.out;
  // The same image as a scene texture.
  fs::copy_file(dir_ / "crc.png", scene_ / "crc.png");
  const CliRun s = relief_t(render(with_image_uri("c.gltf", "crc.png")));
  expect_input_error(s, "/images/0/uri: ");
  EXPECT_EQ(s.out.find("libpng"), std::string::npos) << s.out;
}

}  // namespace
