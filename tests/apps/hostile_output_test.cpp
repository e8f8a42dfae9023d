// Output safety (issue 20, defects 5, 6, 7 and the output side of 9): a full disk (RLIMIT_FSIZE
// through `ulimit -f`, and /dev/full) is a one-line error that leaves the old file at the path
// byte for byte and no temporary; two options naming one file, and any output that cannot be
// written, are refused before anything renders; SIGTERM / SIGINT during a write exit 143 / 130
// and remove the temporaries; a temporary a killed run left is removed by the next write to the
// same output; error lines never name a temporary, hold no control byte and stay under 300
// characters. Every run that could hang is bounded (`timeout 20`, or a deadline and SIGKILL).
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "apps/output.h"
#include "apps/scene_source.h"
#include "rasterizer/output_file.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"
#include "scene/scene.h"
#include "tests/apps/cli_run.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& p) {
  return "'" + p.string() + "'";
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

void put(const fs::path& p, const std::string& bytes) {
  std::ofstream f(p, std::ios::binary);
  f << bytes;
}

// Names in `dir` that look like relief temporaries (".NAME.tmp...").
std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (n.find(".tmp") != std::string::npos) out.push_back(n);
  }
  return out;
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += x + " ";
  return s;
}

// `relief ARGS` in `dir`, under `timeout 20`, after the shell line `setup` (e.g. "ulimit -f 4").
CliRun relief_in(const fs::path& dir, const std::string& args, const std::string& setup = "") {
  return run_shell("cd " + quoted(dir) + " && " + (setup.empty() ? "" : setup + "; ") +
                   "RELIEF_CACHE_DIR=none timeout 20 " + RELIEF_CLI + " " + args);
}

// One line "relief: ...", holding each of `needles` and no temporary's name.
void expect_one_line(const CliRun& r, const std::vector<std::string>& needles) {
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_EQ(r.out.rfind("relief: ", 0), 0u) << r.out;
  EXPECT_EQ(r.out.find(".tmp"), std::string::npos) << r.out;
  EXPECT_LT(r.out.size(), 300u) << r.out;
  for (const std::string& n : needles)
    EXPECT_NE(r.out.find(n), std::string::npos) << n << "\n" << r.out;
}

bool gl_renders(const fs::path& dir) {
  return cli_gl_missing().empty() &&
         relief_in(dir, "render plane --backend gl --size 8x8 -o gl_probe.png").code == 0;
}

// ---- full disk ----

// The old good file at `path` survives a run whose writes fail: exit 1, one line naming `path`.
void expect_full_disk_keeps(const fs::path& dir, const std::string& args,
                            const std::vector<std::string>& kept, const std::string& named) {
  std::vector<std::string> before;
  for (const std::string& k : kept) before.push_back(slurp(dir / k));
  const CliRun r = relief_in(dir, args, "ulimit -f 4");
  EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
  expect_one_line(r, {named, "File too large"});
  for (size_t i = 0; i < kept.size(); ++i)
    EXPECT_TRUE(slurp(dir / kept[i]) == before[i]) << kept[i] << " changed after: " << args;
  EXPECT_TRUE(temporaries(dir).empty()) << joined(temporaries(dir));
}

TEST(Hostile, FullDiskKeepsTheOldImageForEveryFormat) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  for (const std::string ext : {".png", ".exr", ".tif"}) {
    const std::string name = "a" + ext;
    ASSERT_EQ(relief_in(dir, "render plane --size 8x8 -o " + name).code, 0);  // the good file
    ASSERT_GT(fs::file_size(dir / name), 0u);
    expect_full_disk_keeps(dir, "render plane --size 128x128 -o " + name, {name}, name);
  }
}

TEST(Hostile, FullDiskOnAnAovKeepsEveryOldOutput) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  ASSERT_EQ(
      relief_in(dir, "render plane --size 8x8 -o a.png --aov normal=n.exr --stats s.json").code, 0);
  // The image fits under the limit (2048 bytes in dash, 4096 in bash), the normal AOV does not:
  // neither is replaced.
  expect_full_disk_keeps(dir,
                         "render plane --size 24x24 -o a.png --aov normal=n.exr --stats s.json",
                         {"a.png", "n.exr", "s.json"}, "n.exr");
}

