// The CLI on a render farm (issue 21): scene paths and outputs checked before anything renders,
// --frames lists, --skip-existing / --placeholder resume and claims, --quiet, --log-json,
// `relief version`, the build and bake objects of --stats, the cone-map bake report.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/image_io.h"
#include "tests/apps/cli_run.h"
#include "tests/test_dir.h"

namespace {

namespace fs = std::filesystem;
using relief::test::fresh_test_dir;

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::string q(const fs::path& p) {
  return "'" + p.string() + "'";
}

// Every file in `dir` (names), temporaries included.
std::set<std::string> files_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

// The JSON lines of a --log-json run's stdout (stderr dropped): frame -> the line.
std::map<int, nlohmann::json> frame_log(const std::string& out) {
  std::map<int, nlohmann::json> log;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    EXPECT_FALSE(j.is_discarded()) << "not JSON: " << line;
    if (j.is_discarded()) continue;
    log[j.at("frame").get<int>()] = j;
  }
  return log;
}

// `relief ARGS` with stdout only (stderr to /dev/null), for --log-json.
CliRun run_stdout(const std::string& args) {
  return run_shell("(" + std::string(RELIEF_CLI) + " " + args + " 2>/dev/null)");
}

const std::string kSmall = " --size 64x48 --threads 2 ";

