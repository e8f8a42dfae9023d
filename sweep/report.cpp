// The self-contained HTML report of a sweep (sweep/sweep.h): build metadata, machine and command,
// per-view Pareto plots as inline SVG, angle x setting tables, image and heat-map strips as data:
// URIs, and every row in a sortable table.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
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
std::string num(double v) {
  return html_escape(format_number(v));
}
std::string gl_num(double v) {
  return v < 0 ? std::string("n/a") : num(v);
}

const char* const kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

// The setting's label without its technique name: "16+8" of "relief 16+8"; empty for none.
std::string step_label(const Row& r) {
  if (r.setting.rfind(r.technique + " ", 0) == 0) return r.setting.substr(r.technique.size() + 1);
  return r.steps > 0 ? std::to_string(r.steps) : "";
}

std::string view_id(const std::string& field, const std::string& lod, double angle) {
  std::string id = field + "-" + lod + "-" + fmt("%.0f", angle);
  for (char& c : id)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
  return id;
}

// The error a plot shows of a row: p99 or mean hit error.
double plot_error(const Row& r, bool p99) {
  return p99 ? r.hit_err_p99 : r.hit_err_mean;
}

// The frame of a Pareto plot (pixels) and its log axes: decades lx0..lx1 of ns per fragment,
// ly0..ly1 of error, errors below floor_v drawn on the floor.
struct PlotAxes {
  static constexpr double W = 560, H = 330, L = 62, R = 150, T = 24, B = 46;
  double lx0, lx1, ly0, ly1, floor_v;
  double X(double ns) const {
    return L + (std::log10(std::max(ns, 1e-30)) - lx0) / (lx1 - lx0) * (W - L - R);
  }
  double Y(double e) const {
    return T + (ly1 - std::log10(std::max(e, floor_v))) / (ly1 - ly0) * (H - T - B);
  }
};

// The axes that hold every point of `pts`: CPU and GL times, non-zero errors.
PlotAxes plot_axes(const std::vector<const Row*>& pts, bool p99) {
  double x0 = 1e300, x1 = 0, ymin = 1e300, ymax = 0;
  for (const Row* r : pts) {
    for (double ns : {r->ns_median, r->gl_ns_median}) {
      if (!(ns > 0)) continue;
      x0 = std::min(x0, ns);
      x1 = std::max(x1, ns);
    }
    const double e = plot_error(*r, p99);
    if (e > 0) ymin = std::min(ymin, e), ymax = std::max(ymax, e);
  }
  if (!(x1 > 0)) x0 = 1, x1 = 10;
  if (!(ymax > 0)) ymin = 1e-3, ymax = 1e-2;
  PlotAxes a;
  a.lx0 = std::floor(std::log10(x0));
  a.lx1 = std::max(std::ceil(std::log10(x1)), a.lx0 + 1);
  // the floor: one decade under the smallest non-zero error, not below 1e-5
  a.ly0 = std::max(std::floor(std::log10(ymin)) - 1, -5.0);
  a.ly1 = std::max(std::ceil(std::log10(ymax)), a.ly0 + 1);
  a.floor_v = std::pow(10.0, a.ly0);
  return a;
}

// The <svg> element's opening, the plot's frame and title.
void svg_frame(std::ostringstream& o, bool p99, const std::string& id) {
  using A = PlotAxes;
  o << "<svg class=\"pareto\" id=\"pareto-" << html_escape(id) << (p99 ? "-p99" : "-mean")
    << "\" data-metric=\"" << (p99 ? "p99" : "mean")
    << "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" << A::W << "\" height=\"" << A::H
    << "\" viewBox=\"0 0 " << A::W << " " << A::H << "\">\n";
  o << "<rect x=\"" << A::L << "\" y=\"" << A::T << "\" width=\"" << A::W - A::L - A::R
    << "\" height=\"" << A::H - A::T - A::B << "\" fill=\"#fff\" stroke=\"#888\"/>\n";
  o << "<text class=\"title\" x=\"" << (A::L + A::W - A::R) / 2 << "\" y=\"15\" font-size=\"12\" "
    << "text-anchor=\"middle\" font-weight=\"bold\">" << (p99 ? "p99" : "mean")
    << " hit error</text>\n";
}