TEST(Hostile, FullDiskOnTheGlBackendKeepsTheOldImage) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  if (!gl_renders(dir)) GTEST_SKIP() << "no GL backend here";
  ASSERT_EQ(relief_in(dir, "render plane --backend gl --size 8x8 -o a.png").code, 0);
  expect_full_disk_keeps(dir, "render plane --backend gl --size 128x128 -o a.png", {"a.png"},
                         "a.png");
}

TEST(Hostile, FullDiskKeepsTheOldExport) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  for (const std::string name : {"e.gltf", "e.glb"}) {
    put(dir / name, "old export");
    expect_full_disk_keeps(dir, "export plane -o " + name, {name}, "e");
    EXPECT_FALSE(fs::exists(dir / "e.bin")) << "a part of a failed export was renamed into place";
  }
}

// A 128 x 128 depth map of noise (its cone and normal maps do not compress to a few bytes).
void write_noise_depth(const fs::path& path) {
  relief::Plane p(128, 128);
  uint32_t x = 12345;
  for (float& v : p.values) {
    x = x * 1664525u + 1013904223u;
    v = (x >> 8) / 16777216.0f;
  }
  ASSERT_TRUE(relief::write_plane(path.string(), p).ok());
}

TEST(Hostile, FullDiskKeepsTheOldBakeOutputs) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  write_noise_depth(dir / "depth.png");
  put(dir / "cone.exr", "old cone map");
  put(dir / "normal.png", "old normal map");
  expect_full_disk_keeps(dir, "bake depth.png --cone relaxed -o cone.exr", {"cone.exr"},
                         "cone.exr");
  expect_full_disk_keeps(dir, "bake depth.png --normal -o normal.png", {"normal.png"},
                         "normal.png");
  ASSERT_EQ(relief_in(dir, "export teapot -o mesh.gltf").code, 0);
  for (const char* s : {"_front.exr", "_back.exr", "_front_normal.exr", "_back_normal.exr"})
    put(dir / (std::string("dual") + s), std::string("old ") + s);
  // (The old code removed all four names, the previous run's good files included.)
  expect_full_disk_keeps(
      dir, "bake --dual mesh.gltf -o dual --size 64",
      {"dual_front.exr", "dual_back.exr", "dual_front_normal.exr", "dual_back_normal.exr"},
      "dual_front.exr");
  for (const char* s : {"_depth.png", "_base_color.png", "_normal.png"})
    put(dir / (std::string("fur") + s), std::string("old ") + s);
  expect_full_disk_keeps(dir, "bake --fur fur -o fur --size 128",
                         {"fur_depth.png", "fur_base_color.png", "fur_normal.png"},
                         "fur_depth.png");
}

// Runs `write` in a child process whose files may not grow past `limit` bytes (RLIMIT_FSIZE);
// returns its Status message, or "ok".
std::string under_file_size_limit(rlim_t limit, const std::function<relief::Status()>& write) {
  int fds[2];
  if (::pipe(fds) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    relief::install_output_signal_handlers();  // what the CLI does: SIGXFSZ ignored
    const struct rlimit rl = {limit, limit};
    ::setrlimit(RLIMIT_FSIZE, &rl);
    const relief::Status s = write();
    const std::string m = s.ok() ? "ok" : s.message();
    (void)!::write(fds[1], m.data(), m.size());
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string m;
  char buf[512];
  for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) m.append(buf, n);
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (!WIFEXITED(status)) return "child died with signal " + std::to_string(WTERMSIG(status));
  return m;
}

