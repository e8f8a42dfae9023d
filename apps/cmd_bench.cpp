// `relief bench`: the accuracy/cost sweep of the relief techniques (sweep/sweep.h, issue 8) and
// `--target-error`, the cheapest setting per material of a scene under an error target.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "apps/commands.h"
#include "apps/output.h"
#include "apps/scene_source.h"
#include "apps/version.h"
#include "plugins/registry.h"
#include "rasterizer/safe_file.h"
#include "sweep/sweep.h"

namespace relief::cli {
namespace {

struct BenchArgs {
  std::string backend = "cpu";
  std::string gl_interpolation = "gpu";
  std::string size = "256x256";
  int threads = 0;
  std::string angles = "0,30,60,75,85,89";
  std::string steps = "8,16,32,64";
  int binary_steps = -1;
  std::string techniques;
  std::string fields = "bricks,pattern";
  std::string lod = "level0";
  std::string search_lod = "quad";
  std::vector<std::string> depth_files;
  float depth_scale = 0.05f;
  bool height = false;
  int warmup = 1;
  int repeats = 5;
  bool quick = false;
  std::string csv, json, report;
  double target_error = -1.0;
  std::string scene;
  std::string camera;
  bool allow_outside_scene_dir = false;
  bool strict = false;  // --strict (scene/gltf_extensions.h)
  std::vector<std::string> plugins;
  bool no_progress = false;
  bool no_self_shadow = false;
  CLI::App* sub = nullptr;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

Result<std::vector<double>> parse_numbers(const std::string& flag, const std::string& text,
                                          double lo, double hi) {
  std::vector<double> v;
  for (const std::string& item : split(text)) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end || !(x >= lo && x <= hi)) {
      char range[64];  // the bounds the check uses, as the help text gives them (0..89.9)
      std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
      return Status::usage(flag + ": expected numbers in " + range + ", got '" + item + "'");
    }
    v.push_back(x);
  }
  if (v.empty()) return Status::usage(flag + ": expected a comma-separated list");
  return v;
}

// The exact command line, from /proc (shell-quoted where needed).
std::string command_line() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string out, arg;
  auto flush = [&] {
    const bool plain = !arg.empty() && arg.find_first_of(" \t'\"$\\*?;&|<>()") == std::string::npos;
    out += (out.empty() ? "" : " ") + (plain ? arg : "'" + arg + "'");
    arg.clear();
  };
  for (char c : all) {
    if (c == '\0')
      flush();
    else
      arg += c;
  }
  if (!arg.empty()) flush();
  return out;
}

// The CPU model and core count (machine_description() without the load average).
std::string cpu_model() {
  const std::string m = sweep::machine_description();
  return m.substr(0, m.find(", load average"));
}

// The report's and the JSON's build metadata: apps/version.h, the date (UTC) and the CPU.
std::vector<std::pair<std::string, std::string>> build_metadata() {
  const BuildInfo b = build_info();
  std::string backends;
  for (const std::string& x : b.backends) backends += (backends.empty() ? "" : ", ") + x;
  char date[32] = "";
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  if (gmtime_r(&now, &utc)) std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return {{"version", b.version},   {"commit", b.commit}, {"build_type", b.build_type},
          {"compiler", b.compiler}, {"simd", b.simd},     {"simd_supported", b.simd_supported},
          {"backends", backends},   {"date", date},       {"cpu", cpu_model()}};
}

// The --csv, --json and --report outputs, checked before the sweep runs (no output at all on
// error): folders that exist and can be written, no file named twice (apps/output.h).
Status check_outputs(const BenchArgs& a) {
  OutputCheck check;
  for (const auto& [flag, path] : {std::pair{"--csv", a.csv}, std::pair{"--json", a.json}})
    if (!path.empty()) RELIEF_RETURN_IF_ERROR(check.add(flag, path, OutputCheck::Kind::kAny));
  if (a.report.empty()) return {};
  std::error_code ec;
  const std::filesystem::path dir(a.report);
  if (std::filesystem::exists(dir, ec) && !std::filesystem::is_directory(dir, ec))
    return Status::error("--report: " + printable(a.report) + " exists and is not a folder");
  if (std::filesystem::is_directory(dir, ec))
    return check.add("--report", (dir / "index.html").string(), OutputCheck::Kind::kAny);
  return {};
}

