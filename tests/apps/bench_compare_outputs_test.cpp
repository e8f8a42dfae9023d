// `relief bench` (--csv, --json, --report) and `relief compare --heatmap` check their outputs
// before any work, like `relief render` (issue 20, defects 6 and 9): a folder that does not
// exist, a file named twice or an unknown image extension fails at once with one line, and
// nothing is written.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/apps/cli_run.h"

namespace {

namespace fs = std::filesystem;

// Runs `relief ARGS` under a timeout; returns the result and the seconds it took.
CliRun timed(const std::string& args, double& seconds) {
  const auto t0 = std::chrono::steady_clock::now();
  CliRun r = run_shell("timeout 60 " + std::string(RELIEF_CLI) + " " + args);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void expect_one_error_line(const CliRun& r, const std::string& what) {
  EXPECT_EQ(lines(r.out), 1) << r.out;
  EXPECT_EQ(r.out.rfind("relief: ", 0), 0u) << r.out;
  EXPECT_NE(r.out.find(what), std::string::npos) << r.out;
}

TEST(OutputsChecked, BenchRefusesBadOutputsBeforeTheSweep) {
  const fs::path dir = relief::test::fresh_test_dir("relief_bench_outputs");
  const std::string d = dir.string();
  const std::string sweep = "bench --quick --size 64x48 --techniques relief --no-progress";
  double s = 0;
  CliRun r = timed(sweep + " --csv " + d + "/nodir/a.csv", s);
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_error_line(r, d + "/nodir/a.csv: directory does not exist");
  EXPECT_LT(s, 5.0);
  r = timed(sweep + " --csv " + d + "/a.csv --json " + d + "/./a.csv", s);
  EXPECT_EQ(r.code, 2) << r.out;
  expect_one_error_line(r, "is the same file as --csv");
  std::ofstream(dir / "file") << "x";
  r = timed(sweep + " --report " + d + "/file", s);
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_error_line(r, "--report: " + d + "/file exists and is not a folder");
  EXPECT_FALSE(fs::exists(dir / "a.csv"));
  fs::remove_all(dir);
}

TEST(OutputsChecked, CompareRefusesABadHeatmapBeforeReading) {
  const fs::path dir = relief::test::fresh_test_dir("relief_compare_outputs");
  const std::string d = dir.string();
  // The inputs do not exist: a bad heatmap path is reported first, as the first thing checked.
  CliRun r = run("compare " + d + "/a.png " + d + "/b.png --heatmap " + d + "/nodir/h.png");
  EXPECT_EQ(r.code, 1) << r.out;
  expect_one_error_line(r, d + "/nodir/h.png: directory does not exist");
  r = run("compare " + d + "/a.png " + d + "/b.png --heatmap " + d + "/h.xyz");
  EXPECT_EQ(r.code, 2) << r.out;
  expect_one_error_line(r, "unknown image extension");
  fs::remove_all(dir);
}

}  // namespace