// Grid lines at every decade, their values, and the axis labels.
void svg_axes(std::ostringstream& o, const PlotAxes& a, bool p99) {
  using A = PlotAxes;
  for (double e = a.lx0; e <= a.lx1; e += 1) {
    const double x = a.X(std::pow(10, e));
    o << "<line x1=\"" << x << "\" x2=\"" << x << "\" y1=\"" << A::T << "\" y2=\"" << A::H - A::B
      << "\" stroke=\"#eee\"/><text x=\"" << x << "\" y=\"" << A::H - A::B + 14
      << "\" font-size=\"10\" text-anchor=\"middle\">" << fmt("%.0f", std::pow(10, e))
      << "</text>\n";
  }
  for (double e = a.ly0; e <= a.ly1; e += 1) {
    const double y = a.Y(std::pow(10, e));
    o << "<line x1=\"" << A::L << "\" x2=\"" << A::W - A::R << "\" y1=\"" << y << "\" y2=\"" << y
      << "\" stroke=\"#eee\"/><text x=\"" << A::L - 5 << "\" y=\"" << y + 4
      << "\" font-size=\"10\" text-anchor=\"end\">"
      << (e == a.ly0 ? std::string("0, &lt;") : std::string()) << fmt("%g", std::pow(10, e))
      << "</text>\n";
  }
  o << "<text class=\"xlabel\" x=\"" << (A::L + A::W - A::R) / 2 << "\" y=\"" << A::H - 10
    << "\" font-size=\"11\" text-anchor=\"middle\">ns per fragment (median; log)</text>\n";
  o << "<text class=\"ylabel\" x=\"13\" y=\"" << (A::T + A::H - A::B) / 2
    << "\" font-size=\"11\" text-anchor=\"middle\" transform=\"rotate(-90 13 "
    << (A::T + A::H - A::B) / 2 << ")\">" << (p99 ? "p99" : "mean")
    << " hit error, texels (log)</text>\n";
}

// The Pareto front of the CPU points (on this metric), dashed.
void svg_front(std::ostringstream& o, const PlotAxes& a, const std::vector<const Row*>& pts,
               bool p99) {
  std::vector<Row> flat;
  for (const Row* r : pts) {
    Row c = *r;
    c.hit_err_p99 = plot_error(*r, p99);
    flat.push_back(c);
  }
  const std::vector<size_t> front = pareto_front(flat);
  o << "<polyline class=\"front\" fill=\"none\" stroke=\"#444\" stroke-dasharray=\"4 3\" points=\"";
  for (size_t i : front) o << a.X(flat[i].ns_median) << "," << a.Y(flat[i].hit_err_p99) << " ";
  o << "\"/>\n";
}

// One disc per setting (CPU time), its step label, and a hollow circle at its GL time.
void svg_points(std::ostringstream& o, const PlotAxes& a, const std::vector<const Row*>& pts,
                bool p99, const std::map<std::string, std::string>& colour) {
  for (const Row* r : pts) {
    const std::string c = colour.at(r->technique);
    const std::string tip = html_escape(r->setting) + ": " + num(r->ns_median) + " ns, " +
                            (p99 ? "p99 " : "mean ") + num(plot_error(*r, p99)) + " texel";
    const double x = a.X(r->ns_median), y = a.Y(plot_error(*r, p99));
    o << "<circle class=\"point\" cx=\"" << x << "\" cy=\"" << y << "\" r=\"4.5\" fill=\"" << c
      << "\"><title>" << tip << "</title></circle>\n";
    const std::string lbl = step_label(*r);
    if (!lbl.empty())
      o << "<text class=\"steps\" x=\"" << x + 6 << "\" y=\"" << y - 5
        << "\" font-size=\"9\" fill=\"" << c << "\">" << html_escape(lbl) << "</text>\n";
    if (r->gl_ns_median > 0)
      o << "<circle class=\"gl-point\" cx=\"" << a.X(r->gl_ns_median) << "\" cy=\"" << y
        << "\" r=\"4.5\" fill=\"none\" stroke=\"" << c << "\" stroke-width=\"1.5\"><title>"
        << html_escape(r->setting) << " on GL: " << num(r->gl_ns_median)
        << " ns</title></circle>\n";
  }
}