class Progress {
 public:
  explicit Progress(bool on) : on_(on && isatty(2)) {}
  ~Progress() { finish(); }
  void operator()(int done, int total, const std::string& what) {
    if (!on_) return;
    const int width = 30, filled = total ? done * width / total : width;
    std::fprintf(stderr, "\r[%s%s] %d/%d %-48.48s", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done, total, what.c_str());
    std::fflush(stderr);
    shown_ = true;
  }
  void finish() {
    if (shown_) std::fprintf(stderr, "\n");
    shown_ = false;
  }

 private:
  bool on_;
  bool shown_ = false;
};

int do_target(const BenchArgs& a, const sweep::Options& opt,
              const std::vector<sweep::Setting>& settings) {
  if (opt.lods.size() != 1)
    return fail("--lod: --target-error picks on one LOD mode (level0 or as-rendered), not both", 2);
  const std::string scene_name = a.scene.empty() ? default_scene_source() : a.scene;
  Result<Scene> scene = load_scene_source(scene_name, a.allow_outside_scene_dir, a.strict);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  Result<int> camera = resolve_camera(*scene, a.camera);
  if (!camera.ok()) return fail(camera.status().message(), camera.status().exit_code());
  std::vector<sweep::Row> all;
  std::ostringstream report;
  bool any = false;
  for (size_t m = 0; m < scene->materials.size(); ++m) {
    const Material& mat = scene->materials[m];
    Result<sweep::Field> field = sweep::field_of_material(*scene, static_cast<int>(m));
    if (!field.ok()) {
      report << "material '" << mat.name << "': no depth map, nothing to choose\n";
      continue;
    }
    const std::vector<double> angles =
        sweep::scene_view_angles(*scene, static_cast<int>(m), *camera, opt.width, opt.height);
    if (angles.empty()) {
      report << "material '" << mat.name << "': not seen by the camera, nothing to choose\n";
      continue;
    }
    any = true;
    sweep::Options o = opt;
    o.angles = angles;
    Progress progress(!a.no_progress);
    o.progress = [&](int d, int t, const std::string& w) { progress(d, t, mat.name + ": " + w); };
    Result<sweep::SweepResult> r = sweep::run_sweep({*field}, settings, o);
    progress.finish();
    if (!r.ok()) return fail(r.status().message(), r.status().exit_code());
    const sweep::Pick p = sweep::pick_cheapest(r->rows, field->name, angles, a.target_error);
    report << "material '" << mat.name << "': view angles";
    for (double x : angles) report << " " << x;
    report << " deg -> " << (p.found ? p.setting : std::string("none")) << "\n" << p.why;
    all.insert(all.end(), r->rows.begin(), r->rows.end());
  }
  if (!any) return fail("scene '" + scene_name + "': no material with a depth map in view", 1);
  std::printf("--target-error %g texel (p99 hit error) on %s, %dx%d:\n%s", a.target_error,
              scene_name.c_str(), opt.width, opt.height, report.str().c_str());
  if (!a.csv.empty()) {
    Status s = write_text_atomic(a.csv, sweep::to_csv(all));
    if (!s.ok()) return fail(s.message(), s.exit_code());
  }
  return 0;
}

