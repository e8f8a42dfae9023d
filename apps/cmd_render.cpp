// `relief render`: one frame of a built-in scene (or a scene file) to an image, with optional
// AOVs, per-pass statistics and the plan.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/output.h"
#include "apps/scene_source.h"
#include "plugins/registry.h"
#include "render/render.h"
#include "scene/image_io.h"

namespace relief::cli {
namespace {

struct RenderArgs {
  std::string scene;
  std::string output;
  std::string size = "800x600";
  int threads = 0;
  int tile_size = 64;
  std::string camera;
  std::string technique;
  std::vector<std::string> params;
  std::vector<std::string> aovs;
  std::vector<std::string> plugins;
  std::string stats;
  std::string backend = "cpu";
  int gpu = -1;
  bool explain = false;
  bool scalar = false;
  bool no_shadows = false;
  bool no_self_shadow = false;
  ShadowSettings shadow;
};

// Files are first written under temporary names, renamed into place only when all succeeded.
class OutputSet {
 public:
  ~OutputSet() {
    for (auto& [tmp, final_path] : files_) std::remove(tmp.c_str());
  }
  std::string temp_for(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const std::string tmp =
        (p.parent_path() / ("." + p.stem().string() + ".tmp" + std::to_string(::getpid()) +
                            p.extension().string()))
            .string();
    files_.emplace_back(tmp, path);
    return tmp;
  }
  Status commit() {
    for (auto& [tmp, final_path] : files_) {
      std::error_code ec;
      std::filesystem::rename(tmp, final_path, ec);
      if (ec) return Status::error(final_path + ": cannot rename into place: " + ec.message());
    }
    files_.clear();
    return {};
  }