// The legend: the techniques that have points here, and the hollow marker when any ran on GL.
void svg_legend(std::ostringstream& o, const std::vector<const Row*>& pts,
                const std::vector<std::string>& techniques,
                const std::map<std::string, std::string>& colour) {
  using A = PlotAxes;
  const bool gl =
      std::any_of(pts.begin(), pts.end(), [](const Row* r) { return r->gl_ns_median > 0; });
  double ly = A::T + 8;
  o << "<g class=\"legend\">\n";
  for (const std::string& t : techniques) {
    if (std::none_of(pts.begin(), pts.end(), [&](const Row* r) { return r->technique == t; }))
      continue;
    o << "<circle cx=\"" << A::W - A::R + 14 << "\" cy=\"" << ly << "\" r=\"4.5\" fill=\""
      << colour.at(t) << "\"/><text x=\"" << A::W - A::R + 24 << "\" y=\"" << ly + 4
      << "\" font-size=\"11\">" << html_escape(t) << "</text>\n";
    ly += 16;
  }
  if (gl)
    o << "<circle cx=\"" << A::W - A::R + 14 << "\" cy=\"" << ly << "\" r=\"4.5\" fill=\"none\" "
      << "stroke=\"#444\"/><text x=\"" << A::W - A::R + 24 << "\" y=\"" << ly + 4
      << "\" font-size=\"11\">hollow: GL time</text>\n";
  o << "</g>\n";
}

// One Pareto plot of one view (the rows of one field, LOD mode and angle: one point per setting):
// x = median ns per fragment (log), y = mean or p99 hit error in texels (log; 0 sits on the
// floor, marked "0"). Filled discs: CPU backend; hollow circles: the GLSL twin's time (GL) at the
// same error (accuracy is always measured on CPU frames). The step setting is printed beside each
// point; the legend names the techniques.
std::string pareto_svg(const std::vector<const Row*>& pts, bool p99, const std::string& id,
                       const std::vector<std::string>& techniques,
                       const std::map<std::string, std::string>& colour) {
  const PlotAxes a = plot_axes(pts, p99);
  std::ostringstream o;
  svg_frame(o, p99, id);
  svg_axes(o, a, p99);
  svg_front(o, a, pts, p99);
  svg_points(o, a, pts, p99, colour);
  svg_legend(o, pts, techniques, colour);
  o << "</svg>\n";
  return o.str();
}

// Rows of one field and LOD mode, grouped: the settings in first-seen order and the angles.
struct Grid {
  std::vector<std::string> settings;
  std::vector<double> angles;
  std::map<std::pair<std::string, double>, const Row*> at;
};
Grid grid(const std::vector<Row>& rows, const std::string& field, const std::string& lod) {
  Grid g;
  for (const Row& r : rows) {
    if (r.field != field || r.lod != lod) continue;
    if (std::find(g.settings.begin(), g.settings.end(), r.setting) == g.settings.end())
      g.settings.push_back(r.setting);
    if (std::find(g.angles.begin(), g.angles.end(), r.angle) == g.angles.end())
      g.angles.push_back(r.angle);
    g.at[{r.setting, r.angle}] = &r;
  }
  return g;
}

// The angle x setting table of one metric (docs/accuracy.md's layout), over every field and LOD.
struct Metric {
  const char* title;
  std::function<std::string(const Row&)> cell;
};
std::string angle_table(const std::vector<Row>& rows, const std::vector<std::string>& fields,
                        const std::vector<std::string>& lods, const Metric& m) {
  std::vector<double> angles;
  for (const Row& r : rows)
    if (std::find(angles.begin(), angles.end(), r.angle) == angles.end()) angles.push_back(r.angle);
  std::ostringstream o;
  o << "<h3>" << m.title << "</h3>\n<div class=\"scroll\"><table class=\"grid\"><thead><tr>"
    << "<th class=\"l\">field</th>" << (lods.size() > 1 ? "<th class=\"l\">lod</th>" : "")
    << "<th class=\"l\">setting</th>";
  for (double a : angles) o << "<th>" << fmt("%g", a) << "&deg;</th>";
  o << "</tr></thead><tbody>\n";
  for (const std::string& f : fields)
    for (const std::string& l : lods) {
      const Grid g = grid(rows, f, l);
      for (const std::string& s : g.settings) {
        o << "<tr><td class=\"l\">" << html_escape(f) << "</td>";
        if (lods.size() > 1) o << "<td class=\"l\">" << html_escape(l) << "</td>";
        o << "<td class=\"l\">" << html_escape(s) << "</td>";
        for (double a : angles) {
          auto it = g.at.find({s, a});
          o << "<td>" << (it == g.at.end() ? std::string("&ndash;") : m.cell(*it->second))
            << "</td>";
        }
        o << "</tr>\n";
      }
    }
  o << "</tbody></table></div>\n";
  return o.str();
}

