// Multi-frame rendering: --frames, --shard, --spp, --exposure (apps/frames.h, apps/cmd_render.cpp).
#include "apps/frames.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include <glm/vec3.hpp>

#include "scene/image_io.h"
#include "tests/apps/cli_run.h"

namespace relief::cli {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder for one test.
std::string fresh_dir(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("frames_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

size_t files_in(const std::string& dir) {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file();
  return n;
}

Image read(const std::string& path) {
  Result<Image> im = read_image(path);
  EXPECT_TRUE(im.ok()) << path << ": " << (im.ok() ? "" : im.status().message());
  return im.ok() ? *im : Image();
}

bool same_pixels(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height && a.pixels == b.pixels;
}

TEST(Frames, ParsesRanges) {
  Result<FrameList> r = parse_frames("3-7");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->first(), 3);
  EXPECT_EQ(r->last(), 7);
  EXPECT_EQ(r->count(), 5);
  r = parse_frames("12");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->count(), 1);
  for (const char* bad : {"", "7-3", "-1-3", "1-", "a-b", "1-2-3", "1--2", "12345678", " 1-2"})
    EXPECT_FALSE(parse_frames(bad).ok()) << bad;
}

TEST(Frames, ParsesListsWithSteps) {
  Result<FrameList> r = parse_frames("1,5,10-20,30-90:3");
  ASSERT_TRUE(r.ok()) << r.status().message();
  std::vector<int> want{1, 5};
  for (int f = 10; f <= 20; ++f) want.push_back(f);
  for (int f = 30; f <= 90; f += 3) want.push_back(f);
  EXPECT_EQ(r->frames, want);
  r = parse_frames("40-50:4,2");  // sorted; the step stops at or before B
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->frames, (std::vector<int>{2, 40, 44, 48}));
  for (const char* bad : {"1,", ",1", "1,,2", "1-5:0", "1-5:", "1:2", "5,5", "1-10,10-12",
                          "1-9:2,5", "0-9999999,0", "1;2", "1-2:3:4", "0-9999999"})
    EXPECT_FALSE(parse_frames(bad).ok()) << bad;
  const Result<FrameList> twice = parse_frames("3,1-4");
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.status().message().find("frame 3 is named twice"), std::string::npos)
      << twice.status().message();
  EXPECT_EQ(twice.status().exit_code(), 2);
}

TEST(Frames, FormatsNames) {
  bool pattern = false;
  ASSERT_TRUE(check_frame_pattern("out/f_%04d.png", "-o", pattern).ok());
  EXPECT_TRUE(pattern);
  EXPECT_EQ(format_frame_name("out/f_%04d.png", 7), "out/f_0007.png");
  EXPECT_EQ(format_frame_name("f%d.exr", 12345), "f12345.exr");
  EXPECT_EQ(format_frame_name("f%3d.exr", 5), "f  5.exr");
  EXPECT_EQ(format_frame_name("f%02d.exr", 123), "f123.exr");
  EXPECT_EQ(format_frame_name("100%%_%04d.png", 3), "100%_0003.png");
  ASSERT_TRUE(check_frame_pattern("100%%.png", "-o", pattern).ok());
  EXPECT_FALSE(pattern);
  EXPECT_EQ(format_frame_name("100%%.png", 3), "100%.png");
  for (const char* bad : {"%s.png", "%04d_%04d.png", "%", "a%x", "%0d.png", "%-4d.png", "%10d"})
    EXPECT_FALSE(check_frame_pattern(bad, "-o", pattern).ok()) << bad;
}

TEST(Frames, ShardsCoverEveryFrameExactlyOnce) {
  for (const char* text : {"0", "1-240", "5-11", "1,5,10-20,30-90:3"}) {
    const FrameList list = *parse_frames(text);
    for (int n = 1; n <= 13; ++n) {
      std::vector<int> all;
      for (int i = 0; i < n; ++i) {
        const std::vector<int> f = shard_frames(list, Shard{i, n});
        // contiguous, balanced blocks of the list
        EXPECT_LE(f.size(), static_cast<size_t>(list.count() / n + 1));
        all.insert(all.end(), f.begin(), f.end());
      }
      EXPECT_EQ(all, list.frames) << text << " in " << n;
    }
  }
  for (const char* bad : {"", "2/2", "0/0", "1", "-1/2", "a/b", "0/100001", "1/2/3"})
    EXPECT_FALSE(parse_shard(bad).ok()) << bad;
  EXPECT_TRUE(parse_shard("99999/100000").ok());
}

TEST(Frames, SppAndExposureValues) {
  EXPECT_EQ(*parse_spp("1"), 1);
  EXPECT_EQ(*parse_spp("16"), 16);
  EXPECT_EQ(*parse_spp("256"), 256);
  for (const char* bad : {"0", "2", "3", "257", "-4", "4.0", "x", ""})
    EXPECT_FALSE(parse_spp(bad).ok()) << bad;
  EXPECT_EQ(*parse_exposure("-1.5"), -1.5f);
  EXPECT_EQ(*parse_exposure("+2"), 2.0f);
  for (const char* bad : {"nan", "inf", "-inf", "25", "-24.5", "1e1", "", "1,5", "0x10"})
    EXPECT_FALSE(parse_exposure(bad).ok()) << bad;
}

