// Sweep output (sweep/sweep.h): the documented columns as CSV, JSON and a terminal table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "sweep/sweep.h"

namespace relief::sweep {
namespace {

// One column: its name and how a row gives its value (a number, or text when `text` is set).
struct Column {
  const char* name;
  std::function<double(const Row&)> number;
  std::function<std::string(const Row&)> text;
};

const std::vector<Column>& column_table() {
  static const std::vector<Column> cols = {
      {"field", nullptr, [](const Row& r) { return r.field; }},
      {"technique", nullptr, [](const Row& r) { return r.technique; }},
      {"setting", nullptr, [](const Row& r) { return r.setting; }},
      {"steps", [](const Row& r) { return r.steps; }, nullptr},
      {"angle_deg", [](const Row& r) { return r.angle; }, nullptr},
      {"lod", nullptr, [](const Row& r) { return r.lod; }},
      {"fragments", [](const Row& r) { return static_cast<double>(r.fragments); }, nullptr},
      {"ns_per_fragment", [](const Row& r) { return r.ns_median; }, nullptr},
      {"ns_min", [](const Row& r) { return r.ns_min; }, nullptr},
      {"ns_max", [](const Row& r) { return r.ns_max; }, nullptr},
      {"gl_ns_per_fragment", [](const Row& r) { return r.gl_ns_median; }, nullptr},
      {"gl_ns_min", [](const Row& r) { return r.gl_ns_min; }, nullptr},
      {"gl_ns_max", [](const Row& r) { return r.gl_ns_max; }, nullptr},
      {"cpu_gl_ratio", [](const Row& r) { return r.cpu_gl_ratio; }, nullptr},
      {"fetches_mean", [](const Row& r) { return r.fetches_mean; }, nullptr},
      {"fetches_p99", [](const Row& r) { return r.fetches_p99; }, nullptr},
      {"steps_mean", [](const Row& r) { return r.steps_mean; }, nullptr},
      {"steps_p99", [](const Row& r) { return r.steps_p99; }, nullptr},
      {"hit_err_mean_texels", [](const Row& r) { return r.hit_err_mean; }, nullptr},
      {"hit_err_p99_texels", [](const Row& r) { return r.hit_err_p99; }, nullptr},
      {"hit_err_over1_frac", [](const Row& r) { return r.hit_err_over1_frac; }, nullptr},
      {"depth_err_mean", [](const Row& r) { return r.depth_err_mean; }, nullptr},
      {"depth_err_p99", [](const Row& r) { return r.depth_err_p99; }, nullptr},
      {"wrong_layer_frac", [](const Row& r) { return r.wrong_layer_frac; }, nullptr},
      {"air_frac", [](const Row& r) { return r.air_frac; }, nullptr},
      {"below_frac", [](const Row& r) { return r.below_frac; }, nullptr},
      {"wrong_occlusion_frac", [](const Row& r) { return r.wrong_occlusion_frac; }, nullptr},
      {"image_rmse", [](const Row& r) { return r.rmse; }, nullptr},
      {"image_psnr_db", [](const Row& r) { return r.psnr_db; }, nullptr},
      {"shadow_compared", [](const Row& r) { return static_cast<double>(r.shadow_compared); },
       nullptr},
      {"shadow_err", [](const Row& r) { return r.shadow_err; }, nullptr},
      {"shadow_ray_err", [](const Row& r) { return r.shadow_ray_err; }, nullptr},
      {"gl_note", nullptr, [](const Row& r) { return r.gl_note; }},
  };
  return cols;
}

std::string csv_quote(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", std::isfinite(v) ? v : 0.0);
  return buf;
}

std::string read_first_line_with(const char* path, const char* key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const size_t c = line.find(':');
      return c == std::string::npos ? line : line.substr(line.find_first_not_of(" \t", c + 1));
    }
  return "";
}

}  // namespace

const std::vector<std::string>& columns() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const Column& c : column_table()) n.push_back(c.name);
    return n;
  }();
  return names;
}