// What the report's sections share: the fields, techniques and LOD modes in first-seen order,
// whether any row ran on GL (or says why not), and one colour per technique.
struct ReportIndex {
  std::vector<std::string> fields, techniques, lods;
  bool gl = false;
  std::map<std::string, std::string> colour;
};
ReportIndex index_rows(const std::vector<Row>& rows) {
  ReportIndex x;
  for (const Row& r : rows) {
    if (std::find(x.fields.begin(), x.fields.end(), r.field) == x.fields.end())
      x.fields.push_back(r.field);
    if (std::find(x.techniques.begin(), x.techniques.end(), r.technique) == x.techniques.end())
      x.techniques.push_back(r.technique);
    if (std::find(x.lods.begin(), x.lods.end(), r.lod) == x.lods.end()) x.lods.push_back(r.lod);
    x.gl |= r.gl_ns_median >= 0 || !r.gl_note.empty();
  }
  for (size_t i = 0; i < x.techniques.size(); ++i) x.colour[x.techniques[i]] = kPalette[i % 10];
  return x;
}

// The page's head and style sheet.
void head_section(std::ostringstream& h) {
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
    << "<title>relief bench: accuracy and cost</title>\n<style>\n"
    << "body{font-family:sans-serif;margin:1.5em;max-width:1500px}\n"
    << "table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ccc;padding:2px 5px;"
       "text-align:right;white-space:nowrap}td.l,th.l{text-align:left}\n"
    << "div.scroll{overflow-x:auto;max-width:100%;margin-bottom:1em}\n"
    << "table.sortable th{cursor:pointer;background:#f4f4f4}"
       "table.sortable th[data-dir=asc]::after{content:' \\25B2'}"
       "table.sortable th[data-dir=desc]::after{content:' \\25BC'}\n"
    << "table.meta td{white-space:normal;word-break:break-all;max-width:1100px}\n"
    << "div.plots{display:flex;flex-wrap:wrap;gap:6px}figure{margin:4px}"
       "figcaption{font-size:12px;font-weight:bold}\n"
    << "table.strip td{vertical-align:top;text-align:center;font-size:11px}"
       "table.strip img{image-rendering:pixelated;width:112px;display:block}\n"
    << "</style></head><body>\n";
}

// The title, the build and machine table, what was measured, and the sweep's notes.
void build_section(std::ostringstream& h, const SweepResult& result, const RunInfo& info) {
  h << "<h1>relief bench</h1>\n";
  h << "<h2>Build and machine</h2>\n<table id=\"build\" class=\"meta\"><tbody>\n";
  for (const auto& [k, v] : info.build)
    h << "<tr><th class=\"l\">" << html_escape(k) << "</th><td class=\"l\">" << html_escape(v)
      << "</td></tr>\n";
  h << "<tr><th class=\"l\">machine</th><td class=\"l\">" << html_escape(info.machine)
    << "</td></tr>\n<tr><th class=\"l\">CPU backend</th><td class=\"l\">"
    << html_escape(result.cpu_device) << "</td></tr>\n<tr><th class=\"l\">GL backend</th><td "
    << "class=\"l\">"
    << (result.gl_device.empty() ? "n/a (not run)" : html_escape(result.gl_device))
    << "</td></tr>\n<tr><th class=\"l\">command</th><td class=\"l\"><code>"
    << html_escape(info.command) << "</code></td></tr>\n</tbody></table>\n";
  h << "<p>" << info.options.width << " x " << info.options.height << " px, " << info.options.warmup
    << " warm-up + " << info.options.repeats
    << " timed frames per row; orthographic views at azimuth " << kAzimuthDeg
    << " deg; errors against <code>exact</code> on level 0 (the true surface) at the same "
       "fragments. LOD modes: level0 = the depth map without mips; as-rendered = with its mips "
       "and the material's filter. Column meanings: docs/accuracy.md.</p>\n";
  for (const std::string& n : result.notes) h << "<p>" << html_escape(n) << "</p>\n";
}