TEST(FarmCli, VersionFlagAndSubcommandPrintTheBuild) {
  const CliRun flag = run("--version");
  ASSERT_EQ(flag.code, 0) << flag.out;
  for (const char* key : {"relief 0.", "commit:", "build type:", "simd:", "backends:", "cpu"})
    EXPECT_NE(flag.out.find(key), std::string::npos) << key << " in " << flag.out;
  const CliRun json = run("version --json");
  ASSERT_EQ(json.code, 0) << json.out;
  const nlohmann::json j = nlohmann::json::parse(json.out);
  for (const char* key : {"version", "commit", "build_type", "simd", "backends", "compiler"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(j["simd"] == "avx512" || j["simd"] == "avx2" || j["simd"] == "baseline") << j;
  EXPECT_FALSE(j["commit"].get<std::string>().empty());
  // `relief version` prints the same; the SIMD path is the one in use (RELIEF_SIMD=baseline).
  const CliRun base = run_shell("RELIEF_SIMD=baseline " + std::string(RELIEF_CLI) + " version");
  ASSERT_EQ(base.code, 0) << base.out;
  EXPECT_NE(base.out.find("simd:       baseline"), std::string::npos) << base.out;
  EXPECT_EQ(base.out.substr(0, base.out.find("simd:")), flag.out.substr(0, flag.out.find("simd:")));
}

TEST(FarmCli, ScenePathsAreCheckedFirstAndNamed) {
  const fs::path dir = fresh_test_dir("farm_scene");
  fs::create_directories(dir / "scenes.d");
  std::ofstream(dir / "notes") << "x";
  std::ofstream(dir / "a.obj") << "o";
  struct Case {
    std::string scene, message;
    int code;
  };
  const std::vector<Case> cases = {
      {(dir / "scenes.d").string() + "/", ": is a directory", 1},
      {(dir / "a.obj").string(), ": unsupported scene format '.obj' (expected .gltf or .glb)", 1},
      {(dir / "nosuch.gltf").string(), ": no such file", 1},
      {(dir / "notes").string(), ": unsupported scene format (no extension; expected", 1},
      {"nosuchscene", "unknown scene 'nosuchscene' (built-in scenes: plane", 1},
  };
  for (const Case& c : cases) {
    // Without -o: the scene's error, not "--output is required".
    const CliRun r = run("render " + q(c.scene));
    EXPECT_EQ(r.code, c.code) << c.scene << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.scene << ": " << r.out;
    if (c.scene != "nosuchscene") {
      EXPECT_EQ(r.out.rfind("relief: " + c.scene + ":", 0), 0u) << r.out;
    }
  }
  // A folder named without '/' or extension is a path too (not "unknown scene").
  const CliRun bare = run_shell("cd " + q(dir) + " && " + RELIEF_CLI + " render scenes.d");
  EXPECT_NE(bare.out.find("scenes.d: is a directory"), std::string::npos) << bare.out;
  // A built-in scene without -o is the usage error.
  const CliRun no_o = run("render plane");
  EXPECT_EQ(no_o.code, 2) << no_o.out;
  EXPECT_NE(no_o.out.find("--output is required"), std::string::npos) << no_o.out;
  EXPECT_EQ(files_in(dir), (std::set<std::string>{"scenes.d", "notes", "a.obj"}));
}

// A render that would bake a cone map first (18 s on 2 cores, and a file in the cache folder):
// an output error must come before it, naming the user's path, with nothing written.
TEST(FarmCli, OutputErrorsCostNoRender) {
  const fs::path dir = fresh_test_dir("farm_outputs");
  const fs::path out = dir / "out", cache = dir / "cache";
  fs::create_directories(out);
  fs::create_directories(cache);
  fs::create_directories(out / "sub");
  const std::string o = (out / "ok.png").string();
  struct Case {
    std::string flags, path, message;
  };
  const std::vector<Case> cases = {
      {"-o room.jpg", "room.jpg", "unknown image extension '.jpg'"},
      {"-o " + (out / "sub").string() + "/", (out / "sub").string() + "/", "is a directory"},
      {"-o " + (out / "a").string(), (out / "a").string(), "no image extension"},
      {"-o " + (out / "nodir/a.png").string(), (out / "nodir/a.png").string(),
       "directory does not exist"},
      {"-o " + o + " --aov depth=" + (out / "d.jpg").string(), (out / "d.jpg").string(),
       "unknown image extension"},
      {"-o " + o + " --stats " + (out / "sub").string(), (out / "sub").string(), "is a directory"},
      {"-o " + (out / "f%d.png").string() +
           " --frames 0-3 --aov depth=" + (out / "nodir/d%d.exr").string(),
       (out / "nodir/d0.exr").string(), "directory does not exist"},
  };
  for (const Case& c : cases) {
    const CliRun r = run_shell("cd " + q(dir) + " && RELIEF_CACHE_DIR=" + q(cache) +
                               " timeout 20 " + RELIEF_CLI +
                               " render plane --technique "
                               "relaxed_cone" +
                               kSmall + c.flags);
    EXPECT_TRUE(r.code == 1 || r.code == 2) << c.flags << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << c.flags << ": " << r.out;
    EXPECT_EQ(r.out.rfind("relief: " + c.path + ": ", 0), 0u) << c.flags << ": " << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.flags << ": " << r.out;
    EXPECT_EQ(r.out.find(".tmp"), std::string::npos) << r.out;
    EXPECT_TRUE(fs::is_empty(cache)) << c.flags << ": the cone map was baked";
    EXPECT_EQ(files_in(out), std::set<std::string>{"sub"}) << c.flags;
  }
}

TEST(FarmCli, FrameListsNameEveryListedFrameOnce) {
  const fs::path dir = fresh_test_dir("farm_lists");
  const CliRun r = run("render plane --size 16x12 --threads 1 --frames 1,4,6-10:2 -o " +
                       q(dir / "f%02d.png") + " --log-json");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(files_in(dir),
            (std::set<std::string>{"f01.png", "f04.png", "f06.png", "f08.png", "f10.png"}));
  // Shards split the list, not the span 1..10: 5 frames over 2 shards are 2 + 3.
  const fs::path s = dir / "s";
  fs::create_directories(s);
  std::vector<int> seen;
  for (int i = 0; i < 2; ++i) {
    const CliRun sr = run_stdout(
        "render plane --size 16x12 --threads 1 --frames 1,4,6-10:2 "
        "--log-json --shard " +
        std::to_string(i) + "/2 -o " + q(s / "f%02d.png"));
    ASSERT_EQ(sr.code, 0) << sr.out;
    const auto log = frame_log(sr.out);
    EXPECT_EQ(log.size(), i == 0 ? 2u : 3u) << sr.out;
    for (const auto& [f, j] : log) seen.push_back(f);
  }
  EXPECT_EQ(seen, (std::vector<int>{1, 4, 6, 8, 10}));
  // The turntable angle is the frame's place in the list's span: the same image as a range.
  const CliRun range =
      run("render plane --size 16x12 --threads 1 --frames 1-10 -o " + q(dir / "r%02d.png"));
  ASSERT_EQ(range.code, 0) << range.out;
  for (const char* f : {"04", "08"})
    EXPECT_EQ(slurp(dir / ("f" + std::string(f) + ".png")),
              slurp(dir / ("r" + std::string(f) + ".png")))
        << f;
}

// A pre-empted run: killed (SIGTERM) after a few frames, rerun with --skip-existing. Only the
// missing frames render; the result equals an uninterrupted render bit for bit.
TEST(FarmCli, KilledRangeResumesWithoutRework) {
  const fs::path dir = fresh_test_dir("farm_resume");
  const fs::path ref = dir / "ref", out = dir / "out";
  fs::create_directories(ref);
  fs::create_directories(out);
  const std::string common = "render plane --size 64x48 --spp 16 --threads 2 --frames 0-11 ";
  const std::string outputs = "-o " + q(out / "f%02d.png") +
                              " --aov depth=" + q(out / "d%02d.exr") + " --stats " +
                              q(out / "s%02d.json");
  const CliRun full =
      run(common + "-o " + q(ref / "f%02d.png") + " --aov depth=" + q(ref / "d%02d.exr"));
  ASSERT_EQ(full.code, 0) << full.out;
  // Start, wait for the third finished image, SIGTERM (what Slurm sends on pre-emption).
  const CliRun killed = run_shell(
      "timeout 20 sh -c '" + std::string(RELIEF_CLI) + " " + common + "--placeholder " + outputs +
      " > /dev/null & pid=$!; while [ $(find " + q(out) +
      " -name \"f*.png\" -size +0 | wc -l) -lt 3 ]; do sleep 0.02; done; kill -TERM $pid; "
      "wait $pid; echo exit=$?'");
  ASSERT_NE(killed.out.find("exit=143"), std::string::npos) << killed.out;
  // No claim (empty file) and no temporary left; complete frames only, with all their outputs.
  std::set<std::string> before = files_in(out);
  std::set<int> done;
  for (const std::string& name : before) {
    ASSERT_TRUE(name[0] == 'f' || name[0] == 'd' || name[0] == 's') << name;
    EXPECT_GT(fs::file_size(out / name), 0u) << name;
    if (name[0] == 'f') done.insert(std::stoi(name.substr(1, 2)));
  }
  ASSERT_GE(done.size(), 3u);
  ASSERT_LT(done.size(), 12u) << "the run finished before the kill";
  // A partly written frame (its stats removed) counts as missing.
  const int partial = *done.begin();
  char stats_name[16];
  std::snprintf(stats_name, sizeof stats_name, "s%02d.json", partial);
  ASSERT_TRUE(fs::remove(out / stats_name));
  std::map<std::string, fs::file_time_type> mtimes;
  for (const std::string& name : files_in(out)) mtimes[name] = fs::last_write_time(out / name);

  const CliRun resumed = run_stdout(common + "--skip-existing --log-json " + outputs);
  ASSERT_EQ(resumed.code, 0) << resumed.out;
  const auto log = frame_log(resumed.out);
  ASSERT_EQ(log.size(), 12u) << resumed.out;
  int rendered = 0;
  for (const auto& [f, j] : log) {
    const bool was_done = done.count(f) && f != partial;
    EXPECT_EQ(j["status"], was_done ? "skipped" : "rendered") << j;
    rendered += j["status"] == "rendered";
    EXPECT_EQ(j["outputs"].size(), 3u) << j;
  }
  EXPECT_EQ(rendered, 12 - static_cast<int>(done.size()) + 1);
  for (const auto& [name, t] : mtimes)  // finished frames were not written again
    if (std::stoi(name.substr(1, 2)) != partial) {
      EXPECT_EQ(fs::last_write_time(out / name), t) << name;
    }
  for (int f = 0; f < 12; ++f) {
    char n[32];
    std::snprintf(n, sizeof n, "f%02d.png", f);
    EXPECT_EQ(slurp(out / n), slurp(ref / n)) << n;
    std::snprintf(n, sizeof n, "d%02d.exr", f);
    const relief::Result<relief::Image> a = relief::read_image((out / n).string());
    const relief::Result<relief::Image> b = relief::read_image((ref / n).string());
    ASSERT_TRUE(a.ok() && b.ok()) << n;
    EXPECT_EQ(a->pixels, b->pixels) << n;
  }
  EXPECT_EQ(files_in(out).size(), 36u);
}

TEST(FarmCli, SkipExistingCountsEmptyFilesOnlyUnderPlaceholder) {
  const fs::path dir = fresh_test_dir("farm_empty");
  const std::string args =
      "render plane --size 16x12 --threads 1 --frames 0-2 --log-json -o " + q(dir / "f%d.png");
  ASSERT_EQ(run(args).code, 0);
  const std::string good = slurp(dir / "f1.png");
  std::ofstream(dir / "f1.png", std::ios::trunc).close();  // a killed node's claim
  // --placeholder: the empty file is a claim; skipped and left as it is.
  auto log = frame_log(run_stdout(args + " --placeholder").out);
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[0]["status"], "skipped");
  EXPECT_EQ(log[1]["status"], "skipped");
  EXPECT_EQ(log[1]["reason"], "claimed");
  EXPECT_EQ(fs::file_size(dir / "f1.png"), 0u);
  // --skip-existing alone: an empty file is no output; frame 1 renders again.
  log = frame_log(run_stdout(args + " --skip-existing").out);
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log[0]["status"], "skipped");
  EXPECT_EQ(log[0]["reason"], "exists");
  EXPECT_EQ(log[1]["status"], "rendered");
  EXPECT_EQ(log[2]["status"], "skipped");
  EXPECT_EQ(slurp(dir / "f1.png"), good);
}