std::string to_csv(const std::vector<Row>& rows) {
  std::ostringstream o;
  const auto& cols = column_table();
  for (size_t i = 0; i < cols.size(); ++i) o << (i ? "," : "") << cols[i].name;
  o << "\n";
  for (const Row& r : rows) {
    for (size_t i = 0; i < cols.size(); ++i)
      o << (i ? "," : "")
        << (cols[i].text ? csv_quote(cols[i].text(r)) : number(cols[i].number(r)));
    o << "\n";
  }
  return o.str();
}

std::string to_json(const SweepResult& result, const RunInfo& info) {
  nlohmann::json j;
  j["command"] = info.command;
  j["machine"] = info.machine;
  j["cpu_device"] = result.cpu_device;
  j["gl_device"] = result.gl_device;
  j["options"] = {{"width", info.options.width},     {"height", info.options.height},
                  {"threads", info.options.threads}, {"angles_deg", info.options.angles},
                  {"warmup", info.options.warmup},   {"repeats", info.options.repeats},
                  {"lods", info.options.lods},       {"azimuth_deg", kAzimuthDeg}};
  j["build"] = nlohmann::json::object();
  for (const auto& [k, v] : info.build) j["build"][k] = v;
  j["columns"] = columns();
  j["rows"] = nlohmann::json::array();
  for (const Row& r : result.rows) {
    nlohmann::json o;
    for (const Column& c : column_table()) {
      if (c.text)
        o[c.name] = c.text(r);
      else
        o[c.name] = std::isfinite(c.number(r)) ? c.number(r) : 0.0;
    }
    j["rows"].push_back(o);
  }
  j["appendix"] = nlohmann::json::array();
  for (const AppendixRow& a : result.appendix)
    j["appendix"].push_back({{"field", a.field},
                             {"angle_deg", a.angle},
                             {"linear_steps", kAppendixLinearSteps},
                             {"binary_steps", kAppendixBinarySteps},
                             {"fragments", a.fragments},
                             {"cpu_ns_per_fragment", a.cpu_ns_median},
                             {"cpu_ns_min", a.cpu_ns_min},
                             {"cpu_ns_max", a.cpu_ns_max},
                             {"gl_ns_per_fragment", a.gl_ns_median},
                             {"gl_ns_min", a.gl_ns_min},
                             {"gl_ns_max", a.gl_ns_max},
                             {"speedup", a.speedup},
                             {"same_hit_frac", a.same_hit_frac},
                             {"note", a.note}});
  j["notes"] = result.notes;
  return j.dump(1) + "\n";
}

std::string format_table(const std::vector<Row>& rows) {
  bool gl = false, lods = false;
  for (const Row& r : rows) {
    gl |= r.gl_ns_median >= 0 || !r.gl_note.empty();
    lods |= r.lod != kLodLevel0;
  }
  std::ostringstream o;
  char buf[512];
  int fw = 5, sw = 7;  // field and setting columns as wide as their longest entry
  for (const Row& r : rows) {
    fw = std::max(fw, static_cast<int>(r.field.size()));
    sw = std::max(sw, static_cast<int>(r.setting.size()));
  }
  std::snprintf(buf, sizeof buf,
                "%-*s %-*s %5s%s %8s %15s %7s %7s %7s %7s %8s %8s %7s %6s %6s %6s %6s", fw, "field",
                sw, "setting", "angle", lods ? "  lod        " : "", "ns/frag", "(min-max)",
                "fetch", "f.p99", "steps", "s.p99", "err mean", "err p99", "depth99", "wrong",
                "air", "psnr", "shadow");
  o << buf;
  if (gl) o << "   gl ns/frag  cpu/gl";
  o << "\n";
  for (const Row& r : rows) {
    char range[64];
    std::snprintf(range, sizeof range, "(%.0f-%.0f)", r.ns_min, r.ns_max);
    char lod[32] = "";
    if (lods) std::snprintf(lod, sizeof lod, "  %-11s", r.lod.c_str());
    std::snprintf(buf, sizeof buf,
                  "%-*s %-*s %5.0f%s %8.0f %15s %7.2f %7.0f %7.2f %7.0f %8.4f %8.4f %7.4f %6.4f "
                  "%6.4f %6.1f %6.4f",
                  fw, r.field.c_str(), sw, r.setting.c_str(), r.angle, lod, r.ns_median, range,
                  r.fetches_mean, r.fetches_p99, r.steps_mean, r.steps_p99, r.hit_err_mean,
                  r.hit_err_p99, r.depth_err_p99, r.wrong_layer_frac, r.air_frac, r.psnr_db,
                  r.shadow_err);
    o << buf;
    if (gl) {
      if (r.gl_ns_median >= 0) {
        std::snprintf(buf, sizeof buf, "   %10.0f  %6.2f", r.gl_ns_median, r.cpu_gl_ratio);
        o << buf;
      } else {
        o << "   " << (r.gl_note.empty() ? "-" : "skipped");
      }
    }
    o << "\n";
  }
  return o.str();
}