// The per-angle Pareto plots: a mean and a p99 plot per field, LOD mode and view angle.
void plots_section(std::ostringstream& h, const std::vector<Row>& rows, const ReportIndex& x) {
  h << "<h2>Error against cost, per view</h2>\n<p>One plot pair per field, LOD mode and view "
       "angle; one point per setting (filled: CPU backend"
    << (x.gl ? "; hollow: the GLSL twin's time on GL, at the CPU frames' error" : "")
    << "), the step setting beside it, one colour per technique. The dashed line joins the "
       "settings no other beats on both cost and error. Errors of 0 sit on the floor of the "
       "axis.</p>\n";
  for (const std::string& f : x.fields)
    for (const std::string& l : x.lods) {
      const Grid g = grid(rows, f, l);
      h << "<h3>" << html_escape(f) << ", " << html_escape(l) << "</h3>\n<div class=\"plots\">\n";
      for (double a : g.angles) {
        std::vector<const Row*> pts;
        for (const std::string& s : g.settings) {
          auto it = g.at.find({s, a});
          if (it != g.at.end()) pts.push_back(it->second);
        }
        const std::string id = view_id(f, l, a);
        h << "<figure id=\"view-" << html_escape(id) << "\"><figcaption>" << html_escape(f)
          << " at " << fmt("%g", a) << "&deg; (" << html_escape(l) << ")</figcaption>\n"
          << pareto_svg(pts, false, id, x.techniques, x.colour)
          << pareto_svg(pts, true, id, x.techniques, x.colour) << "</figure>\n";
      }
      h << "</div>\n";
    }
}

// The angle x setting tables, one per metric (GL times when any row ran on GL).
void tables_section(std::ostringstream& h, const std::vector<Row>& rows, const ReportIndex& x) {
  h << "<h2>Angle x setting tables</h2>\n";
  const Metric metrics[] = {
      {"p99 hit error, texels", [](const Row& r) { return num(r.hit_err_p99); }},
      {"mean hit error, texels", [](const Row& r) { return num(r.hit_err_mean); }},
      {"fraction of fragments more than one texel off",
       [](const Row& r) { return num(r.hit_err_over1_frac); }},
      {"wrong-layer fraction (hits past exact's with air between)",
       [](const Row& r) { return num(r.wrong_layer_frac); }},
      {"air fraction (hits more than half a texel above the surface)",
       [](const Row& r) { return num(r.air_frac); }},
      {"wrong occlusion: in the air or on a wrong layer (wrong_occlusion_frac)",
       [](const Row& r) { return num(r.wrong_occlusion_frac); }},
      {"self-shadow error against exact's mask (shadow_err)",
       [](const Row& r) { return num(r.shadow_err); }},
      {"ns per fragment, CPU (median)", [](const Row& r) { return num(r.ns_median); }},
      {"texture fetches per fragment, mean", [](const Row& r) { return num(r.fetches_mean); }},
  };
  for (const Metric& m : metrics) h << angle_table(rows, x.fields, x.lods, m);
  if (x.gl)
    h << angle_table(rows, x.fields, x.lods,
                     {"ns per fragment, GL (median; n/a: not run)",
                      [](const Row& r) { return gl_num(r.gl_ns_median); }});
}

// The appendix yardstick (sweep.h AppendixRow), when it ran.
void appendix_section(std::ostringstream& h, const std::vector<AppendixRow>& rows) {
  if (rows.empty()) return;
  h << "<h2 id=\"appendix\">Appendix yardstick</h2>\n<p>The relief paper's appendix shader on "
       "GL ("
    << kAppendixLinearSteps << "+" << kAppendixBinarySteps
    << ", textureLod 0, one RGBA8 texture, diffuse only) against the CPU backend's relief with "
       "the same steps at level 0, no self-shadow and no depth write, on the same view. gl / "
       "cpu: how many times faster the CPU is; same hit: the pixels whose two hits lie within "
       "one texel.</p>\n<table class=\"meta\"><thead><tr><th class=\"l\">field</th><th>angle"
       "</th><th>cpu ns/frag</th><th>appendix ns/frag</th><th>gl / cpu</th><th>same hit</th>"
       "</tr></thead><tbody>\n";
  for (const AppendixRow& r : rows)
    h << "<tr><td class=\"l\">" << html_escape(r.field) << "</td><td>" << num(r.angle)
      << "</td><td>" << num(r.cpu_ns_median) << "</td><td>" << gl_num(r.gl_ns_median) << "</td><td>"
      << gl_num(r.speedup) << "</td><td>" << num(r.same_hit_frac) << "</td></tr>\n";
  h << "</tbody></table>\n";
}