TEST(Hostile, EveryWriterReportsAFullDiskAndKeepsTheOldFile) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  uint32_t x = 777;
  auto noise = [&x] {
    x = x * 1664525u + 1013904223u;
    return (x >> 8) / 16777216.0f;
  };
  relief::Image img(128, 128);  // noise: no format compresses it under the limit
  for (glm::vec4& p : img.pixels) p = glm::vec4(noise(), noise(), noise(), 1.0f);
  relief::Plane plane(128, 128);
  for (float& v : plane.values) v = noise();
  relief::Result<relief::Scene> scene = relief::cli::load_scene_source("plane");
  ASSERT_TRUE(scene.ok());
  const std::string text(5000, 'x');
  struct Case {
    std::string name;
    std::function<relief::Status(const std::string&)> write;
  };
  const std::vector<Case> cases = {
      {"s.json", [&](const std::string& p) { return relief::cli::write_text_atomic(p, text); }},
      {"i.png", [&](const std::string& p) { return relief::write_image(p, img); }},
      {"i.exr", [&](const std::string& p) { return relief::write_image(p, img); }},
      {"i.tif", [&](const std::string& p) { return relief::write_image(p, img); }},
      {"p.png", [&](const std::string& p) { return relief::write_plane(p, plane); }},
      {"p.exr", [&](const std::string& p) { return relief::write_plane(p, plane); }},
      {"p.tiff", [&](const std::string& p) { return relief::write_plane(p, plane); }},
      {"g.gltf", [&](const std::string& p) { return relief::save_gltf(*scene, p); }},
      {"g.glb", [&](const std::string& p) { return relief::save_gltf(*scene, p); }},
  };
  for (const Case& c : cases) {
    const std::string path = (dir / c.name).string();
    put(path, "old");
    const std::string m = under_file_size_limit(1024, [&] { return c.write(path); });
    EXPECT_NE(m, "ok") << c.name;
    EXPECT_NE(m.find("File too large"), std::string::npos) << c.name << ": " << m;
    EXPECT_EQ(m.find(".tmp"), std::string::npos) << m;
    EXPECT_TRUE(slurp(path) == "old") << c.name << " was replaced";
    EXPECT_TRUE(temporaries(dir).empty()) << c.name << ": " << joined(temporaries(dir));
    // Without the limit the same writer succeeds and replaces the file.
    EXPECT_EQ(under_file_size_limit(RLIM_INFINITY, [&] { return c.write(path); }), "ok");
    EXPECT_FALSE(slurp(path) == "old") << c.name << " was not replaced";
  }
}

TEST(Hostile, ExportGivesTwoTexturesOfOneLabelTwoFiles) {
  // Two materials of one name used to share one PNG name: the second file replaced the first
  // and both materials read the second texture back.
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  relief::Result<relief::Scene> scene = relief::cli::load_scene_source("plane");
  ASSERT_TRUE(scene.ok());
  relief::Material twin = scene->materials[0];
  const uint8_t red[4] = {255, 0, 0, 255};
  twin.textures["base_color"] =
      std::make_shared<const relief::Texture>(relief::TexFormat::kRGBA8, 1, 1, red);
  scene->materials.push_back(twin);
  relief::Instance inst = scene->instances[0];
  inst.material = static_cast<int>(scene->materials.size()) - 1;
  scene->instances.push_back(inst);
  const std::string path = (dir / "twins.gltf").string();
  ASSERT_TRUE(relief::save_gltf(*scene, path).ok());
  relief::Result<relief::Scene> back = relief::load_scene(path);
  ASSERT_TRUE(back.ok()) << back.status().message();
  ASSERT_EQ(back->materials.size(), scene->materials.size());
  const relief::Texture& a = *back->materials[0].textures.at("base_color");
  const relief::Texture& b = *back->materials.back().textures.at("base_color");
  EXPECT_NE(a.width(0), b.width(0)) << "both materials read one PNG";
  EXPECT_TRUE(temporaries(dir).empty()) << joined(temporaries(dir));
}

TEST(Hostile, DevFullIsRefusedNotWrittenThrough) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  CliRun r = relief_in(dir, "render plane --size 8x8 -o a.png --stats /dev/full");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"/dev/full"});
  EXPECT_FALSE(fs::exists(dir / "a.png"));
  fs::create_symlink("/dev/full", dir / "full.png");
  r = relief_in(dir, "render plane --size 8x8 -o full.png");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"full.png"});
  EXPECT_TRUE(fs::is_character_file("/dev/full"));
  EXPECT_TRUE(temporaries(dir).empty()) << joined(temporaries(dir));
  EXPECT_TRUE(temporaries("/dev").empty()) << joined(temporaries("/dev"));
}

// ---- same path twice, and checks before rendering ----

