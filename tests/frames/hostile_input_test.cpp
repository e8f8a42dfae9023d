// Hostile input files (issue 20, docs/errors.md "Only regular files", "The scene folder rule"):
// special files are refused before anything reads them, URIs stay in the scene's folder, every
// message is one short line, and image sizes are checked from the header. Each test arms an
// alarm, so a regression that blocks (a FIFO opened for reading) fails instead of hanging.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "builtin/builtin.h"
#include "rasterizer/safe_file.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"
#include "tests/scene/png_header.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// Kills the test process after 20 s (SIGALRM's default action), so a hang is a failure.
struct Alarm {
  Alarm() { ::alarm(20); }
  ~Alarm() { ::alarm(0); }
};

// Load options that let URIs lead outside the scene's folder (`--allow-outside-scene-dir`).
GltfLoadOptions outside_allowed() {
  GltfLoadOptions o;
  o.allow_outside_scene_dir = true;
  return o;
}

void expect_one_line(const std::string& m) {
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_EQ(m.find('\r'), std::string::npos) << m;
  EXPECT_LT(m.size(), 300u) << m;
}

// A scene folder with the built-in plane saved as p.gltf (p.bin, two PNGs), and helpers that
// write variants of its JSON.
class Hostile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_test_dir("hostile");
    scene_ = dir_ / "scene";
    fs::create_directories(scene_);
    Result<Scene> s = make_builtin_scene("plane");
    ASSERT_TRUE(s.ok()) << s.status().message();
    ASSERT_TRUE(save_gltf(*s, (scene_ / "p.gltf").string()).ok());
    std::ifstream f(scene_ / "p.gltf");
    doc_ = json::parse(f);
    ASSERT_TRUE(doc_["buffers"].is_array());
    ASSERT_GE(doc_["images"].size(), 1u);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string write(const std::string& name, const json& j) {
    const fs::path p = scene_ / name;
    std::ofstream(p) << j.dump();
    return p.string();
  }
  std::string with_image_uri(const std::string& name, const std::string& uri) {
    json j = doc_;
    j["images"][0]["uri"] = uri;
    return write(name, j);
  }
  std::string with_buffer_uri(const std::string& name, const std::string& uri) {
    json j = doc_;
    j["buffers"][0]["uri"] = uri;
    return write(name, j);
  }
  // load_gltf fails with one line that holds `what`.
  std::string expect_refused(const std::string& path, const std::string& what,
                             const GltfLoadOptions& o = {}) {
    Alarm alarm;
    Result<Scene> s = load_scene(path, o);
    EXPECT_FALSE(s.ok()) << path;
    if (s.ok()) return "";
    const std::string& m = s.status().message();
    expect_one_line(m);
    EXPECT_EQ(m.rfind(path, 0), 0u) << m;  // starts with the file
    EXPECT_NE(m.find(what), std::string::npos) << m;
    EXPECT_EQ(s.status().exit_code(), 1);
    return m;
  }
  fs::path dir_, scene_;
  json doc_;
};

TEST(HostileSafeFile, PrintableEscapesControlBytesAndShortens) {
  EXPECT_EQ(printable("a\nb\x01\\c"), "a\\x0ab\\x01\\x5cc");
  EXPECT_EQ(printable(std::string("a\0b", 3)), "a\\x00b");
  EXPECT_EQ(printable(std::string(100, 'x'), 60), std::string(60, 'x') + "...");
  EXPECT_EQ(printable("h\xc3\xa9"), "h\xc3\xa9");  // UTF-8 is left alone
}

TEST(HostileSafeFile, FifoIsRefusedWithoutBlocking) {
  Alarm alarm;
  const fs::path dir = test::fresh_test_dir("hostile_fifo");
  const std::string fifo = (dir / "f.png").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  Result<std::string> r = read_regular_file(fifo);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(), fifo + ": not a regular file (a FIFO)");
  fs::remove_all(dir);
}