// One cell of an image strip: row `r`'s kept colour image and heat map, with its errors.
Result<std::string> strip_cell(const Row& r, const RowImages& im, const std::string& setting,
                               double angle, const std::string& dir) {
  Result<std::string> c = png_uri(im.color, dir);
  if (!c.ok()) return c.status();
  Result<std::string> e = png_uri(im.heat, dir);
  if (!e.ok()) return e.status();
  std::ostringstream h;
  h << "<td><img alt=\"" << html_escape(setting) << " at " << fmt("%g", angle) << " deg\" src=\""
    << *c << "\"><img alt=\"heat map " << html_escape(setting) << " at " << fmt("%g", angle)
    << " deg\" src=\"" << *e << "\">p99 " << num(r.hit_err_p99) << ", air " << num(r.air_frac)
    << "<br>PSNR " << fmt("%.1f", r.psnr_db) << " dB</td>";
  return h.str();
}

// The image strips: per field and LOD mode, a row per setting of each view's kept images.
Status images_section(std::ostringstream& h, const SweepResult& result, const ReportIndex& x,
                      const std::string& dir) {
  if (result.images.empty()) return Status();
  h << "<h2>Images and error heat maps</h2>\n<p>Per setting, each view's shaded result and its "
       "heat map against exact (black: equal; blue, green below 8/255; yellow to red up to "
       "32/255 and above; each heat-map pixel of a reduced image shows the worst pixel it "
       "covers).</p>\n";
  std::map<size_t, const RowImages*> by_row;
  for (const RowImages& im : result.images) by_row[im.row] = &im;
  for (const std::string& f : x.fields)
    for (const std::string& l : x.lods) {
      const Grid g = grid(result.rows, f, l);
      h << "<h3>" << html_escape(f) << ", " << html_escape(l) << "</h3>\n"
        << "<div class=\"scroll\"><table class=\"strip\"><thead><tr><th class=\"l\">setting"
        << "</th>";
      for (double a : g.angles) h << "<th>" << fmt("%g", a) << "&deg;</th>";
      h << "</tr></thead><tbody>\n";
      for (const std::string& s : g.settings) {
        h << "<tr><td class=\"l\">" << html_escape(s) << "</td>";
        for (double a : g.angles) {
          auto it = g.at.find({s, a});
          const RowImages* im = nullptr;
          if (it != g.at.end()) {
            auto ri = by_row.find(static_cast<size_t>(it->second - result.rows.data()));
            if (ri != by_row.end()) im = ri->second;
          }
          if (!im) {
            h << "<td>&ndash;</td>";
            continue;
          }
          Result<std::string> cell = strip_cell(*it->second, *im, s, a, dir);
          if (!cell.ok()) return cell.status();
          h << *cell;
        }
        h << "</tr>\n";
      }
      h << "</tbody></table></div>\n";
    }
  return Status();
}

// The rows table's header: text columns align left.
void rows_header(std::ostringstream& h, const std::vector<std::string>& cells) {
  h << "<thead><tr>";
  for (const std::string& c : cells) {
    const bool text =
        c == "field" || c == "technique" || c == "setting" || c == "lod" || c == "gl_note";
    h << "<th" << (text ? " class=\"l\"" : "") << ">" << html_escape(c) << "</th>";
  }
  h << "</tr></thead><tbody>\n";
}

// One row of the rows table: numbers for people (the exact value in data-v, which sorts), n/a
// in a GL column where GL did not run.
void rows_row(std::ostringstream& h, const std::vector<std::string>& names,
              const std::vector<std::string>& cells) {
  h << "<tr>";
  for (size_t i = 0; i < cells.size(); ++i) {
    const std::string& name = i < names.size() ? names[i] : std::string();
    const std::string& c = cells[i];
    char* end = nullptr;
    const double v = std::strtod(c.c_str(), &end);
    const bool numeric = !c.empty() && end && *end == '\0';
    const bool gl_col = name.rfind("gl_", 0) == 0 || name == "cpu_gl_ratio";
    if (!numeric)
      h << "<td class=\"l\" data-v=\"" << html_escape(c) << "\">" << html_escape(c) << "</td>";
    else if (gl_col && v < 0)
      h << "<td data-v=\"\">n/a</td>";
    else
      h << "<td data-v=\"" << html_escape(c) << "\">" << num(v) << "</td>";
  }
  h << "</tr>\n";
}