TEST(FarmCli, ConcurrentPlaceholderRunsRenderEachFrameOnce) {
  const fs::path dir = fresh_test_dir("farm_claims");
  const std::string cmd = std::string(RELIEF_CLI) +
                          " render plane --size 32x24 --spp 4 --threads 1 --frames 0-15 "
                          "--placeholder --log-json -o " +
                          q(dir / "f%02d.png");
  const CliRun r = run_shell("timeout 20 sh -c '" + cmd + " > " + q(dir / "a.log") + " & " + cmd +
                             " > " + q(dir / "b.log") + " & wait'");
  ASSERT_EQ(r.code, 0) << r.out;
  std::map<int, int> rendered;
  for (const char* name : {"a.log", "b.log"})
    for (const auto& [f, j] : frame_log(slurp(dir / name)))
      rendered[f] += j["status"] == "rendered";
  for (int f = 0; f < 16; ++f) EXPECT_EQ(rendered[f], 1) << "frame " << f;
  for (int f = 0; f < 16; ++f) {
    char n[16];
    std::snprintf(n, sizeof n, "f%02d.png", f);
    EXPECT_GT(fs::file_size(dir / n), 0u) << n;
  }
  EXPECT_EQ(files_in(dir).size(), 18u);  // 16 frames and 2 logs: no claim or temporary left
}