// The sweep's options from the command line (--quick fills in the small sweep's defaults;
// explicit options still win), and the step counts of --steps.
Status parse_sweep_options(BenchArgs& a, sweep::Options& opt, std::vector<int>& step_counts) {
  if (a.quick) {
    if (!a.sub->count("--size")) a.size = "128x128";
    if (!a.sub->count("--angles")) a.angles = "0,60,85";
    if (!a.sub->count("--steps")) a.steps = "8,32";
    if (!a.sub->count("--repeats")) a.repeats = 3;
  }
  RELIEF_RETURN_IF_ERROR(parse_size(a.size, opt.width, opt.height));
  if (a.threads < 0 || a.threads > 256) return Status::usage("--threads: expected 0..256");
  if (a.repeats < 1 || a.repeats > 1000) return Status::usage("--repeats: expected 1..1000");
  if (a.warmup < 0 || a.warmup > 100) return Status::usage("--warmup: expected 0..100");
  if (a.sub->count("--binary-steps") && (a.binary_steps < 0 || a.binary_steps > 32))
    return Status::usage("--binary-steps: expected 0..32");
  opt.threads = a.threads;
  opt.repeats = a.repeats;
  opt.warmup = a.warmup;
  opt.self_shadow = !a.no_self_shadow;
  if (a.lod == "level0" || a.lod == "as-rendered")
    opt.lods = {a.lod};
  else if (a.lod == "both")
    opt.lods = {sweep::kLodLevel0, sweep::kLodAsRendered};
  else
    return Status::usage("--lod: expected level0, as-rendered or both, got '" + a.lod + "'");
  Result<std::vector<double>> angles = parse_numbers("--angles", a.angles, 0.0, 89.9);
  if (!angles.ok()) return Status::usage(angles.status().message());
  opt.angles = *angles;
  Result<std::vector<double>> steps = parse_numbers("--steps", a.steps, 1.0, 256.0);
  if (!steps.ok()) return Status::usage(steps.status().message());
  for (double x : *steps) step_counts.push_back(static_cast<int>(std::lround(x)));
  const std::vector<std::string> backends = split(a.backend);
  for (const std::string& b : backends) {
    if (b != "cpu" && b != "gl")
      return Status::usage("--backend: expected cpu, gl or cpu,gl, got '" + a.backend + "'");
  }
  opt.gl = std::find(backends.begin(), backends.end(), "gl") != backends.end();
  Result<GlInterpolation> interpolation = parse_gl_interpolation(a.gl_interpolation);
  if (!interpolation.ok()) return interpolation.status();
  opt.gl_interpolation = *interpolation;
  // accuracy is always measured on the CPU backend; `gl` alone still needs its rows
  opt.cpu = true;
  if (a.sub->count("--target-error") > 0 &&
      !(a.target_error > 0.0 && std::isfinite(a.target_error)))
    return Status::usage("--target-error: expected a positive number of texels");
  return check_outputs(a);
}

// The settings of --techniques, --steps, --binary-steps and --search-lod (after --plugin loads).
Result<std::vector<sweep::Setting>> parse_settings(const BenchArgs& a,
                                                   const std::vector<int>& step_counts) {
  for (const std::string& p : a.plugins)
    RELIEF_RETURN_IF_ERROR(load_plugin_arg(p));  // a bare name is ./NAME
  std::vector<std::string> techniques = sweep::sweep_techniques();
  if (!a.techniques.empty()) {
    const std::vector<std::string> known = techniques;
    techniques = split(a.techniques);
    for (const std::string& t : techniques)
      if (std::find(known.begin(), known.end(), t) == known.end()) {
        std::string list;
        for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
        return Status::usage("--techniques: '" + t + "' is not a technique with a depth map (" +
                             list + ")");
      }
  }
  const std::vector<std::string> search_lods = split(a.search_lod);
  for (const std::string& l : search_lods)
    if (l != "quad" && l != "zero" && l != "max-mip")
      return Status::usage("--search-lod: expected quad, zero or max-mip (comma-separated), got '" +
                           l + "'");
  std::vector<sweep::Setting> settings;
  for (const std::string& t : techniques) {
    for (sweep::Setting& st : sweep::settings_for(*PluginRegistry::global().find(t), step_counts,
                                                  a.binary_steps, search_lods))
      settings.push_back(std::move(st));
  }
  return settings;
}