TEST(HostileSafeFile, DevicesDirectoriesAndMissingFilesAreRefused) {
  Alarm alarm;
  for (const char* dev : {"/dev/zero", "/dev/urandom", "/dev/null"}) {
    Result<std::string> r = read_regular_file(dev);
    ASSERT_FALSE(r.ok()) << dev;
    EXPECT_EQ(r.status().message(), std::string(dev) + ": not a regular file (a character device)");
  }
  const fs::path dir = test::fresh_test_dir("hostile_dev");
  EXPECT_EQ(read_regular_file(dir.string()).status().message(), dir.string() + ": is a directory");
  EXPECT_EQ(read_regular_file((dir / "none").string()).status().message(),
            (dir / "none").string() + ": no such file");
  std::ofstream(dir / "ok.bin") << "abc";
  Result<std::string> ok = read_regular_file((dir / "ok.bin").string());
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(*ok, "abc");
  // The documented size cap is checked from fstat, before reading.
  Result<std::string> capped = read_regular_file((dir / "ok.bin").string(), 2);
  ASSERT_FALSE(capped.ok());
  EXPECT_NE(capped.status().message().find("more than the limit of 2 bytes"), std::string::npos);
  fs::remove_all(dir);
}

TEST(HostileSafeFile, UriRulesRefuseSchemesAbsolutePathsControlBytesAndLeaving) {
  const fs::path dir = test::fresh_test_dir("hostile_uri");
  const SceneFolder folder{dir.string(), false};
  auto refused = [&](const std::string& uri, const std::string& what) {
    Result<ResolvedUri> r = resolve_scene_uri(folder, uri);
    ASSERT_FALSE(r.ok()) << uri;
    expect_one_line(r.status().message());
    EXPECT_NE(r.status().message().find(what), std::string::npos) << r.status().message();
  };
  refused("file:///etc/passwd", "URI schemes are not allowed");
  refused("http://example.com/a.png", "URI schemes are not allowed");
  refused("/etc/passwd", "an absolute path (URIs are relative to the scene's folder");
  refused("%2fetc/passwd", "an absolute path (URIs are relative to the scene's folder");
  refused("../x.png", "leads outside the scene's folder");
  refused("%2e%2e/x.png", "leads outside the scene's folder");
  refused("%2E%2E%2Fx.png", "leads outside the scene's folder");
  refused("a/../../x.png", "leads outside the scene's folder");
  refused("a%00b.png", "NUL or control character");
  refused("a%0ab.png", "NUL or control character");
  refused(std::string("a\x01.png"), "NUL or control character");
  refused("a%zz.png", "bad percent escape");
  refused("", "empty URI");
  refused(std::string(5000, 'a') + "%00", "NUL or control character");
  EXPECT_TRUE(resolve_scene_uri(folder, "sub/../x.png").ok());
  EXPECT_TRUE(resolve_scene_uri(folder, "x%20y.png").ok());
  EXPECT_TRUE(resolve_scene_uri({dir.string(), true}, "../x.png").ok());
  // A folder name that is a prefix of a sibling's is no way out ("/a/scene" vs "/a/scene2").
  fs::create_directories(dir.string() + "2");
  refused("../" + dir.filename().string() + "2/x.png", "leads outside the scene's folder");
  fs::remove_all(dir.string() + "2");
  fs::remove_all(dir);
}

TEST_F(Hostile, FifoImageUriIsRefused) {
  ASSERT_EQ(::mkfifo((scene_ / "fifo.png").c_str(), 0600), 0);
  expect_refused(with_image_uri("f.gltf", "fifo.png"), "fifo.png: not a regular file (a FIFO)");
}

TEST_F(Hostile, FifoBufferUriIsRefused) {
  ASSERT_EQ(::mkfifo((scene_ / "fifo.bin").c_str(), 0600), 0);
  const std::string m = expect_refused(with_buffer_uri("f.gltf", "fifo.bin"), "/buffers/0/uri: ");
  EXPECT_NE(m.find("fifo.bin: not a regular file (a FIFO)"), std::string::npos) << m;
}

TEST_F(Hostile, FifoSceneFileIsRefused) {
  const std::string path = (scene_ / "f.gltf").string();
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  expect_refused(path, "not a regular file (a FIFO)");
}