// `args` (at 8192x8192, which takes far longer than 5 s to render here) fails in well under
// 5 s with `code` and one line holding `needles`; a.png, if there, is unchanged.
void expect_refused_early(const fs::path& dir, const std::string& args, int code,
                          const std::vector<std::string>& needles) {
  const std::string before = fs::exists(dir / "a.png") ? slurp(dir / "a.png") : "";
  const auto t0 = std::chrono::steady_clock::now();
  const CliRun r = relief_in(dir, "render plane --size 8192x8192 " + args);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.code, code) << args << "\n" << r.out;
  expect_one_line(r, needles);
  EXPECT_LT(s, 5.0) << args << ": refused only after rendering";
  if (!before.empty()) {
    EXPECT_TRUE(slurp(dir / "a.png") == before) << "a.png changed: " << args;
  }
  EXPECT_TRUE(temporaries(dir).empty()) << joined(temporaries(dir));
}

TEST(Hostile, DuplicateOutputPathsAreRefusedBeforeRendering) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  ASSERT_EQ(relief_in(dir, "render plane --size 8x8 -o a.png").code, 0);
  fs::create_directories(dir / "sub");
  fs::create_symlink("a.png", dir / "link.png");
  expect_refused_early(dir, "-o a.png --aov uv=a.png", 2, {"--aov uv", "--output", "a.png"});
  expect_refused_early(dir, "-o a.png --aov uv=./a.png", 2, {"--aov uv", "--output"});
  expect_refused_early(dir, "-o a.png --aov normal=sub/../a.png", 2, {"--aov normal", "--output"});
  expect_refused_early(dir, "-o a.png --stats a.png", 2, {"--stats", "--output"});
  expect_refused_early(dir, "-o a.png --aov uv=u.exr --aov normal=./u.exr", 2,
                       {"--aov uv", "--aov normal", "u.exr"});
  expect_refused_early(dir, "-o a.png --aov uv=link.png", 2, {"--aov uv", "--output"});
  expect_refused_early(dir, "-o " + quoted(dir / "a.png") + " --aov uv=a.png", 2,
                       {"--aov uv", "--output"});
  expect_refused_early(dir, "--frames 1-3 -o f%04d.png --aov uv=./f%04d.png", 2,
                       {"--aov uv", "--output", "f0001.png"});
  // Across frames: frame 11's image is frame 1's uv AOV.
  expect_refused_early(dir, "--frames 1-20 -o f%d.png --aov uv=f1%d.png", 2,
                       {"--aov uv", "--output", "f11.png"});
}

TEST(Hostile, UnwritableOutputsAreRefusedBeforeRendering) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  fs::create_directories(dir / "d.png");
  put(dir / "file", "x");
  expect_refused_early(dir, "-o nodir/a.png", 1, {"nodir/a.png", "directory does not exist"});
  expect_refused_early(dir, "-o d.png", 1, {"d.png: is a directory"});
  expect_refused_early(dir, "-o a.png --aov uv=d.png", 1, {"d.png: is a directory"});
  expect_refused_early(dir, "-o a.png --stats nodir/s.json", 1, {"nodir/s.json"});
  expect_refused_early(dir, "-o file/a.png", 1, {"file/a.png", "not a directory"});
  expect_refused_early(dir, "-o sub/", 1, {"sub/: not a file name"});
  expect_refused_early(dir, "-o a.bmp", 2, {"a.bmp: unknown image extension '.bmp'"});
  expect_refused_early(dir, "-o a", 2, {"a: no image extension"});
  expect_refused_early(dir, "-o a.png --aov depth=d", 2, {"d: no image extension"});
  expect_refused_early(dir, "-o a.png --aov uv=u.jpg", 2, {"u.jpg: unknown image extension"});
  if (::geteuid() != 0) {  // root writes anywhere
    fs::create_directories(dir / "ro");
    fs::permissions(dir / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    expect_refused_early(dir, "-o ro/a.png", 1, {"ro/a.png", "not writable"});
    fs::permissions(dir / "ro", fs::perms::owner_all);
  }
}