// Every row, sortable: the CSV's columns as a table.
void rows_section(std::ostringstream& h, const std::vector<Row>& rows) {
  h << "<h2>Rows</h2>\n<p>Click a column header to sort (again: reverse). GL columns read n/a "
       "where GL was not run.</p>\n<div class=\"scroll\"><table id=\"rows\" class=\"sortable\">";
  const std::string csv = to_csv(rows);
  std::istringstream lines(csv);
  std::string line;
  std::vector<std::string> names;
  bool header = true;
  while (std::getline(lines, line)) {
    // the CSV's cells, split on unquoted commas (quotes dropped)
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"') {
        quoted = !quoted;
      } else if (ch == ',' && !quoted) {
        cells.push_back(cell);
        cell.clear();
      } else {
        cell += ch;
      }
    }
    cells.push_back(cell);
    if (header) {
      names = cells;
      rows_header(h, cells);
      header = false;
      continue;
    }
    rows_row(h, names, cells);
  }
  h << "</tbody></table></div>\n";
}

// Sorting, and a self-check the headless test reads: what the page drew.
void script_section(std::ostringstream& h) {
  h << "<script>\n(function(){\n"
       "function key(td){var v=td.getAttribute('data-v');var n=parseFloat(v);"
       "return isNaN(n)?{n:false,v:v}:{n:true,v:n};}\n"
       "function sortBy(t,c){var th=t.tHead.rows[0].cells,b=t.tBodies[0];"
       "var d=th[c].getAttribute('data-dir')==='asc'?-1:1;"
       "for(var k=0;k<th.length;k++)th[k].removeAttribute('data-dir');"
       "th[c].setAttribute('data-dir',d===1?'asc':'desc');"
       "var rows=Array.prototype.slice.call(b.rows);"
       "rows.sort(function(x,y){var a=key(x.cells[c]),e=key(y.cells[c]);"
       "if(a.n&&e.n)return (a.v-e.v)*d;if(a.n!==e.n)return a.n?-1:1;"
       "return String(a.v).localeCompare(String(e.v))*d;});"
       "rows.forEach(function(r){b.appendChild(r);});}\n"
       "document.querySelectorAll('table.sortable').forEach(function(t){"
       "var th=t.tHead.rows[0].cells;for(var c=0;c<th.length;c++)(function(c){"
       "th[c].addEventListener('click',function(){sortBy(t,c);});})(c);});\n"
       "var b=document.body;"
       "b.setAttribute('data-plots',String(document.querySelectorAll('svg.pareto').length));"
       "b.setAttribute('data-plot-points',"
       "String(document.querySelectorAll('svg.pareto circle.point').length));"
       "b.setAttribute('data-step-labels',"
       "String(document.querySelectorAll('svg.pareto text.steps').length));"
       "b.setAttribute('data-legends',"
       "String(document.querySelectorAll('svg.pareto g.legend').length));"
       "var t=document.getElementById('rows');"
       "b.setAttribute('data-table-rows',String(t?t.tBodies[0].rows.length:0));\n"
       "// #sort=COLUMN sorts the rows table by that column on load (the test's check)\n"
       "var m=/#sort=([a-z0-9_]+)/.exec(location.hash);if(m&&t){var th=t.tHead.rows[0].cells;"
       "for(var c=0;c<th.length;c++)if(th[c].textContent===m[1]){sortBy(t,c);"
       "b.setAttribute('data-sorted-by',m[1]);}}\n"
       "})();\n</script>\n";
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
  const ReportIndex index = index_rows(result.rows);
  std::ostringstream h;
  head_section(h);
  build_section(h, result, info);
  plots_section(h, result.rows, index);
  tables_section(h, result.rows, index);
  appendix_section(h, result.appendix);
  if (Status s = images_section(h, result, index, dir); !s.ok()) return s;
  rows_section(h, result.rows);
  script_section(h);
  h << "</body></html>\n";
  return write_file_atomic(dir + "/index.html", h.str());  // checked writes, fsync, rename
}

}  // namespace relief::sweep