TEST_F(Hostile, DeviceImageUriIsRefused) {
  fs::create_symlink("/dev/zero", scene_ / "zero.png");
  fs::create_symlink("/dev/urandom", scene_ / "random.png");
  // Inside the folder by name, outside by target: the folder rule refuses it first...
  expect_refused(with_image_uri("z.gltf", "zero.png"), "leads outside the scene's folder");
  // ...and with the rule lifted, the regular-file rule does.
  expect_refused(with_image_uri("z.gltf", "zero.png"), "not a regular file (a character device)",
                 outside_allowed());
  expect_refused(with_image_uri("r.gltf", "random.png"), "not a regular file (a character device)",
                 outside_allowed());
  expect_refused(with_buffer_uri("b.gltf", "zero.png"), "not a regular file (a character device)",
                 outside_allowed());
}

TEST_F(Hostile, DotDotBufferUriIsRefusedAndAllowedByTheOption) {
  fs::copy_file(scene_ / "p.bin", dir_ / "outside.bin");
  const std::string path = with_buffer_uri("d.gltf", "../outside.bin");
  expect_refused(path, "/buffers/0/uri: '../outside.bin': leads outside the scene's folder");
  Result<Scene> s = load_scene(path, outside_allowed());
  EXPECT_TRUE(s.ok()) << s.status().message();
}

TEST_F(Hostile, SystemFileAsBufferIsRefusedAndItsSizeNotPrinted) {
  const std::string path = with_buffer_uri("pw.gltf", "../../../../../../../../etc/passwd");
  expect_refused(path, "leads outside the scene's folder");
  // Allowed outside: the size differs, and the size of a file outside the folder is not told.
  const std::string m =
      expect_refused(path, "file size differs from byteLength", outside_allowed());
  const std::string size = std::to_string(fs::file_size("/etc/passwd"));
  EXPECT_EQ(m.find(" " + size + " "), std::string::npos) << m;
}

TEST_F(Hostile, WrongByteLengthInsideTheFolderSaysBothSizes) {
  json j = doc_;
  const unsigned long long n = j["buffers"][0]["byteLength"].get<unsigned long long>();
  j["buffers"][0]["byteLength"] = n - 8;
  expect_refused(write("l.gltf", j),
                 "file is " + std::to_string(n) + " bytes, byteLength is " + std::to_string(n - 8));
}

TEST_F(Hostile, DotDotImageUriIsRefusedAndAllowedByTheOption) {
  fs::copy_file(scene_ / "p_bricks_base_color.png", dir_ / "outside.png");
  const std::string path = with_image_uri("d.gltf", "../outside.png");
  expect_refused(path, "/images/0/uri: '../outside.png': leads outside the scene's folder");
  Result<Scene> s = load_scene(path, outside_allowed());
  EXPECT_TRUE(s.ok()) << s.status().message();
}

TEST_F(Hostile, PercentEncodedDotDotImageUriIsRefused) {
  fs::copy_file(scene_ / "p_bricks_base_color.png", dir_ / "outside.png");
  expect_refused(with_image_uri("d.gltf", "%2e%2e/outside.png"),
                 "leads outside the scene's folder");
  expect_refused(with_image_uri("d.gltf", "%2E%2E%2Foutside.png"),
                 "leads outside the scene's folder");
}

TEST_F(Hostile, AbsoluteImageUriIsRefusedAndAllowedByTheOption) {
  const std::string abs = (scene_ / "p_bricks_base_color.png").string();
  Result<Scene> s = load_scene(with_image_uri("ok.gltf", abs), outside_allowed());
  EXPECT_TRUE(s.ok()) << s.status().message();
  // Allowed outside, an absolute path still opens only regular files.
  expect_refused(with_image_uri("z.gltf", "/dev/zero"), "not a regular file (a character device)",
                 outside_allowed());
  expect_refused(with_image_uri("a.gltf", abs),
                 "an absolute path (URIs are relative to the scene's folder");
  expect_refused(with_image_uri("a.gltf", "/etc/passwd"),
                 "an absolute path (URIs are relative to the scene's folder");
  expect_refused(with_buffer_uri("b.gltf", "/etc/passwd"),
                 "an absolute path (URIs are relative to the scene's folder");
}