TEST(Hostile, BakeOutputIsCheckedBeforeBaking) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  write_noise_depth(dir / "depth.png");
  CliRun r = relief_in(dir, "bake depth.png --cone relaxed -o nodir/c.exr");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"nodir/c.exr: directory does not exist"});
  EXPECT_EQ(r.out.find("baking"), std::string::npos) << r.out;
  ASSERT_EQ(relief_in(dir, "export plane -o mesh.gltf").code, 0);
  r = relief_in(dir, "bake --dual mesh.gltf -o nodir/dual --size 64");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"nodir/dual_front.exr: directory does not exist"});
}

// ---- signals ----

// A relief process started with posix_spawn (stdout and stderr to `log`), in `dir`.
pid_t spawn_relief(const fs::path& dir, const std::vector<std::string>& args) {
  std::vector<std::string> argv_s = {"/bin/sh", "-c",
                                     "cd " + quoted(dir) + " && exec " + std::string(RELIEF_CLI)};
  for (const std::string& a : args) argv_s[2] += " " + a;
  argv_s[2] += " >relief.log 2>&1";
  std::vector<char*> argv;
  for (std::string& a : argv_s) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::vector<std::string> env_s = {"RELIEF_CACHE_DIR=none"};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "RELIEF_CACHE_DIR=", 17) != 0) env_s.push_back(*e);
  std::vector<char*> envp;
  for (std::string& e : env_s) envp.push_back(e.data());
  envp.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawn(&pid, "/bin/sh", nullptr, nullptr, argv.data(), envp.data()) != 0) return -1;
  return pid;
}

// Waits at most `seconds` for `pid`; SIGKILLs it past that. The wait status, or -1 on timeout.
int wait_bounded(pid_t pid, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (std::chrono::steady_clock::now() < end) {
    if (::waitpid(pid, &status, WNOHANG) == pid) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return -1;
}

// Polls `dir` until a temporary appears (true) or `pid` exits / 20 s pass (false).
bool wait_for_temporary(const fs::path& dir, pid_t pid) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < end) {
    if (!temporaries(dir).empty()) return true;
    int status;
    if (::waitpid(pid, &status, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(300));
  }
  return false;
}

const std::vector<std::string> kBigRun = {
    "render", "plane",           "--size",  "768x768",      "--frames", "1-40",
    "-o",     "x%04d.exr",       "--aov",   "uv=u%04d.exr", "--aov",    "normal=n%04d.exr",
    "--aov",  "depth=d%04d.exr", "--stats", "s%04d.json"};

TEST(Hostile, SignalDuringAWriteRemovesTemporariesAndExits128PlusSignal) {
  for (const int sig : {SIGTERM, SIGINT}) {
    const fs::path dir = relief::test::fresh_test_dir("hostile_out");
    const pid_t pid = spawn_relief(dir, kBigRun);
    ASSERT_GT(pid, 0);
    const bool hit = wait_for_temporary(dir, pid);
    ::kill(pid, sig);
    const int status = wait_bounded(pid, 20);
    EXPECT_TRUE(hit) << "no temporary seen before the run ended";
    ASSERT_NE(status, -1) << "relief did not exit after signal " << sig;
    EXPECT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status) << "\n"
                                   << slurp(dir / "relief.log");
    if (WIFEXITED(status)) {
      EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    }
    EXPECT_TRUE(temporaries(dir).empty()) << sig << ": " << joined(temporaries(dir));
  }
}

TEST(Hostile, SignalAtAnyTimeLeavesNoTemporary) {
  for (const int sig : {SIGTERM, SIGINT})
    for (const int ms : {150, 700, 1600, 2500}) {
      const fs::path dir = relief::test::fresh_test_dir("hostile_out");
      const pid_t pid = spawn_relief(dir, kBigRun);
      ASSERT_GT(pid, 0);
      std::this_thread::sleep_for(std::chrono::milliseconds(ms));
      ::kill(pid, sig);
      const int status = wait_bounded(pid, 20);
      ASSERT_NE(status, -1) << "relief did not exit after signal " << sig;
      // A signal before relief installed its handlers (the shell not yet exec'd, libraries still
      // loading on a busy machine) kills it by default; then nothing was written at all.
      const bool before_start = WIFSIGNALED(status) && fs::exists(dir / "relief.log") &&
                                std::distance(fs::directory_iterator(dir), {}) == 1;
      if (!before_start) {
        EXPECT_TRUE(WIFEXITED(status))
            << sig << " at " << ms << " ms: killed by signal " << WTERMSIG(status);
        if (WIFEXITED(status)) {
          EXPECT_EQ(WEXITSTATUS(status), 128 + sig) << ms << " ms";
        }
      }
      EXPECT_TRUE(temporaries(dir).empty())
          << sig << " at " << ms << " ms: " << joined(temporaries(dir));
    }
}