// Also: --quiet still prints the error.
TEST(FarmCli, FailedFrameReleasesItsClaim) {
  const fs::path dir = fresh_test_dir("farm_failed");
  // A file-size limit of 1 KiB: the claim (0 bytes) is created, the PNG cannot be written.
  const CliRun r = run_shell("ulimit -f 1; (" + std::string(RELIEF_CLI) +
                             " render plane --size 64x48 --threads 1 --frames 0-1 --placeholder "
                             "--log-json --quiet -o " +
                             q(dir / "f%d.png") + " 2>" + q(dir / "err.txt") + ")");
  EXPECT_EQ(r.code, 1) << r.out;
  const auto log = frame_log(r.out);
  ASSERT_EQ(log.size(), 1u) << r.out;
  EXPECT_EQ(log.at(0)["status"], "failed");
  EXPECT_NE(log.at(0)["error"].get<std::string>().find("f0.png"), std::string::npos);
  const std::string err = slurp(dir / "err.txt");
  EXPECT_EQ(lines(err), 1) << err;
  EXPECT_EQ(err.rfind("relief: " + (dir / "f0.png").string() + ": ", 0), 0u) << err;
  EXPECT_EQ(files_in(dir), std::set<std::string>{"err.txt"});  // the claim is gone
}

TEST(FarmCli, QuietPrintsOnlyErrors) {
  const fs::path dir = fresh_test_dir("farm_quiet");
  const CliRun ok = run("render plane --size 16x12 --frames 0-2 --quiet -o " + q(dir / "f%d.png"));
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_EQ(ok.out, "");
  EXPECT_EQ(files_in(dir).size(), 3u);
  // With --log-json: the JSON lines and nothing else.
  const CliRun json =
      run("render plane --size 16x12 --frames 0-1 -q --log-json -o " + q(dir / "j%d.png"));
  EXPECT_EQ(json.code, 0);
  EXPECT_EQ(lines(json.out), 2) << json.out;
  EXPECT_EQ(frame_log(json.out).size(), 2u);
}

