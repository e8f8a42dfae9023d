// `relief bench` as a user meets it (issues 8, 22): the CSV and JSON carry exactly the columns
// docs/accuracy.md documents (and the JSON the build metadata), the HTML report is one
// self-contained page that headless Chromium loads without console errors, with per-angle plots,
// their labels and legends, a sortable table that sorts, people's numbers, and a screenshot that
// is a real picture; --target-error prints its choice and why, and bad input is one line, a
// non-zero exit and no output file. Tiny sizes throughout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/apps/cli_run.h"

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
  // build metadata: version, commit, SIMD path, date, CPU
  const auto& build = j.at("build");
  for (const char* k : {"version", "commit", "simd", "date", "cpu"}) {
    ASSERT_TRUE(build.contains(k)) << k;
    EXPECT_FALSE(build.at(k).get<std::string>().empty()) << k;
  }
  EXPECT_NE(build.at("cpu").get<std::string>().find("cores"), std::string::npos);
  EXPECT_EQ(j.at("rows").at(0).at("lod"), "level0");
}

TEST(BenchCli, LodBothAndGeneratedFields) {
  const std::string csv = tmp("bench_lod.csv");
  const CliRun r =
      run("bench --size 16x16 --threads 2 --fields thin,spikes,ramp --techniques relief,exact "
          "--steps 8 --angles 45 --repeats 1 --warmup 0 --no-progress --lod both --csv " +
          csv);
  ASSERT_EQ(r.code, 0) << r.out;
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = split_csv_line(line);
  const size_t lod = std::find(header.begin(), header.end(), "lod") - header.begin();
  ASSERT_LT(lod, header.size());
  std::map<std::string, int> per_lod;
  std::set<std::string> fields;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    ++per_lod[cells.at(lod)];
    fields.insert(cells.at(0));
  }
  EXPECT_EQ(per_lod["level0"], 3 * 2);
  EXPECT_EQ(per_lod["as-rendered"], 3 * 2);
  EXPECT_EQ(fields, (std::set<std::string>{"thin", "spikes", "ramp"}));
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
// `fragment`: appended to the page's URL ("#sort=..."); the profile and log sit beside `file`.
CliRun headless(const std::string& browser, const std::string& file, std::string& console,
                const std::string& fragment = "") {
  const std::string err = file + ".stderr";
  // braces: run_shell's trailing 2>&1 must not undo the redirection of the browser's stderr
  const CliRun r = run_shell("{ timeout 120 " + browser +
                             " --headless --no-sandbox --disable-gpu --enable-logging=stderr "
                             "--v=0 --user-data-dir=" +
                             file + ".profile" + " --dump-dom 'file://" + file + fragment + "' 2>" +
                             err + "; }");
  console.clear();
  std::istringstream log(slurp(err));
  std::string line;
  while (std::getline(log, line))
    if (line.find("CONSOLE") != std::string::npos) console += line + "\n";
  return r;
}

// A headless screenshot of `url` (PNG, width x height), as a person would look at the page.
CliRun screenshot(const std::string& browser, const std::string& url, const std::string& png,
                  int width, int height) {
  return run_shell(
      "{ timeout 120 " + browser +
      " --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" + png +
      ".profile --window-size=" + std::to_string(width) + "," + std::to_string(height) +
      " --screenshot=" + png + " '" + url + "' 2>/dev/null; }");
}