TEST(Hostile, RerunAfterSigkillRemovesItsStaleTemporary) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  const std::vector<std::string> run1 = {"render", "plane",       "--size", "1024x1024",
                                         "-o",     "x.exr",       "--aov",  "uv=u.exr",
                                         "--aov",  "normal=n.exr"};
  const pid_t pid = spawn_relief(dir, run1);
  ASSERT_GT(pid, 0);
  const bool hit = wait_for_temporary(dir, pid);
  ::kill(pid, SIGKILL);  // cannot be caught: its temporary stays
  ASSERT_NE(wait_bounded(pid, 20), -1);
  if (!hit || temporaries(dir).empty()) GTEST_SKIP() << "the run ended before a temporary was seen";
  const std::vector<std::string> left = temporaries(dir);
  ASSERT_EQ(
      relief_in(dir, "render plane --size 8x8 -o x.exr --aov uv=u.exr --aov normal=n.exr").code, 0);
  EXPECT_TRUE(temporaries(dir).empty())
      << "left by the killed run: " << joined(left) << "; now: " << joined(temporaries(dir));
}

TEST(Hostile, StaleTemporariesOfDeadProcessesOnlyAreRemoved) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  pid_t dead = 999999;
  while (::kill(dead, 0) == 0 || errno != ESRCH) --dead;  // a PID no process has
  const std::string stale = ".a.png.tmp" + std::to_string(dead) + "_0.png";
  const std::string live = ".a.png.tmp" + std::to_string(::getpid()) + "_0.png";  // ours: alive
  const std::string other = ".b.png.tmp" + std::to_string(dead) + "_0.png";       // not a.png's
  const std::string lookalike = ".a.png.tmpx" + std::to_string(dead) + "_0.png";
  for (const std::string& n : {stale, live, other, lookalike}) put(dir / n, "partial");
  const CliRun r = relief_in(dir, "render plane --size 8x8 -o a.png");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_FALSE(fs::exists(dir / stale));
  EXPECT_TRUE(fs::exists(dir / live));
  EXPECT_TRUE(fs::exists(dir / other));
  EXPECT_TRUE(fs::exists(dir / lookalike));
}

// ---- error lines ----

TEST(Hostile, OutputErrorLinesAreEscapedCappedAndNeverNameATemporary) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  // A newline and an escape sequence in a folder that does not exist.
  CliRun r = relief_in(dir, "render plane --size 8x8 -o \"$(printf 'no\\ndir\\033[31m/a.png')\"");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"no\\x0adir\\x1b[31m/a.png", "directory does not exist"});
  EXPECT_EQ(r.out.find('\033'), std::string::npos) << r.out;
  // A long name: the line is cut, still one line under 300 characters.
  const std::string long_dir(2000, 'd');
  r = relief_in(dir, "render plane --size 8x8 -o " + long_dir + "/a.png");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_line(r, {"ddd..."});
  // No extension: the user's name, not the temporary's (it was "unknown image extension
  // '.tmp<PID>'").
  r = relief_in(dir, "render plane --size 8x8 -o out --aov uv=uv");
  EXPECT_EQ(r.code, 2) << r.out;
  expect_one_line(r, {"out: no image extension"});
}

TEST(Hostile, WritesKeepThePermissionsOfTheFileReplaced) {
  const fs::path dir = relief::test::fresh_test_dir("hostile_out");
  ASSERT_EQ(relief_in(dir, "render plane --size 8x8 -o a.png").code, 0);
  fs::permissions(dir / "a.png", fs::perms(0640));
  ASSERT_EQ(relief_in(dir, "render plane --size 16x16 -o a.png").code, 0);
  EXPECT_EQ(fs::status(dir / "a.png").permissions() & fs::perms::all, fs::perms(0640));
}

}  // namespace