// The height fields of --fields and --depth; at least one.
Result<std::vector<sweep::Field>> parse_fields(const BenchArgs& a) {
  std::vector<sweep::Field> fields;
  const std::vector<std::string>& known = sweep::builtin_field_names();
  for (const std::string& name : split(a.fields)) {
    if (name == "none") continue;
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += k + ", ";
      return Status::usage("--fields: unknown built-in height field '" + name + "' (" + list +
                           "none)");
    }
    Result<sweep::Field> f = sweep::builtin_field(name);
    if (!f.ok()) return Status::error(f.status().message());
    fields.push_back(std::move(f).value());
  }
  for (const std::string& file : a.depth_files) {
    Result<sweep::Field> f = sweep::field_from_file(file, a.depth_scale, a.height);
    if (!f.ok()) return f.status();
    fields.push_back(std::move(f).value());
  }
  if (fields.empty())
    return Status::usage("no height field to sweep (--fields none and no --depth)");
  return fields;
}

// The table on stdout, then --csv, --json and --report.
Status write_bench_outputs(const BenchArgs& a, const sweep::SweepResult& r,
                           const sweep::Options& opt) {
  sweep::RunInfo info{command_line(), sweep::machine_description(), opt, build_metadata()};
  // The device names its thread count ("cpu (2 threads)"), --threads 0 resolved.
  std::printf("%s\n%s, %dx%d, %d warm-up + %d timed frames per row\n", info.machine.c_str(),
              r.cpu_device.c_str(), opt.width, opt.height, opt.warmup, opt.repeats);
  if (!r.gl_device.empty()) std::printf("gl: %s\n", r.gl_device.c_str());
  std::printf("%s", sweep::format_table(r.rows).c_str());
  std::printf("%s", sweep::format_appendix_table(r.appendix).c_str());
  for (const std::string& n : r.notes) std::printf("%s\n", n.c_str());
  if (!a.csv.empty()) RELIEF_RETURN_IF_ERROR(write_text_atomic(a.csv, sweep::to_csv(r.rows)));
  if (!a.json.empty()) RELIEF_RETURN_IF_ERROR(write_text_atomic(a.json, sweep::to_json(r, info)));
  if (!a.report.empty()) {
    RELIEF_RETURN_IF_ERROR(sweep::write_report(a.report, r, info));
    std::printf("report: %s/index.html\n", a.report.c_str());
  }
  return {};
}

int do_bench(BenchArgs& a) {
  sweep::Options opt;
  std::vector<int> step_counts;
  Status s = parse_sweep_options(a, opt, step_counts);
  if (!s.ok()) return fail(s.message(), s.exit_code());
  Result<std::vector<sweep::Setting>> settings = parse_settings(a, step_counts);
  if (!settings.ok()) return fail(settings.status().message(), settings.status().exit_code());
  if (a.sub->count("--target-error") > 0) return do_target(a, opt, *settings);
  Result<std::vector<sweep::Field>> fields = parse_fields(a);
  if (!fields.ok()) return fail(fields.status().message(), fields.status().exit_code());

  opt.keep_images = !a.report.empty();
  Progress progress(!a.no_progress);
  opt.progress = [&](int d, int t, const std::string& w) { progress(d, t, w); };
  Result<sweep::SweepResult> r = sweep::run_sweep(*fields, *settings, opt);
  progress.finish();
  if (!r.ok()) return fail(r.status().message(), r.status().exit_code());
  s = write_bench_outputs(a, *r, opt);
  if (!s.ok()) return fail(s.message(), s.exit_code());
  return 0;
}

}  // namespace