// The attribute the page's script set on <body> (-1 when missing).
int body_count(const std::string& dom, const std::string& attr) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex(attr + "=\"([0-9]+)\""))) return -1;
  return std::stoi(m[1]);
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
  // per angle (30, 80) a mean and a p99 plot, each with one point per setting (relief 4+8,
  // relief 16+8, exact), the step label of each relief point, and a legend
  EXPECT_EQ(body_count(ok.out, "data-plots"), 2 * 2) << ok.out.substr(0, 500);
  EXPECT_EQ(body_count(ok.out, "data-plot-points"), 2 * 2 * 3);
  EXPECT_EQ(body_count(ok.out, "data-step-labels"), 2 * 2 * 2);
  EXPECT_EQ(body_count(ok.out, "data-legends"), 2 * 2);
  EXPECT_EQ(body_count(ok.out, "data-table-rows"), 2 * 3);
  EXPECT_NE(ok.out.find("<svg class=\"pareto\""), std::string::npos);
  for (const char* label : {">4+8</text>", ">16+8</text>", "ns per fragment (median; log)",
                            "p99 hit error, texels (log)", "mean hit error, texels (log)",
                            ">relief</text>", ">exact</text>"})
    EXPECT_NE(ok.out.find(label), std::string::npos) << label;
  // the tables: angle x setting, build metadata; image strips for every setting
  EXPECT_NE(html.find("<h3>air fraction"), std::string::npos);
  EXPECT_NE(html.find("<th class=\"l\">commit</th>"), std::string::npos);
  EXPECT_NE(html.find("<th class=\"l\">simd</th>"), std::string::npos);
  size_t heat = 0;
  for (size_t p = html.find("alt=\"heat map "); p != std::string::npos;
       p = html.find("alt=\"heat map ", p + 1))
    ++heat;
  EXPECT_EQ(heat, 2u * 3u);  // every row's heat map
  // numbers for people: no exponents, GL not run reads n/a, never -1
  const size_t rows_at = html.find("<table id=\"rows\"");
  ASSERT_NE(rows_at, std::string::npos);
  const std::string rows_html = html.substr(rows_at, html.find("</table>", rows_at) - rows_at);
  EXPECT_FALSE(std::regex_search(rows_html, std::regex(">-?[0-9.]+e[-+][0-9]+<"))) << rows_html;
  EXPECT_EQ(rows_html.find(">-1<"), std::string::npos);
  EXPECT_NE(rows_html.find(">n/a<"), std::string::npos);
  // the wide table scrolls inside its box
  EXPECT_NE(html.find("<div class=\"scroll\"><table id=\"rows\""), std::string::npos);

  // sorting: #sort=hit_err_p99_texels puts the exact rows (error 0) first
  std::string console_sorted;
  const CliRun sorted = headless(browser, page, console_sorted, "#sort=hit_err_p99_texels");
  ASSERT_EQ(sorted.code, 0) << sorted.out;
  EXPECT_EQ(console_sorted, "");
  EXPECT_NE(sorted.out.find("data-sorted-by=\"hit_err_p99_texels\""), std::string::npos);
  const size_t body = sorted.out.find("<tbody>", sorted.out.find("id=\"rows\""));
  ASSERT_NE(body, std::string::npos);
  const std::string first_row = sorted.out.substr(body, sorted.out.find("</tr>", body) - body);
  EXPECT_NE(first_row.find(">exact<"), std::string::npos) << first_row;

  // a screenshot a person would look at: a PNG of the page, not blank (the plots' colours)
  const std::string png = dir + ".png";
  std::filesystem::remove(png);
  const CliRun shot = screenshot(browser, "file://" + page, png, 1300, 1600);
  ASSERT_EQ(shot.code, 0) << shot.out;
  const std::string bytes = slurp(png);
  ASSERT_GT(bytes.size(), 20000u) << "screenshot too small to hold the plots";
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  RecordProperty("screenshot", png);

  // the control: a page with a script error is caught
  const std::string bad = tmp("bench_bad.html");
  std::ofstream(bad) << "<html><body><script>no_such_function();</script></body></html>";
  headless(browser, bad, console);
  EXPECT_NE(console.find("no_such_function"), std::string::npos) << console;
}

// --backend cpu,gl: the GL series beside CPU, hollow markers at the GLSL twin's time; GL ns in
// the tables. Skipped where the CLI cannot render with GL (cli_gl_missing says why).
TEST(BenchCli, ReportShowsTheGlSeriesBesideCpu) {
  if (const std::string why = cli_gl_missing(); !why.empty()) GTEST_SKIP() << why;
  const std::string dir = tmp("bench_report_gl");
  std::filesystem::remove_all(dir);
  const CliRun r =
      run("bench --backend cpu,gl --size 16x16 --threads 2 --fields pattern --techniques relief "
          "--steps 8 --angles 45 --repeats 1 --warmup 0 --no-progress --report " +
          dir);
  ASSERT_EQ(r.code, 0) << r.out;
  if (r.out.find("no GL context") != std::string::npos) GTEST_SKIP() << r.out;
  // the second yardstick beside the rows: the paper's appendix shader, one row per view
  EXPECT_NE(r.out.find("appendix yardstick"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\npattern    45"), std::string::npos) << r.out;
  const std::string html = slurp(dir + "/index.html");
  EXPECT_NE(html.find("<h2 id=\"appendix\">Appendix yardstick</h2>"), std::string::npos);
  size_t hollow = 0;
  for (size_t p = html.find("class=\"gl-point\""); p != std::string::npos;
       p = html.find("class=\"gl-point\"", p + 1))
    ++hollow;
  EXPECT_EQ(hollow, 2u);  // one setting, mean and p99 plots
  EXPECT_NE(html.find("hollow: GL time"), std::string::npos);
  EXPECT_NE(html.find("<h3>ns per fragment, GL"), std::string::npos);
  EXPECT_EQ(html.find("GL backend</th><td class=\"l\">n/a"), std::string::npos);
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
      {"--fields marble", 2, "thin, spikes, ramp"},
      {"--lod sideways", 2, "--lod"},
      {"--binary-steps 99", 2, "--binary-steps"},
      {"--lod both --target-error 1", 2, "--lod"},
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