TEST(Frames, BoxFilterAveragesBlocks) {
  Image im(4, 2);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) im.at(x, y) = glm::vec4(x + 4 * y, 1, 0, 1);
  const Image d = box_downsample(im, 2);
  ASSERT_EQ(d.width, 2);
  ASSERT_EQ(d.height, 1);
  EXPECT_EQ(d.at(0, 0).x, (0 + 1 + 4 + 5) / 4.0f);
  EXPECT_EQ(d.at(1, 0).x, (2 + 3 + 6 + 7) / 4.0f);
  EXPECT_EQ(point_downsample(im, 2).at(1, 0).x, 7.0f);  // sample (1, 1) of the block
}

TEST(FramesCli, NamesEveryFrameFromThePattern) {
  const std::string dir = fresh_dir("names");
  const CliRun r =
      run("render plane --size 32x24 --threads 2 --frames 3-6 -o " + dir +
          "/f_%04d.png --aov depth=" + dir + "/d_%02d.exr --aov uv=" + dir + "/uv_%d.exr");
  ASSERT_EQ(r.code, 0) << r.out;
  for (int f = 3; f <= 6; ++f) {
    EXPECT_TRUE(fs::exists(dir + "/f_000" + std::to_string(f) + ".png")) << f;
    EXPECT_TRUE(fs::exists(dir + "/d_0" + std::to_string(f) + ".exr")) << f;
    EXPECT_TRUE(fs::exists(dir + "/uv_" + std::to_string(f) + ".exr")) << f;
  }
  EXPECT_EQ(files_in(dir), 12u);                   // no temporaries left
  EXPECT_EQ(r.out.find('\r'), std::string::npos);  // no progress bar: stderr is not a terminal
}

TEST(FramesCli, TurntableStartsAtTheStillFrameAndTurns) {
  const std::string dir = fresh_dir("turntable");
  const std::string common = " --size 48x32 --threads 2 ";
  ASSERT_EQ(run("render plane" + common + "-o " + dir + "/still.exr").code, 0);
  const CliRun r = run("render plane" + common + "--frames 0-3 -o " + dir + "/t%d.exr");
  ASSERT_EQ(r.code, 0) << r.out;
  const Image still = read(dir + "/still.exr"), t0 = read(dir + "/t0.exr"),
              t1 = read(dir + "/t1.exr"), t2 = read(dir + "/t2.exr");
  EXPECT_TRUE(same_pixels(still, t0));
  EXPECT_FALSE(same_pixels(t0, t1));
  EXPECT_FALSE(same_pixels(t1, t2));
  // A one-shard split of the same range renders the same frames.
  const CliRun r2 =
      run("render plane" + common + "--frames 0-3 --shard 0/1 -o " + dir + "/u%d.exr");
  ASSERT_EQ(r2.code, 0) << r2.out;
  EXPECT_TRUE(same_pixels(read(dir + "/u1.exr"), t1));
}

TEST(FramesCli, ProgressBarOnlyOnATerminal) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
  const std::string dir = fresh_dir("progress");
  // script(1) runs the command on a pseudo-terminal and copies what it shows.
  const CliRun r =
      run_shell("script -qec '" + std::string(RELIEF_CLI) +
                " render plane --size 16x12 --frames 0-2 -o " + dir + "/p%d.png' /dev/null");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("\r"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("3/3 frames"), std::string::npos) << r.out;
  EXPECT_EQ(files_in(dir), 3u);
}

TEST(FramesCli, ShardsWriteEachFrameOnce) {
  const std::string dir = fresh_dir("shards");
  std::multiset<std::string> written;
  for (int i = 0; i < 3; ++i) {
    const CliRun r = run("render plane --size 16x12 --threads 1 --frames 10-14 --shard " +
                         std::to_string(i) + "/3 -o " + dir + "/s%03d.png");
    ASSERT_EQ(r.code, 0) << r.out;
    for (int f = 10; f <= 14; ++f) {
      const std::string name = dir + "/s0" + std::to_string(f) + ".png";
      if (r.out.find(name + ":") != std::string::npos) written.insert(name);
    }
  }
  EXPECT_EQ(written.size(), 5u);
  for (const std::string& w : written) EXPECT_EQ(written.count(w), 1u) << w;
  EXPECT_EQ(files_in(dir), 5u);
  // More shards than frames: a shard with nothing to do says so and succeeds.
  const CliRun r = run("render plane --size 16x12 --frames 0-1 --shard 5/8 -o " + dir + "/e%d.png");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("no frames"), std::string::npos) << r.out;
}

