// `relief bench` as a user meets it (issue 8): the CSV and JSON carry exactly the columns
// docs/accuracy.md documents, the HTML report is one self-contained page that headless Chromium
// loads without console errors and whose plot shows its points, --target-error prints its choice
// and why, and bad input is one line, a non-zero exit and no output file. Tiny sizes throughout.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/cli_run.h"

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The column names of docs/accuracy.md's "## Columns" table (first cell, in backticks).
std::vector<std::string> documented_columns() {
  std::istringstream doc(slurp(std::string(RELIEF_SOURCE_DIR) + "/docs/accuracy.md"));
  std::vector<std::string> cols;
  std::string line;
  bool in_section = false;
  const std::regex cell(R"(^\|\s*`([a-z0-9_]+)`\s*\|)");
  while (std::getline(doc, line)) {
    if (line.rfind("## ", 0) == 0) in_section = line == "## Columns";
    std::smatch m;
    if (in_section && std::regex_search(line, m, cell)) cols.push_back(m[1]);
  }
  return cols;
}

const char* const kSmall =
    "bench --size 24x24 --threads 2 --fields pattern --techniques relief,exact --steps 4,16 "
    "--angles 30,80 --repeats 1 --warmup 0 --no-progress";

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      cells.push_back(cell);
      cell.clear();
    } else {
      cell += c;
    }
  }
  cells.push_back(cell);
  return cells;
}

TEST(BenchCli, CsvAndJsonHaveTheDocumentedColumns) {
  const std::vector<std::string> doc = documented_columns();
  ASSERT_GE(doc.size(), 20u) << "docs/accuracy.md: no ## Columns table";
  const std::string csv = tmp("bench.csv"), json = tmp("bench.json");
  const CliRun r = run(std::string(kSmall) + " --csv " + csv + " --json " + json);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("relief 4+8"), std::string::npos) << r.out;  // the terminal table
  std::istringstream in(slurp(csv));
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(split_csv_line(header), doc);
  int rows = 0;
  while (std::getline(in, line)) {
    EXPECT_EQ(split_csv_line(line).size(), doc.size()) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 2 * 3);  // 2 angles x (relief 4, relief 16, exact)
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j.at("columns").get<std::vector<std::string>>(), doc);
  ASSERT_EQ(j.at("rows").size(), 6u);
  for (const auto& row : j.at("rows")) {
    std::vector<std::string> keys;
    for (const auto& [k, v] : row.items()) keys.push_back(k);
    std::vector<std::string> sorted_doc = doc;
    std::sort(sorted_doc.begin(), sorted_doc.end());
    std::sort(keys.begin(), keys.end());
    EXPECT_EQ(keys, sorted_doc);
  }
  EXPECT_NE(j.at("command").get<std::string>().find("--techniques relief,exact"),
            std::string::npos);
  EXPECT_NE(j.at("machine").get<std::string>().find("cores"), std::string::npos);
}

// Headless Chromium (skipped where it is not installed; scripts/install-deps.sh installs it):
// console messages are logged to stderr, the page's script counts the plot's points into
// data-plot-points. A broken page is the control: its error must be seen.
std::string chromium() {
  for (const char* c : {"chromium", "chromium-browser"}) {
    const CliRun r = run_shell(std::string("command -v ") + c);
    if (r.code == 0) return c;
  }
  return "";
}
CliRun headless(const std::string& browser, const std::string& file, std::string& console) {
  const std::string err = file + ".stderr";
  // braces: run_shell's trailing 2>&1 must not undo the redirection of the browser's stderr
  const CliRun r =
      run_shell("{ timeout 120 " + browser +
                  " --headless --no-sandbox --disable-gpu --enable-logging=stderr "
                  "--v=0 --user-data-dir=" +
                  file + ".profile" + " --dump-dom file://" + file + " 2>" + err + "; }");
  console.clear();
  std::istringstream log(slurp(err));
  std::string line;
  while (std::getline(log, line))
    if (line.find("CONSOLE") != std::string::npos) console += line + "\n";
  return r;
}

TEST(BenchCli, ReportLoadsInHeadlessChromiumAndShowsThePlot) {
  const std::string browser = chromium();
  if (browser.empty()) GTEST_SKIP() << "chromium is not installed";
  const std::string dir = tmp("bench_report");
  std::filesystem::remove_all(dir);
  const CliRun r = run(std::string(kSmall) + " --report " + dir);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string page = dir + "/index.html";
  const std::string html = slurp(page);
  ASSERT_FALSE(html.empty());
  // self-contained: images inline, nothing fetched from elsewhere
  EXPECT_NE(html.find("src=\"data:image/png;base64,"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_NE(html.find("--techniques relief,exact"), std::string::npos);       // the command line
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);  // one file

  std::string console;
  const CliRun ok = headless(browser, page, console);
  ASSERT_EQ(ok.code, 0) << ok.out;
  EXPECT_EQ(console, "") << "console messages while loading the report";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(ok.out, m, std::regex("data-plot-points=\"([0-9]+)\"")))
      << ok.out.substr(0, 500);
  EXPECT_EQ(std::stoi(m[1]), 3);  // one point per setting of the one field
  EXPECT_NE(ok.out.find("<svg class=\"pareto\""), std::string::npos);

  // the control: a page with a script error is caught
  const std::string bad = tmp("bench_bad.html");
  std::ofstream(bad) << "<html><body><script>no_such_function();</script></body></html>";
  headless(browser, bad, console);
  EXPECT_NE(console.find("no_such_function"), std::string::npos) << console;
}

TEST(BenchCli, TargetErrorPrintsTheChoiceAndWhy) {
  const CliRun r =
      run("bench --target-error 2 --scene plane --size 32x18 --threads 2 --techniques relief,exact "
          "--steps 8,32 --repeats 1 --warmup 0 --no-progress");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("material 'bricks': view angles"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("chose"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ns/frag"), std::string::npos) << r.out;
}

TEST(BenchCli, BadInputIsOneLineAndNoOutput) {
  const std::string csv = tmp("bench_bad.csv");
  std::filesystem::remove(csv);  // a leftover of an earlier run would pass for output
  std::filesystem::remove(csv);
  struct Case {
    std::string args;
    int code;
    const char* says;
  };
  const Case cases[] = {
      {"--angles 30,95", 2, "--angles"},
      {"--angles x", 2, "--angles"},
      {"--backend vulkan", 2, "--backend"},
      {"--techniques relief,nope", 2, "nope"},
      {"--fields marble", 2, "marble"},
      {"--depth /no/such/file.png", 1, "/no/such/file.png"},
      {"--target-error -1", 2, "--target-error"},
      {"--repeats 0", 2, "--repeats"},
  };
  for (const Case& c : cases) {
    const CliRun r = run("bench --size 16x16 --no-progress --csv " + csv + " " + c.args);
    EXPECT_EQ(r.code, c.code) << c.args << ": " << r.out;
    EXPECT_EQ(lines(r.out), 1) << c.args << ": " << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << ": " << r.out;
    EXPECT_FALSE(std::filesystem::exists(csv)) << c.args;
  }
  const CliRun r = run("bench --size 16x16 --csv /no/such/dir/x.csv");
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_EQ(lines(r.out), 1) << r.out;
}

}  // namespace