 private:
  std::vector<std::pair<std::string, std::string>> files_;
};

nlohmann::json stats_json(const RenderResult& r, const std::string& scene,
                          const RenderOptions& opt) {
  nlohmann::json j;
  j["scene"] = scene;
  j["width"] = opt.width;
  j["height"] = opt.height;
  j["device"] = r.device;
  j["frame_ms"] = r.frame_ms;
  j["compile_ms"] = r.compile_ms;
  j["upload_ms"] = r.upload_ms;
  j["readback_ms"] = r.readback_ms;
  for (const PassStats& p : r.passes) {
    const RasterStats& s = p.raster;
    nlohmann::json pj;
    pj["name"] = p.name;
    pj["kind"] = p.kind == PassPlan::Kind::kShadow ? "shadow" : "main";
    if (p.kind == PassPlan::Kind::kShadow) {
      pj["light"] = p.light;
      pj["faces"] = p.faces;
      pj["resolution"] = p.resolution;
    }
    pj["ms"] = p.ms;
    pj["gpu_ms"] = p.gpu_ms;
    pj["setup_ms"] = s.setup_ms;
    pj["raster_ms"] = s.raster_ms;
    pj["triangles_in"] = s.triangles_in;
    pj["triangles_culled"] = s.triangles_culled;
    pj["triangles_clipped"] = s.triangles_clipped;
    pj["triangles_binned"] = s.triangles_binned;
    pj["quads"] = s.quads;
    pj["fragments_shaded"] = s.work.fragments;
    pj["fragments_discarded"] = s.work.discarded;
    pj["texture_fetches"] = s.work.texture_fetches;
    pj["search_steps"] = s.work.search_steps;
    pj["shadow_steps"] = s.work.shadow_steps;
    j["passes"].push_back(pj);
  }
  return j;
}

int do_render(const RenderArgs& a) {
  RenderOptions opt;
  Status s = parse_size(a.size, opt.width, opt.height);
  if (!s.ok()) return fail(s.message(), s.exit_code());
  if (a.threads < 0 || a.threads > 256) return fail("--threads: expected 0..256", 2);
  if (a.tile_size < 8 || a.tile_size > 512 || a.tile_size % 2)
    return fail("--tile-size: expected an even number in 8..512", 2);
  opt.threads = a.threads;
  opt.tile_size = a.tile_size;
  opt.technique = a.technique;
  opt.scalar_lanes = a.scalar;
  opt.shadows = !a.no_shadows;
  opt.self_shadow = !a.no_self_shadow;
  opt.shadow = a.shadow;
  opt.count_work = !a.stats.empty();  // the GL backend counts only when asked
  for (const std::string& kv : a.params) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      return fail("--param: expected key=value, got '" + kv + "'", 2);
    opt.params[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  std::map<std::string, std::string> aov_files;
  for (const std::string& kv : a.aovs) {
    const size_t eq = kv.find('=');
    const std::string name = kv.substr(0, eq);
    if (eq == std::string::npos || eq + 1 >= kv.size())
      return fail("--aov: expected NAME=FILE, got '" + kv + "'", 2);
    bool known = name == "depth";
    for (int i = 0; i < kAovCount; ++i)
      if (name == kAovNames[i]) {
        known = true;
        opt.aovs |= aov_bit(static_cast<Aov>(i));
      }
    if (!known)
      return fail("--aov: unknown AOV '" + name + "' (depth, uv, hit_depth, steps, normal)", 2);
    aov_files[name] = kv.substr(eq + 1);
  }
  for (const std::string& p : a.plugins) {
    Status ls = PluginRegistry::global().load(p);
    if (!ls.ok()) return fail(ls.message(), ls.exit_code());
  }
  if (a.backend != "cpu" && a.backend != "gl")
    return fail("--backend: expected cpu or gl, got '" + a.backend + "'", 2);

  const std::string scene_name = a.scene.empty() ? default_scene_source() : a.scene;
  Result<Scene> scene = load_scene_source(scene_name);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  Result<int> camera = resolve_camera(*scene, a.camera);
  if (!camera.ok()) return fail(camera.status().message(), camera.status().exit_code());
  opt.camera = *camera;
  Result<Plan> plan = make_plan(*scene, opt);
  if (!plan.ok()) return fail(plan.status().message(), plan.status().exit_code());
  if (a.explain) std::printf("%s", plan->explain().c_str());

  Result<std::unique_ptr<Backend>> backend = make_backend(a.backend, opt.threads, a.gpu);
  if (!backend.ok()) return fail(backend.status().message(), backend.status().exit_code());
  const auto t0 = std::chrono::steady_clock::now();
  Result<RenderResult> r = (*backend)->render(*scene, *plan, opt);
  if (!r.ok()) return fail(r.status().message(), r.status().exit_code());

  OutputSet out;
  s = write_image(out.temp_for(a.output), r->framebuffer.color);
  if (!s.ok()) return fail(s.with_context(a.output).message(), s.exit_code());
  for (const auto& [name, file] : aov_files) {
    const std::string tmp = out.temp_for(file);
    if (name == "depth") {
      s = write_plane(tmp, r->framebuffer.depth);
    } else {
      for (int i = 0; i < kAovCount; ++i)
        if (name == kAovNames[i]) s = write_image(tmp, r->framebuffer.aov_image(static_cast<Aov>(i)));
    }
    if (!s.ok()) return fail(file + ": " + s.message(), s.exit_code());
  }
  if (!a.stats.empty()) {
    const std::string tmp = out.temp_for(a.stats);
    nlohmann::json j = stats_json(*r, scene_name, opt);
    for (const PassPlan& p : plan->passes) j["plan"]["passes"][p.name] = p.reason;
    j["plan"]["skipped"] = plan->skipped;
    s = write_text_atomic(tmp, j.dump(2) + "\n");
    if (!s.ok()) return fail(a.stats + ": cannot write statistics", 1);
  }
  s = out.commit();
  if (!s.ok()) return fail(s.message(), s.exit_code());
  const double total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %dx%d %s on %s, frame %.1f ms, with output %.1f ms\n", a.output.c_str(),
              opt.width, opt.height, scene_name.c_str(), r->device.c_str(), r->frame_ms, total_ms);
  return 0;
}

}  // namespace

void register_render(CLI::App& app, Action& action) {
  auto a = std::make_shared<RenderArgs>();
  auto* sub = app.add_subcommand("render", "Render one frame of a scene to an image");
  sub->add_option("scene", a->scene, "Built-in scene name (see `relief scenes`) or .gltf/.glb file");
  sub->add_option("-o,--output", a->output, "Output image (.png 8-bit sRGB, .exr float, .tif)")
      ->required();
  sub->add_option("--size", a->size, "Image size WxH")->capture_default_str();
  sub->add_option("--threads", a->threads, "Worker threads, 0 = all cores")->capture_default_str();
  sub->add_option("--tile-size", a->tile_size, "Tile size in pixels (even, 8..512)")
      ->capture_default_str();
  sub->add_option("--camera", a->camera,
                  "Camera by name or index (default: the first; see docs/scene-format.md)");
  sub->add_option("--technique", a->technique, "Replace every material's technique (plugin)");
  sub->add_option("--param", a->params, "Plugin parameter override key=value (repeatable)");
  sub->add_option("--aov", a->aovs, "Extra output NAME=FILE: depth, uv, hit_depth, steps, normal");
  sub->add_option("--plugin", a->plugins, "Load an external plugin (.so)");
  sub->add_option("--stats", a->stats, "Write per-pass counters and timings as JSON");
  sub->add_option("--backend", a->backend, "cpu or gl")->capture_default_str();
  sub->add_option("--gpu", a->gpu, "GL backend: EGL device index (-1 = first usable)");
  sub->add_flag("--explain", a->explain, "Print the plan: passes, variants and why");
  sub->add_flag("--scalar", a->scalar, "Run kernels one fragment at a time (reference path)");
  sub->add_flag("--no-shadows", a->no_shadows, "No shadow passes (shadow maps) in this frame");
  sub->add_flag("--no-self-shadow", a->no_self_shadow, "No self-shadow rays in this frame");
  sub->add_option("--shadow-bias", a->shadow.depth_bias, "Shadow-map constant bias, texels")
      ->capture_default_str();
  sub->add_option("--shadow-slope-bias", a->shadow.slope_bias,
                  "Shadow-map slope-scaled bias, texels per unit tan(angle)")
      ->capture_default_str();
  sub->add_option("--shadow-pcf", a->shadow.pcf_radius,
                  "Shadow-map PCF radius r: (2r+2)^2 bilinear taps")
      ->capture_default_str();
  sub->callback([&action, a] { action = [a] { return do_render(*a); }; });
}

}  // namespace relief::cli
