// The self-contained HTML report of a sweep (sweep/sweep.h): machine and command, a Pareto plot
// per field as inline SVG, the gallery of images and heat maps as data: URIs, and every row.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "rasterizer/output_file.h"
#include "scene/image_io.h"
#include "sweep/sweep.h"

namespace relief::sweep {
namespace {

std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v =
        (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
    for (int s = 18; s >= 0; s -= 6) o += k[(v >> s) & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = uint8_t(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= uint8_t(bytes[i + 1]) << 8;
    o += k[(v >> 18) & 63];
    o += k[(v >> 12) & 63];
    o += i + 1 < bytes.size() ? k[(v >> 6) & 63] : '=';
    o += '=';
  }
  return o;
}

// A PNG data: URI of `image`, encoded in memory (`dir` names the report in messages).
Result<std::string> png_uri(const Image& image, const std::string& dir) {
  Result<std::vector<unsigned char>> bytes = encode_image(dir + "/index.html.png", image);
  if (!bytes.ok()) return bytes.status();
  return "data:image/png;base64," + base64(std::string(bytes->begin(), bytes->end()));
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, std::isfinite(v) ? v : 0.0);
  return buf;
}

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

// One point per setting of a field: ns = mean over its views of the median ns per fragment,
// err = the largest p99 hit error over its views (the worst angle).
std::vector<Row> per_setting(const std::vector<Row>& rows, const std::string& field) {
  std::map<std::string, std::pair<Row, int>> acc;
  std::vector<std::string> order;
  for (const Row& r : rows) {
    if (r.field != field) continue;
    auto it = acc.find(r.setting);
    if (it == acc.end()) {
      order.push_back(r.setting);
      Row a = r;
      a.ns_median = 0;
      a.hit_err_p99 = 0;
      it = acc.emplace(r.setting, std::pair{a, 0}).first;
    }
    it->second.first.ns_median += r.ns_median;
    it->second.first.hit_err_p99 = std::max(it->second.first.hit_err_p99, r.hit_err_p99);
    ++it->second.second;
  }
  std::vector<Row> out;
  for (const std::string& s : order) {
    Row a = acc[s].first;
    a.ns_median /= acc[s].second;
    out.push_back(a);
  }
  return out;
}

std::string pareto_svg(const std::vector<Row>& pts, const std::string& field,
                       const std::map<std::string, std::string>& colour) {
  const double W = 640, H = 400, L = 70, R = 20, T = 20, B = 50;
  const double kFloor = 1e-3;  // p99 errors below this (exact: 0) sit on the axis floor
  double x0 = 1e300, x1 = 0, y1 = kFloor * 10;
  for (const Row& r : pts) {
    x0 = std::min(x0, std::max(r.ns_median, 1.0));
    x1 = std::max(x1, std::max(r.ns_median, 1.0));
    y1 = std::max(y1, r.hit_err_p99);
  }
  const double lx0 = std::floor(std::log10(x0)), lx1 = std::max(std::ceil(std::log10(x1)), lx0 + 1);
  const double ly0 = std::log10(kFloor), ly1 = std::max(std::ceil(std::log10(y1)), ly0 + 1);
  auto X = [&](double ns) {
    return L + (std::log10(std::max(ns, 1.0)) - lx0) / (lx1 - lx0) * (W - L - R);
  };
  auto Y = [&](double e) {
    return T + (ly1 - std::log10(std::max(e, kFloor))) / (ly1 - ly0) * (H - T - B);
  };
  std::ostringstream o;
  o << "<svg class=\"pareto\" id=\"pareto-" << html_escape(field)
    << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" viewBox=\"0 0 " << W << " " << H << "\">\n";
  o << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\""
    << H - T - B << "\" fill=\"none\" stroke=\"#888\"/>\n";
  for (double e = lx0; e <= lx1; e += 1)
    o << "<text x=\"" << X(std::pow(10, e)) << "\" y=\"" << H - B + 16
      << "\" font-size=\"11\" text-anchor=\"middle\">" << fmt("%.0f", std::pow(10, e))
      << "</text>\n";
  for (double e = ly0; e <= ly1; e += 1)
    o << "<text x=\"" << L - 6 << "\" y=\"" << Y(std::pow(10, e)) + 4
      << "\" font-size=\"11\" text-anchor=\"end\">" << (e == ly0 ? "&lt;=" : "")
      << fmt("%g", std::pow(10, e)) << "</text>\n";
  o << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12
    << "\" font-size=\"12\" text-anchor=\"middle\">ns per fragment (median, mean over views; "
       "log)</text>\n";
  o << "<text x=\"14\" y=\"" << (T + H - B) / 2
    << "\" font-size=\"12\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << (T + H - B) / 2
    << ")\">p99 hit error, texels (worst view; log)</text>\n";
  const std::vector<size_t> front = pareto_front(pts);
  o << "<polyline class=\"front\" fill=\"none\" stroke=\"#444\" stroke-dasharray=\"4 3\" points=\"";
  for (size_t i : front) o << X(pts[i].ns_median) << "," << Y(pts[i].hit_err_p99) << " ";
  o << "\"/>\n";
  for (const Row& r : pts)
    o << "<circle class=\"point\" cx=\"" << X(r.ns_median) << "\" cy=\"" << Y(r.hit_err_p99)
      << "\" r=\"5\" fill=\"" << colour.at(r.technique) << "\"><title>" << html_escape(r.setting)
      << ": " << fmt("%.0f", r.ns_median) << " ns, p99 " << fmt("%.4g", r.hit_err_p99)
      << " texel</title></circle>\n";
  o << "</svg>\n";
  return o.str();
}

}  // namespace

std::vector<size_t> pareto_front(const std::vector<Row>& rows) {
  std::vector<size_t> idx(rows.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
    return rows[a].ns_median != rows[b].ns_median ? rows[a].ns_median < rows[b].ns_median
                                                  : rows[a].hit_err_p99 < rows[b].hit_err_p99;
  });
  std::vector<size_t> front;
  double best = INFINITY;
  for (size_t i : idx)
    if (rows[i].hit_err_p99 < best) {
      best = rows[i].hit_err_p99;
      front.push_back(i);
    }
  return front;
}