TEST_F(Hostile, FileSchemeUriIsRefused) {
  expect_refused(with_image_uri("s.gltf", "file:///etc/passwd"), "URI schemes are not allowed");
  expect_refused(with_buffer_uri("s.gltf", "file:///etc/passwd"), "URI schemes are not allowed");
  expect_refused(with_image_uri("s.gltf", "https://example.com/x.png"),
                 "URI schemes are not allowed");
}

TEST_F(Hostile, SymlinkInsideTheFolderPointingOutsideIsRefused) {
  fs::copy_file(scene_ / "p_bricks_base_color.png", dir_ / "outside.png");
  fs::create_symlink(dir_ / "outside.png", scene_ / "link.png");
  fs::create_directory_symlink(dir_, scene_ / "up");
  expect_refused(with_image_uri("l.gltf", "link.png"), "leads outside the scene's folder");
  expect_refused(with_image_uri("l.gltf", "up/outside.png"), "leads outside the scene's folder");
  // A symlink that stays inside is fine.
  fs::create_symlink("p_bricks_base_color.png", scene_ / "inner.png");
  Result<Scene> s = load_scene(with_image_uri("i.gltf", "inner.png"));
  EXPECT_TRUE(s.ok()) << s.status().message();
}

TEST_F(Hostile, DirectoryUriIsADirectory) {
  fs::create_directories(scene_ / "sub");
  expect_refused(with_image_uri("d.gltf", "sub"), "sub: is a directory");
  expect_refused(with_buffer_uri("d.gltf", "sub"), "sub: is a directory");
  expect_refused(with_image_uri("d.gltf", "."), "is a directory");
}

TEST_F(Hostile, DataUriWithWrongByteLengthIsOneShortLine) {
  // 1.3 MB of base64 that is not byteLength bytes: the message must not echo the URI.
  std::string uri = "data:application/octet-stream;base64,";
  uri.append(1300000, 'A');  // (operator+ on a temporary trips GCC 12's -Warray-bounds)
  const std::string m = expect_refused(with_buffer_uri("big.gltf", uri),
                                       "/buffers/0/uri: data URI holds 975000 bytes, byteLength");
  EXPECT_EQ(m.find("AAAAAAAA"), std::string::npos) << m.substr(0, 400);
  expect_refused(with_buffer_uri("b64.gltf", "data:application/octet-stream;base64,!!!!"),
                 "data URI is not valid base64");
}

TEST_F(Hostile, NulAndControlCharactersInUrisAreRefusedAndEscaped) {
  std::string m = expect_refused(with_image_uri("n.gltf", "a%00b.png"), "NUL or control character");
  EXPECT_NE(m.find("a%00b.png"), std::string::npos) << m;
  m = expect_refused(with_image_uri("c.gltf", std::string("a\x01\nb\x1b[31m.png")),
                     "NUL or control character");
  EXPECT_NE(m.find("\\x01\\x0ab\\x1b[31m"), std::string::npos) << m;
  expect_refused(with_buffer_uri("c.gltf", "p%0a.bin"), "NUL or control character");
  // A long URI is shortened in the message.
  m = expect_refused(with_image_uri("long.gltf", std::string(4000, 'x') + "%01"),
                     "NUL or control character");
}

TEST_F(Hostile, EmbeddedImagesDecodeWithoutATemporaryFile) {
  // A data: URI image decodes from memory; its errors name no temporary file.
  json j = doc_;
  j["images"][0] = {{"uri", "data:image/png;base64,iVBORw0KGgoAAAAN"}};
  const std::string m = expect_refused(write("e.gltf", j), "/images/0/uri: ");
  EXPECT_EQ(m.find("relief_gltf_"), std::string::npos) << m;
  EXPECT_NE(m.find("embedded image: cannot read image"), std::string::npos) << m;
}