void register_bench(CLI::App& app, Action& action) {
  auto a = std::make_shared<BenchArgs>();
  auto* sub = app.add_subcommand(
      "bench",
      "Accuracy/cost sweep: techniques x steps x view angles x height fields (docs/accuracy.md)");
  a->sub = sub;
  sub->add_option("--backend", a->backend,
                  "cpu, gl or cpu,gl (gl: time of the GLSL twins and, when relief is swept, of "
                  "the relief paper's appendix shader)")
      ->capture_default_str();
  sub->add_option("--gl-interpolation", a->gl_interpolation,
                  "gl: how the twins interpolate, gpu (GL's own, as `render --backend gl`) or "
                  "cpu-planes (the CPU's planes, as the agreement tests)")
      ->capture_default_str();
  sub->add_option("--size", a->size, "Frame size WxH of each view")->capture_default_str();
  sub->add_option("--threads", a->threads, "Worker threads, 0 = all cores")->capture_default_str();
  sub->add_option("--angles", a->angles, "View angles, degrees from the normal (0..89.9)")
      ->capture_default_str();
  sub->add_option("--steps", a->steps, "Step counts of techniques with a `steps` parameter")
      ->capture_default_str();
  sub->add_option("--binary-steps", a->binary_steps,
                  "Binary steps of every technique that has them (default: each one's own)");
  sub->add_option("--techniques", a->techniques,
                  "Comma-separated techniques (default: all with a depth map)");
  sub->add_option("--fields", a->fields,
                  "Built-in height fields: bricks, pattern, thin, spikes, ramp, fur, grass, none")
      ->capture_default_str();
  sub->add_option("--lod", a->lod,
                  "level0 (depth map without mips), as-rendered (with its mips and the "
                  "material's filter; errors against exact at level 0) or both")
      ->capture_default_str();
  sub->add_option("--search-lod", a->search_lod,
                  "The `lod` parameter of the searches that have one (relief, pom, "
                  "steep_parallax, relief_quadric): quad, zero, max-mip, comma-separated")
      ->capture_default_str();
  sub->add_option("--depth", a->depth_files, "Also sweep this depth image (repeatable)");
  sub->add_option("--depth-scale", a->depth_scale, "Relief depth of --depth images, uv units")
      ->capture_default_str();
  sub->add_flag("--height", a->height, "--depth images are height maps (1 = top)");
  sub->add_option("--warmup", a->warmup, "Untimed frames before timing each row")
      ->capture_default_str();
  sub->add_option("--repeats", a->repeats, "Timed frames per row (median, min, max)")
      ->capture_default_str();
  sub->add_flag("--quick", a->quick, "Small sweep: 128x128, angles 0,60,85, steps 8,32, 3 repeats");
  sub->add_option("--csv", a->csv, "Write the rows as CSV (columns: docs/accuracy.md)");
  sub->add_option("--json", a->json, "Write the rows, machine and command as JSON");
  sub->add_option("--report", a->report,
                  "Write DIR/index.html: per-angle Pareto plots, tables, images, sortable rows");
  sub->add_option(
      "--target-error", a->target_error,
      "Pick per material of --scene the cheapest setting with p99 hit error under E texels");
  sub->add_option("--scene", a->scene, "Scene for --target-error (built-in name or .gltf/.glb)");
  sub->add_option("--camera", a->camera, "Camera of --scene (name or index)");
  sub->add_flag("--allow-outside-scene-dir", a->allow_outside_scene_dir, kAllowOutsideSceneDirHelp);
  sub->add_flag("--strict", a->strict, kStrictHelp);
  sub->add_option("--plugin", a->plugins,
                  "Load an external plugin (.so); swept like the built-ins");
  sub->add_flag("--no-self-shadow", a->no_self_shadow,
                "No self-shadow rays (fetches are then the search's and the shading's)");
  sub->add_flag("--no-progress", a->no_progress, "No progress bar on stderr");
  sub->callback([&action, a] { action = [a] { return do_bench(*a); }; });
}

}  // namespace relief::cli