Status write_report(const std::string& dir, const SweepResult& result, const RunInfo& info) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return Status::error(dir + ": cannot create the report folder: " + ec.message());
  std::vector<std::string> fields, techniques;
  for (const Row& r : result.rows) {
    if (std::find(fields.begin(), fields.end(), r.field) == fields.end()) fields.push_back(r.field);
    if (std::find(techniques.begin(), techniques.end(), r.technique) == techniques.end())
      techniques.push_back(r.technique);
  }
  std::map<std::string, std::string> colour;
  for (size_t i = 0; i < techniques.size(); ++i) colour[techniques[i]] = kPalette[i % 10];

  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << "<title>relief bench: accuracy and cost</title>\n<style>\n"
    << "body{font-family:sans-serif;margin:1.5em;max-width:1400px}\n"
    << "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 5px;"
       "text-align:right}td.l,th.l{text-align:left}\n"
    << "img{image-rendering:pixelated;width:160px;display:block}figure{display:inline-block;margin:"
       "4px}"
       "figcaption{font-size:11px}\n</style></head><body>\n";
  h << "<h1>relief bench</h1>\n<p>Machine: " << html_escape(info.machine)
    << "<br>CPU backend: " << html_escape(result.cpu_device);
  if (!result.gl_device.empty()) h << "<br>GL backend: " << html_escape(result.gl_device);
  h << "<br>Command: <code>" << html_escape(info.command) << "</code><br>" << info.options.width
    << " x " << info.options.height << " px, " << info.options.warmup << " warm-up + "
    << info.options.repeats << " timed frames per row; orthographic views at azimuth "
    << kAzimuthDeg << " deg; error against <code>exact</code> on the same fragments.</p>\n";
  for (const std::string& n : result.notes) h << "<p>" << html_escape(n) << "</p>\n";
  h << "<h2>Pareto front: p99 hit error against ns per fragment</h2>\n"
    << "<p>One point per setting: the mean over the views of its median ns per fragment and its "
       "worst p99 hit error over the views. The dashed line joins the settings no other beats on "
       "both.</p>\n<p>";
  for (const std::string& t : techniques)
    h << "<span style=\"color:" << colour[t] << "\">&#9679;</span> " << html_escape(t)
      << " &nbsp; ";
  h << "</p>\n";
  for (const std::string& f : fields)
    h << "<h3>" << html_escape(f) << "</h3>\n"
      << pareto_svg(per_setting(result.rows, f), f, colour);

  if (!result.images.empty()) {
    h << "<h2>Images and error heat maps</h2>\n<p>Shaded result of the fewest-steps setting of "
         "each "
         "technique and its heat map against exact (black: equal; blue, green below 8/255; yellow "
         "to red up to 32/255 and above).</p>\n";
    std::string view;
    for (const RowImages& im : result.images) {
      const Row& r = result.rows.at(im.row);
      const std::string v = r.field + " at " + fmt("%.0f", r.angle) + " deg";
      if (v != view) {
        h << (view.empty() ? "" : "</div>\n") << "<h3>" << html_escape(v) << "</h3><div>\n";
        view = v;
      }
      Result<std::string> c = png_uri(im.color, dir);
      if (!c.ok()) return c.status();
      Result<std::string> e = png_uri(im.heat, dir);
      if (!e.ok()) return e.status();
      h << "<figure><img alt=\"" << html_escape(r.setting) << "\" src=\"" << *c
        << "\"><img alt=\"heat map " << html_escape(r.setting) << "\" src=\"" << *e
        << "\"><figcaption>" << html_escape(r.setting) << ", p99 " << fmt("%.3g", r.hit_err_p99)
        << " texel, PSNR " << fmt("%.1f", r.psnr_db) << " dB</figcaption></figure>\n";
    }
    h << "</div>\n";
  }

  h << "<h2>Rows</h2>\n<table id=\"rows\"><tr>";
  const std::string csv = to_csv(result.rows);
  std::istringstream lines(csv);
  std::string line;
  bool header = true;
  while (std::getline(lines, line)) {
    if (!header) h << "<tr>";
    // the CSV's cells (quoted cells hold no comma here but notes may; split on unquoted commas)
    std::string cell;
    bool quoted = false;
    auto flush = [&] {
      const bool text =
          !cell.empty() && (std::isalpha(static_cast<unsigned char>(cell[0])) || cell[0] == '"');
      h << (header ? "<th" : "<td") << (text ? " class=\"l\">" : ">") << html_escape(cell)
        << (header ? "</th>" : "</td>");
      cell.clear();
    };
    for (char ch : line) {
      if (ch == '"') quoted = !quoted;
      if (ch == ',' && !quoted)
        flush();
      else
        cell += ch;
    }
    flush();
    h << "</tr>\n";
    header = false;
  }
  h << "</table>\n";
  // A self-check the headless test reads: the plot rendered its points.
  h << "<script>\n(function(){var n=document.querySelectorAll('svg.pareto circle.point').length;"
       "document.body.setAttribute('data-plot-points',String(n));})();\n</script>\n";
  h << "</body></html>\n";

  return write_file_atomic(dir + "/index.html", h.str());  // checked writes, fsync, rename
}

}  // namespace relief::sweep