// The GLB's own JSON chunk goes through the same buffer checks as a .gltf.
TEST_F(Hostile, GlbExternalBufferFollowsTheSameRules) {
  Result<Scene> s = make_builtin_scene("plane");
  ASSERT_TRUE(s.ok());
  const fs::path glb = scene_ / "g.glb";
  ASSERT_TRUE(save_gltf(*s, glb.string()).ok());
  std::ifstream in(glb, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  uint32_t json_len = 0;
  std::memcpy(&json_len, bytes.data() + 12, 4);
  json j = json::parse(bytes.substr(20, json_len));
  auto write_glb = [&](const std::string& name, const std::string& uri) {
    json k = j;
    k["buffers"].push_back({{"uri", uri}, {"byteLength", 4}});
    std::string text = k.dump();
    text.append((4 - text.size() % 4) % 4, ' ');
    std::string out = bytes.substr(0, 12);
    const uint32_t len = static_cast<uint32_t>(text.size()), type = 0x4E4F534Au;
    out.append(reinterpret_cast<const char*>(&len), 4);
    out.append(reinterpret_cast<const char*>(&type), 4);
    out += text + bytes.substr(20 + json_len);
    const uint32_t total = static_cast<uint32_t>(out.size());
    std::memcpy(out.data() + 8, &total, 4);
    std::ofstream(scene_ / name, std::ios::binary) << out;
    return (scene_ / name).string();
  };
  ASSERT_EQ(::mkfifo((scene_ / "fifo.bin").c_str(), 0600), 0);
  expect_refused(write_glb("f.glb", "fifo.bin"), "/buffers/1/uri: ");
  expect_refused(write_glb("f.glb", "fifo.bin"), "fifo.bin: not a regular file (a FIFO)");
  expect_refused(write_glb("d.glb", "../x.bin"), "'../x.bin': leads outside the scene's folder");
  expect_refused(write_glb("a.glb", "file:///etc/passwd"), "URI schemes are not allowed");
}

TEST(HostileImage, TexelLimitHoldsAtAndAboveTheDocumentedNumber) {
  Alarm alarm;
  const fs::path dir = test::fresh_test_dir("hostile_limit");
  EXPECT_EQ(kMaxTextureTexels, 16LL * 1024 * 1024);
  // At the limit the size check passes (the header-only file then fails on its missing pixels).
  const std::string at = (dir / "at.png").string();
  testing::write_png_header_only(at, 4096, 4096);
  Result<Texture> t = load_texture(at);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().message().find("than the limit"), std::string::npos) << t.status().message();
  // One row more: refused from the header, before any pixel memory.
  const std::string above = (dir / "above.png").string();
  testing::write_png_header_only(above, 4096, 4097);
  t = load_texture(above);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.status().message(),
            above + ": image is 4096x4097, more than the limit of 16777216 texels for a texture");
  // A 65 KB PNG that expands to 8192 x 8192 is refused at once as a texture.
  testing::write_png_header_only(above, 8192, 8192);
  t = load_texture(above);
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.status().message().find("more than the limit of 16777216 texels"), std::string::npos);
  // read_image (relief compare) keeps the render-sized limit.
  Result<Image> im = read_image(above);
  ASSERT_FALSE(im.ok());
  EXPECT_EQ(im.status().message().find("than the limit"), std::string::npos)
      << im.status().message();
  fs::remove_all(dir);
}

TEST(HostileImage, GarbageAndTruncatedImagesAreOneLine) {
  Alarm alarm;
  const fs::path dir = test::fresh_test_dir("hostile_garbage");
  const std::string junk = (dir / "junk.png").string();
  std::ofstream(junk, std::ios::binary) << std::string(4096, '\x5a');
  Result<Texture> t = load_texture(junk);
  ASSERT_FALSE(t.ok());
  expect_one_line(t.status().message());
  EXPECT_NE(t.status().message().find("cannot read image: not a PNG"), std::string::npos);
  const std::string empty = (dir / "empty.png").string();
  std::ofstream(empty, std::ios::binary).flush();
  t = load_texture(empty);
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.status().message().find("the file is empty"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace relief