TEST(FramesCli, BadValuesAreOneLineUsageErrorsWithNothingWritten) {
  const std::string dir = fresh_dir("bad");
  const std::string out = " -o " + dir + "/b%04d.png --size 16x12 ";
  for (const char* flags :
       {"--frames 5-3", "--frames x", "--frames -2", "--frames 1,1", "--frames 1-4:0",
        "--frames 1-2 --shard 2/2", "--frames 1-2 --shard 0/0", "--frames 1-2 --shard a",
        "--shard 0/2", "--spp 0", "--spp 3", "--spp 1000", "--exposure nan", "--exposure 30",
        "--exposure inf", "--exposure x", "--fps 0"}) {
    const CliRun r = run("render plane" + out + flags);
    EXPECT_EQ(r.code, 2) << flags << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << flags << ": " << r.out;
    EXPECT_EQ(files_in(dir), 0u) << flags;
  }
  // 16 x 16 samples of 2000 x 1500 pixels are over the target limit.
  const CliRun big = run("render plane -o " + dir + "/big.png --size 2000x1500 --spp 256");
  EXPECT_EQ(big.code, 2) << big.out;
  EXPECT_EQ(lines(big.out), 1) << big.out;
  EXPECT_NE(big.out.find("--spp"), std::string::npos) << big.out;
  // Several frames need a pattern in every output name.
  for (const std::string& names :
       {"-o " + dir + "/nopattern.png", "-o " + dir + "/p%d.png --aov depth=" + dir + "/d.exr",
        "-o " + dir + "/p%d.png --stats " + dir + "/s.json", "-o " + dir + "/p%s.png"}) {
    const CliRun r = run("render plane --size 16x12 --frames 0-1 " + names);
    EXPECT_EQ(r.code, 2) << names << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << r.out;
    EXPECT_EQ(files_in(dir), 0u) << names;
  }
}

// Renders `relief render ARGS -o DIR/NAME.exr` and reads the image back.
Image render_exr(const std::string& dir, const std::string& args, const std::string& name) {
  const std::string file = dir + "/" + name + ".exr";
  const CliRun r = run("render " + args + " -o " + file);
  EXPECT_EQ(r.code, 0) << r.out;
  return read(file);
}

TEST(FramesCli, SuperSamplingIsTheBoxFilterOfTheLargerFrameForAnyThreadCount) {
  const std::string dir = fresh_dir("spp");
  const std::string common = "pattern --size 40x30 --tile-size 16 ";
  const Image a = render_exr(dir, common + "--spp 4 --threads 1", "a");
  const Image b = render_exr(dir, common + "--spp 4 --threads 2", "b");
  const Image big = render_exr(dir, "pattern --size 80x60 --threads 2", "big");
  const Image one = render_exr(dir, common + "--threads 2", "one");
  EXPECT_EQ(a.width, 40);
  EXPECT_TRUE(same_pixels(a, b));
  EXPECT_TRUE(same_pixels(a, box_downsample(big, 2)));
  EXPECT_FALSE(same_pixels(a, one));
}

TEST(FramesCli, ExposureScalesLinearRadianceExactly) {
  const std::string dir = fresh_dir("exposure");
  const std::string common = "plane --size 40x30 --threads 2 ";
  const Image e0 = render_exr(dir, common, "e0");
  const Image e1 = render_exr(dir, common + "--exposure 1", "e1");
  const Image em = render_exr(dir, common + "--exposure -2.5", "em");
  ASSERT_EQ(e0.pixels.size(), e1.pixels.size());
  ASSERT_EQ(e0.pixels.size(), em.pixels.size());
  const float m = std::exp2(-2.5f);
  size_t lit = 0;
  for (size_t i = 0; i < e0.pixels.size(); ++i) {
    const glm::vec4 p = e0.pixels[i];
    EXPECT_EQ(e1.pixels[i], glm::vec4(glm::vec3(p) * 2.0f, p.a)) << i;
    EXPECT_EQ(em.pixels[i], glm::vec4(glm::vec3(p) * m, p.a)) << i;
    lit += p.r > 0.0f;
  }
  EXPECT_GT(lit, e0.pixels.size() / 2);
}

TEST(FramesCli, AnimatedSceneFramesCarryPoseStatistics) {
  const std::string dir = fresh_dir("bending");
  const CliRun r = run("render bending --size 64x48 --threads 2 --frames 11-12 -o " + dir +
                       "/b%d.png --stats " + dir + "/s%d.json");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("deform"), std::string::npos) << r.out;
  std::ifstream f(dir + "/s12.json");
  const std::string json((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(json.find("\"deformed_vertices\": 1685"), std::string::npos) << json;
  EXPECT_NE(json.find("\"time_s\": 0.5"), std::string::npos) << json;  // frame 12 at 24 fps
  EXPECT_FALSE(same_pixels(read(dir + "/b11.png"), read(dir + "/b12.png")));
}

}  // namespace
}  // namespace relief::cli