std::string format_appendix_table(const std::vector<AppendixRow>& rows) {
  if (rows.empty()) return "";
  std::ostringstream o;
  char buf[256];
  int fw = 5;
  for (const AppendixRow& r : rows) fw = std::max(fw, static_cast<int>(r.field.size()));
  std::snprintf(buf, sizeof buf,
                "appendix yardstick: the relief paper's appendix shader on gl (%d+%d, textureLod "
                "0, diffuse only) against cpu relief %d+%d lod=zero, no self-shadow, no depth "
                "write\n",
                kAppendixLinearSteps, kAppendixBinarySteps, kAppendixLinearSteps,
                kAppendixBinarySteps);
  o << buf;
  std::snprintf(buf, sizeof buf, "%-*s %5s %8s %15s %11s %15s %8s %9s\n", fw, "field", "angle",
                "cpu ns", "(min-max)", "appendix ns", "(min-max)", "gl/cpu", "same hit");
  o << buf;
  for (const AppendixRow& r : rows) {
    char cr[64], gr[64] = "";
    std::snprintf(cr, sizeof cr, "(%.0f-%.0f)", r.cpu_ns_min, r.cpu_ns_max);
    if (r.gl_ns_median >= 0) {
      std::snprintf(gr, sizeof gr, "(%.0f-%.0f)", r.gl_ns_min, r.gl_ns_max);
      std::snprintf(buf, sizeof buf, "%-*s %5.0f %8.1f %15s %11.1f %15s %8.2f %9.4f\n", fw,
                    r.field.c_str(), r.angle, r.cpu_ns_median, cr, r.gl_ns_median, gr, r.speedup,
                    r.same_hit_frac);
    } else {
      std::snprintf(buf, sizeof buf, "%-*s %5.0f %8.1f %15s %11s\n", fw, r.field.c_str(), r.angle,
                    r.cpu_ns_median, cr, "skipped");
    }
    o << buf;
  }
  return o.str();
}

std::string format_number(double v) {
  if (!std::isfinite(v)) return "n/a";
  if (v == 0.0) return "0";
  const double a = std::fabs(v);
  if (a < 1e-6) return v < 0 ? "-<1e-6" : "<1e-6";
  char buf[48];
  if (a >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
  }
  if (v == std::floor(v)) {  // whole numbers (counts, steps, angles) as they are
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  // fixed notation with 3 significant digits (at least, for whole numbers: 12345 stays 12345)
  const int magnitude = static_cast<int>(std::floor(std::log10(a)));
  const int decimals = std::max(0, 2 - magnitude);
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  // rounding may carry into a new digit (9.996 -> "10.00"): drop the extra decimal
  const double back = std::fabs(std::strtod(buf, nullptr));
  if (decimals > 0 && back >= std::pow(10.0, magnitude + 1))
    std::snprintf(buf, sizeof buf, "%.*f", decimals - 1, v);
  return buf;
}

std::string machine_description() {
  std::string cpu = read_first_line_with("/proc/cpuinfo", "model name");
  if (cpu.empty()) cpu = "unknown CPU";
  std::string d = cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " cores";
  std::ifstream load("/proc/loadavg");
  double a = 0, b = 0, c = 0;
  if (load >> a >> b >> c) {
    char buf[96];
    std::snprintf(buf, sizeof buf, ", load average %.2f %.2f %.2f", a, b, c);
    d += buf;
  }
  return d;
}

}  // namespace relief::sweep