TEST(FarmCli, LogJsonIsOneLineAFrameOnStdout) {
  const fs::path dir = fresh_test_dir("farm_log");
  const CliRun r = run_stdout("render plane --size 16x12 --frames 3-5 --explain --log-json -o " +
                              q(dir / "f%d.png") + " --aov uv=" + q(dir / "uv%d.exr"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(lines(r.out), 3) << r.out;  // the plan and the summary went to stderr
  const auto log = frame_log(r.out);
  ASSERT_EQ(log.size(), 3u);
  for (int f = 3; f <= 5; ++f) {
    const nlohmann::json& j = log.at(f);
    EXPECT_EQ(j["status"], "rendered");
    EXPECT_EQ(j["outputs"],
              nlohmann::json::array({(dir / ("f" + std::to_string(f) + ".png")).string(),
                                     (dir / ("uv" + std::to_string(f) + ".exr")).string()}));
    EXPECT_GT(j["ms"].get<double>(), 0.0);
    EXPECT_GT(j["frame_ms"].get<double>(), 0.0);
    EXPECT_LE(j["frame_ms"].get<double>(), j["ms"].get<double>());
    EXPECT_EQ(j["bake_ms"].get<double>(), 0.0);
  }
}

// A glTF copy of the shipped plane with a 32x32 depth map: a cone-map bake of a few ms.
fs::path small_relief_scene(const fs::path& dir) {
  const fs::path src = fs::path(RELIEF_SOURCE_DIR) / "scenes";
  for (const char* f : {"plane.gltf", "plane.bin", "plane_bricks_base_color.png"})
    fs::copy_file(src / f, dir / f);
  relief::Plane depth(32, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) depth.at(x, y) = (x % 8 == 0 || y % 8 == 0) ? 0.0f : 0.8f;
  EXPECT_TRUE(relief::write_plane((dir / "plane_bricks_depth.png").string(), depth).ok());
  return dir / "plane.gltf";
}

TEST(FarmCli, ConeMapBakeIsReportedApartFromTheFrame) {
  const fs::path dir = fresh_test_dir("farm_bake");
  const fs::path scene = small_relief_scene(dir), cache = dir / "cache";
  const std::string cmd = "RELIEF_CACHE_DIR=" + q(cache) + " " + RELIEF_CLI + " render " +
                          q(scene) + " --technique relaxed_cone" + kSmall + "-o " +
                          q(dir / "a.png") + " --stats " + q(dir / "a.json");
  const CliRun first = run_shell(cmd);
  ASSERT_EQ(first.code, 0) << first.out;
  EXPECT_NE(first.out.find(", derived-map bake "), std::string::npos) << first.out;
  EXPECT_NE(first.out.find("(baked 1, cached 0)"), std::string::npos) << first.out;
  nlohmann::json j = nlohmann::json::parse(slurp(dir / "a.json"));
  EXPECT_EQ(j["bake"]["baked"], 1) << j["bake"];
  EXPECT_EQ(j["bake"]["disk_cache_hits"], 0);
  EXPECT_GT(j["bake"]["ms"].get<double>(), 0.0);
  EXPECT_EQ(j["build"]["version"].get<std::string>().rfind("0.", 0), 0u) << j["build"];
  EXPECT_TRUE(j["build"].contains("commit") && j["build"].contains("simd") &&
              j["build"].contains("backends"));
  const CliRun second = run_shell(cmd);
  ASSERT_EQ(second.code, 0) << second.out;
  EXPECT_EQ(second.out.find("derived-map bake"), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("cone maps from the disk cache"), std::string::npos) << second.out;
  j = nlohmann::json::parse(slurp(dir / "a.json"));
  EXPECT_EQ(j["bake"]["baked"], 0);
  EXPECT_EQ(j["bake"]["disk_cache_hits"], 1);
  // Off a terminal nothing about the bake goes to stderr: one status line.
  EXPECT_EQ(lines(first.out), 1) << first.out;
}

TEST(FarmCli, ConeMapBakeShowsALineAndABarOnATerminal) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
  const fs::path dir = fresh_test_dir("farm_bake_tty");
  const fs::path scene = small_relief_scene(dir);
  const std::string cmd = "RELIEF_CACHE_DIR=none " + std::string(RELIEF_CLI) + " render " +
                          scene.string() + " --technique cone_quad" + kSmall + "--frames 0-1 -o " +
                          (dir / "t%d.png").string();
  const CliRun r = run_shell("script -qec '" + cmd + "' /dev/null");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("baking quad cone map 32x32"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("100%"), std::string::npos) << r.out;
  // The summary starts a line of its own (not glued to the progress bar).
  EXPECT_NE(r.out.find("\r\033[K2 frames (0-1"), std::string::npos) << r.out;
  const CliRun quiet = run_shell("script -qec '" + cmd + " --quiet' /dev/null");
  EXPECT_EQ(quiet.code, 0) << quiet.out;
  EXPECT_EQ(quiet.out, "");
}

TEST(FarmCli, BakeRefusesDepthScaleWithCone) {
  const fs::path dir = fresh_test_dir("farm_bake_scale");
  relief::Plane depth(8, 8, 0.5f);
  depth.at(3, 3) = 0.0f;
  ASSERT_TRUE(relief::write_plane((dir / "d.exr").string(), depth).ok());
  const CliRun r =
      run("bake " + q(dir / "d.exr") + " --cone relaxed --depth-scale 0.2 -o " + q(dir / "c.exr"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("--depth-scale"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "c.exr"));
  EXPECT_EQ(
      run("bake " + q(dir / "d.exr") + " --normal --depth-scale 0.2 -o " + q(dir / "n.exr")).code,
      0);
}

// Shadow maps drawn on demand (the default) and whole (--whole-shadow-maps) give the same PNG, and
// --stats says how many of the map's tiles each drew.
TEST(FarmCli, WholeShadowMapsGiveTheSamePngAndStatsCountTheTilesDrawn) {
  const fs::path dir = fresh_test_dir("farm_whole_shadow_maps");
  std::string png[2];
  nlohmann::json stats[2];
  for (int whole = 0; whole < 2; ++whole) {
    const fs::path image = dir / (whole ? "whole.png" : "demand.png");
    const fs::path json = dir / (whole ? "whole.json" : "demand.json");
    const CliRun r = run("render teatime --size 200x150 --threads 2 -q -o " + q(image) +
                         " --stats " + q(json) + (whole ? " --whole-shadow-maps" : ""));
    ASSERT_EQ(r.code, 0) << r.out;
    png[whole] = slurp(image);
    stats[whole] = nlohmann::json::parse(slurp(json));
  }
  EXPECT_FALSE(png[0].empty());
  EXPECT_TRUE(png[0] == png[1]) << "the PNGs differ";
  const nlohmann::json& demand = stats[0]["passes"][0];
  const nlohmann::json& whole = stats[1]["passes"][0];
  ASSERT_EQ(demand["kind"], "shadow");
  ASSERT_EQ(whole["kind"], "shadow");
  EXPECT_EQ(whole["tiles_drawn"], whole["tiles"]);
  EXPECT_EQ(demand["tiles"], whole["tiles"]);
  EXPECT_GT(demand["tiles_drawn"].get<uint64_t>(), 0u);
  EXPECT_LT(demand["tiles_drawn"].get<uint64_t>(), demand["tiles"].get<uint64_t>());
  EXPECT_LT(demand["fragments_shaded"].get<uint64_t>(), whole["fragments_shaded"].get<uint64_t>());
}

TEST(FarmCli, BenchAnglesErrorStatesTheRangeItChecks) {
  const CliRun r = run("bench --angles 0,95");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_NE(r.out.find("--angles: expected numbers in [0, 89.9], got '95'"), std::string::npos)
      << r.out;
}

TEST(FarmCli, BarePluginFileNameIsAPathHere) {
  const fs::path fixture = fs::path(RELIEF_BINARY_DIR) / "lib/relief_test_plugin.so";
  if (!fs::exists(fixture)) GTEST_SKIP() << "build relief_test_plugin first (test_plugins)";
  const fs::path dir = fresh_test_dir("farm_plugin");
  fs::copy_file(fixture, dir / "my.so");
  const CliRun r = run_shell("cd " + q(dir) + " && " + RELIEF_CLI + " techniques --plugin my.so");
  EXPECT_EQ(r.code, 0) << r.out;
  const CliRun none =
      run_shell("cd " + q(dir) + " && " + RELIEF_CLI + " techniques --plugin other.so");
  EXPECT_EQ(none.code, 1) << none.out;
  EXPECT_EQ(lines(none.out), 1) << none.out;
}

TEST(FarmCli, GlBackendSkipsAndResumesAlike) {
  if (const std::string why = cli_gl_missing(); !why.empty()) GTEST_SKIP() << why;
  const fs::path dir = fresh_test_dir("farm_gl");
  const std::string args = "render plane --backend gl --size 32x24 --frames 0-2 -o " +
                           q(dir / "f%d.png") + " --aov depth=" + q(dir / "d%d.exr");
  ASSERT_EQ(run(args).code, 0);
  const std::string f1 = slurp(dir / "f1.png");
  fs::remove(dir / "d1.exr");
  const auto log = frame_log(run_stdout(args + " --skip-existing --log-json").out);
  ASSERT_EQ(log.size(), 3u);
  EXPECT_EQ(log.at(0)["status"], "skipped");
  EXPECT_EQ(log.at(1)["status"], "rendered");
  EXPECT_EQ(log.at(2)["status"], "skipped");
  EXPECT_EQ(slurp(dir / "f1.png"), f1);
  EXPECT_TRUE(fs::exists(dir / "d1.exr"));
}

}  // namespace
