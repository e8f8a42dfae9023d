// `relief render`: frames of a built-in scene (or a scene file) to images, with optional AOVs,
// per-pass statistics and the plan. One frame by default; `--frames A-B` renders a range (the
// scene's animation, else a camera turntable), `--shard I/N` a block of it (apps/frames.h).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/frames.h"
#include "apps/output.h"
#include "apps/scene_source.h"
#include "plugins/registry.h"
#include "rasterizer/output_file.h"
#include "render/render.h"
#include "scene/animation.h"
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
  std::string frames;  // A-B
  std::string shard;   // I/N
  std::string spp = "1";
  std::string exposure = "0";
  double fps = 24.0;
  std::string animation;
  bool turntable = false;
  bool allow_outside_scene_dir = false;
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

// A progress bar on stderr, drawn only when stderr is a terminal and more than one frame renders.
class Progress {
 public:
  explicit Progress(size_t total) : total_(total), on_(total > 1 && ::isatty(STDERR_FILENO)) {
    t0_ = std::chrono::steady_clock::now();
  }
  ~Progress() { clear(); }
  void draw(size_t done) {
    if (!on_) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    const int width = 30, fill = static_cast<int>(width * done / total_);
    const double per = done ? s / done : 0.0;
    std::fprintf(stderr, "\r\033[K[%s%s] %zu/%zu frames, %.2f s/frame, ETA %.0f s",
                 std::string(fill, '#').c_str(), std::string(width - fill, '.').c_str(), done,
                 total_, per, per * (total_ - done));
    std::fflush(stderr);
    drawn_ = true;
  }
  void clear() {
    if (!drawn_) return;
    std::fprintf(stderr, "\r\033[K");
    std::fflush(stderr);
    drawn_ = false;
  }

 private:
  size_t total_;
  bool on_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point t0_;
};

// Which animation clip `--animation NAME|INDEX` names (0 when empty).
Result<int> resolve_clip(const Scene& scene, const std::string& name) {
  const int n = scene.animation ? static_cast<int>(scene.animation->clips.size()) : 0;
  if (name.empty()) return 0;
  for (int i = 0; i < n; ++i)
    if (scene.animation->clips[i].name == name || std::to_string(i) == name) return i;
  std::string known;
  for (int i = 0; i < n; ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " '" +
             scene.animation->clips[i].name + "'";
  return Status::usage("--animation: scene '" + scene.name + "' has no animation '" + name +
                       "' (animations: " + (known.empty() ? "none" : known) + ")");
}

// Output names of a render: each may carry a frame pattern (required for more than one frame).
struct OutputNames {
  std::string image;
  std::map<std::string, std::string> aovs;  // AOV name -> file
  std::string stats;
  Status check(bool multi_frame) const {
    auto one = [&](const std::string& name, const std::string& flag) -> Status {
      bool pattern = false;
      RELIEF_RETURN_IF_ERROR(check_frame_pattern(name, flag, pattern));
      if (multi_frame && !pattern)
        return Status::usage(flag + ": '" + name +
                             "' has no frame pattern such as %04d (needed for more than one "
                             "frame)");
      return {};
    };
    RELIEF_RETURN_IF_ERROR(one(image, "--output"));
    for (const auto& [aov, file] : aovs) RELIEF_RETURN_IF_ERROR(one(file, "--aov " + aov));
    if (!stats.empty()) RELIEF_RETURN_IF_ERROR(one(stats, "--stats"));
    return {};
  }
  // Before anything renders: every output of `frames` (the first kMaxChecked and the last) can
  // be written, images have a known extension, and no file is named twice (across frames too).
  Status check_files(const std::vector<int>& frames, bool named) const {
    constexpr size_t kMaxChecked = 1000;
    OutputCheck outputs;
    for (size_t fi = 0; fi < frames.size(); ++fi) {
      if (fi >= kMaxChecked && fi + 1 != frames.size()) continue;
      auto name_of = [&](const std::string& n) {
        return named ? format_frame_name(n, frames[fi]) : n;
      };
      RELIEF_RETURN_IF_ERROR(outputs.add("--output", name_of(image), OutputCheck::Kind::kImage));
      for (const auto& [aov, file] : aovs)
        RELIEF_RETURN_IF_ERROR(
            outputs.add("--aov " + aov, name_of(file), OutputCheck::Kind::kImage));
      if (!stats.empty())
        RELIEF_RETURN_IF_ERROR(outputs.add("--stats", name_of(stats), OutputCheck::Kind::kAny));
    }
    return {};
  }
};

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
  OutputNames names{a.output, {}, a.stats};
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
    names.aovs[name] = kv.substr(eq + 1);
  }
  // Frames, shards, samples, exposure: all checked before anything renders.
  FrameRange range;
  if (!a.frames.empty()) {
    Result<FrameRange> r = parse_frames(a.frames);
    if (!r.ok()) return fail(r.status().message(), 2);
    range = *r;
  }
  Shard shard;
  if (!a.shard.empty()) {
    if (a.frames.empty()) return fail("--shard: needs --frames A-B (the range to split)", 2);
    Result<Shard> r = parse_shard(a.shard);
    if (!r.ok()) return fail(r.status().message(), 2);
    shard = *r;
  }
  Result<int> spp = parse_spp(a.spp);
  if (!spp.ok()) return fail(spp.status().message(), 2);
  const int k = static_cast<int>(std::lround(std::sqrt(*spp)));
  if (static_cast<long long>(opt.width) * k > kMaxTargetSize ||
      static_cast<long long>(opt.height) * k > kMaxTargetSize ||
      static_cast<long long>(opt.width) * opt.height * k * k > kMaxTargetPixels)
    return fail("--spp: " + a.spp + " samples at " + a.size + " render " +
                    std::to_string(opt.width * k) + "x" + std::to_string(opt.height * k) +
                    ", over the limit of " + std::to_string(kMaxTargetSize) + " a side and " +
                    std::to_string(kMaxTargetPixels) + " pixels",
                2);
  Result<float> exposure = parse_exposure(a.exposure);
  if (!exposure.ok()) return fail(exposure.status().message(), 2);
  if (!(a.fps > 0.0 && a.fps <= 1000.0))
    return fail("--fps: expected a number of frames per second in (0, 1000]", 2);
  s = names.check(!a.frames.empty() && range.count() > 1);
  if (!s.ok()) return fail(s.message(), 2);
  s = names.check_files(a.frames.empty() ? std::vector<int>{0} : shard_frames(range, shard),
                        !a.frames.empty());
  if (!s.ok()) return fail(s.message(), s.exit_code());
  opt.width *= k;
  opt.height *= k;

  for (const std::string& p : a.plugins) {
    Status ls = PluginRegistry::global().load(p);
    if (!ls.ok()) return fail(ls.message(), ls.exit_code());
  }
  if (a.backend != "cpu" && a.backend != "gl")
    return fail("--backend: expected cpu or gl, got '" + a.backend + "'", 2);

  const std::string scene_name = a.scene.empty() ? default_scene_source() : a.scene;
  Result<Scene> scene = load_scene_source(scene_name, a.allow_outside_scene_dir);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  Result<int> camera = resolve_camera(*scene, a.camera);
  if (!camera.ok()) return fail(camera.status().message(), camera.status().exit_code());
  opt.camera = *camera;
  Result<int> clip = resolve_clip(*scene, a.animation);
  if (!clip.ok()) return fail(clip.status().message(), clip.status().exit_code());
  const std::shared_ptr<const SceneAnimation> anim = scene->animation;
  const bool has_clips = anim && !anim->clips.empty();
  // Turntable: with --frames when the scene has no animation (or with --turntable).
  const bool turntable = !a.frames.empty() && (a.turntable || !has_clips);
  glm::dvec3 lo, hi;
  scene_bounds(*scene, lo, hi);
  const glm::dvec3 centre = (lo + hi) * 0.5;
  PoseOptions pose;
  pose.clip = *clip;
  pose.technique = a.technique;

  Result<std::unique_ptr<Backend>> backend = make_backend(a.backend, opt.threads, a.gpu);
  if (!backend.ok()) return fail(backend.status().message(), backend.status().exit_code());
  const std::vector<int> frames = shard_frames(range, shard);
  if (frames.empty()) {
    std::printf("shard %d/%d: no frames (the range %d-%d has %d)\n", shard.index, shard.count,
                range.first, range.last, range.count());
    return 0;
  }
  const float exposure_scale = std::exp2(*exposure);
  const std::vector<Camera> loaded_cameras = scene->cameras;
  Progress progress(frames.size());
  std::vector<double> frame_ms;
  const auto run_t0 = std::chrono::steady_clock::now();
  for (size_t fi = 0; fi < frames.size(); ++fi) {
    const int f = frames[fi];
    const auto t0 = std::chrono::steady_clock::now();
    const double time_s = f / a.fps;
    if (turntable) scene->cameras[opt.camera] = loaded_cameras[opt.camera];
    PoseStats ps;
    if (anim) ps = pose_scene(*anim, pose, time_s, *scene);
    if (turntable) {
      const double angle = 2.0 * M_PI * (f - range.first) / range.count();
      scene->cameras[opt.camera] = orbit_camera(scene->cameras[opt.camera], centre, angle);
    }
    Result<Plan> plan = make_plan(*scene, opt);
    if (!plan.ok())
      return (progress.clear(), fail(plan.status().message(), plan.status().exit_code()));
    if (a.explain && fi == 0) std::printf("%s", plan->explain().c_str());
    Result<RenderResult> r = (*backend)->render(*scene, *plan, opt);
    if (!r.ok()) return (progress.clear(), fail(r.status().message(), r.status().exit_code()));

    const bool named = !a.frames.empty();
    auto name_of = [&](const std::string& n) { return named ? format_frame_name(n, f) : n; };
    const std::string image_file = name_of(names.image);
    Image color = box_downsample(r->framebuffer.color, k);
    if (*exposure != 0.0f) apply_exposure(color, exposure_scale);
    // Every output of the frame is written in full to its temporary, then all are renamed.
    StagedFiles out;
    auto stage = [&out](const std::string& file, const Result<std::vector<unsigned char>>& bytes) {
      if (!bytes.ok()) return bytes.status();
      return out.stage(
          file, std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
    };
    s = stage(image_file, encode_image(image_file, color));
    if (!s.ok()) return (progress.clear(), fail(s.message(), s.exit_code()));
    for (const auto& [name, pattern] : names.aovs) {
      const std::string file = name_of(pattern);
      if (name == "depth") {
        s = stage(file, encode_plane(file, point_downsample(r->framebuffer.depth, k)));
      } else {
        for (int i = 0; i < kAovCount; ++i)
          if (name == kAovNames[i])
            s = stage(file,
                      encode_image(file, point_downsample(
                                             r->framebuffer.aov_image(static_cast<Aov>(i)), k)));
      }
      if (!s.ok()) return (progress.clear(), fail(s.message(), s.exit_code()));
    }
    if (!names.stats.empty()) {
      const std::string file = name_of(names.stats);
      RenderOptions shown = opt;
      shown.width /= k;
      shown.height /= k;
      nlohmann::json j = stats_json(*r, scene_name, shown);
      for (const PassPlan& p : plan->passes) j["plan"]["passes"][p.name] = p.reason;
      j["plan"]["skipped"] = plan->skipped;
      j["frame"] = f;
      j["time_s"] = time_s;
      j["spp"] = *spp;
      j["exposure"] = *exposure;
      if (anim) {
        j["pose"]["deform_ms"] = ps.deform_ms;
        j["pose"]["refit_ms"] = ps.refit_ms;
        j["pose"]["deformed_vertices"] = ps.vertices;
        j["pose"]["refitted_meshes"] = ps.refitted_meshes;
      }
      s = out.stage(file, j.dump(2) + "\n");
      if (!s.ok()) return (progress.clear(), fail(s.message(), s.exit_code()));
    }
    s = out.commit();
    if (!s.ok()) return (progress.clear(), fail(s.message(), s.exit_code()));
    const double total_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    frame_ms.push_back(total_ms);
    progress.clear();
    std::printf("%s: %dx%d %s on %s, frame %.1f ms, with output %.1f ms", image_file.c_str(),
                opt.width / k, opt.height / k, scene_name.c_str(), r->device.c_str(), r->frame_ms,
                total_ms);
    if (anim && !anim->deformers.empty())
      std::printf(", deform %.2f ms (%lld vertices)", ps.deform_ms, ps.vertices);
    if (ps.refitted_meshes) std::printf(", refit %.2f ms", ps.refit_ms);
    std::printf("\n");
    std::fflush(stdout);
    progress.draw(fi + 1);
    (*backend)->recycle(std::move(r).value());  // the next frame reuses its buffers
  }
  if (frames.size() > 1) {
    std::sort(frame_ms.begin(), frame_ms.end());
    const double run_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run_t0).count();
    std::printf("%zu frames (%d-%d, shard %d/%d) in %.2f s, median %.1f ms a frame\n",
                frames.size(), frames.front(), frames.back(), shard.index, shard.count, run_s,
                frame_ms[frame_ms.size() / 2]);
  }
  return 0;
}

}  // namespace

void register_render(CLI::App& app, Action& action) {
  auto a = std::make_shared<RenderArgs>();
  auto* sub = app.add_subcommand("render", "Render a scene (one frame or --frames A-B) to images");
  sub->add_option("scene", a->scene,
                  "Built-in scene name (see `relief scenes`) or .gltf/.glb file");
  sub->add_option("-o,--output", a->output, "Output image (.png 8-bit sRGB, .exr float, .tif)")
      ->required();
  sub->add_option("--size", a->size, "Image size WxH")->capture_default_str();
  sub->add_flag("--allow-outside-scene-dir", a->allow_outside_scene_dir, kAllowOutsideSceneDirHelp);
  sub->add_option("--threads", a->threads, "Worker threads, 0 = all cores")->capture_default_str();
  sub->add_option("--tile-size", a->tile_size, "Tile size in pixels (even, 8..512)")
      ->capture_default_str();
  sub->add_option("--camera", a->camera,
                  "Camera by name or index (default: the first; see docs/scene-format.md)");
  sub->add_option("--technique", a->technique,
                  "Replace the technique of every relief material (one with a depth map)");
  sub->add_option("--param", a->params,
                  "Plugin parameter key=value, for every material whose technique has it "
                  "(repeatable)");
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
  sub->add_option("--frames", a->frames,
                  "Frames A-B (or N): the scene's animation at --fps, else a turntable (the camera "
                  "orbits the scene's centre once over the range); names take %04d");
  sub->add_option("--shard", a->shard,
                  "Render only block I/N of the frames (I from 0; Slurm arrays, Kubernetes "
                  "indexed jobs)");
  sub->add_option("--spp", a->spp,
                  "Samples per pixel, a square k*k: rendered at k times the size and box-filtered")
      ->capture_default_str();
  sub->add_option("--exposure", a->exposure,
                  "Exposure in stops: linear colour times 2^EV before the output transform")
      ->capture_default_str();
  sub->add_option("--fps", a->fps, "Frames per second of the animation clock (frame f at f/fps s)")
      ->capture_default_str();
  sub->add_option("--animation", a->animation, "Animation by name or index (default: the first)");
  sub->add_flag("--turntable", a->turntable,
                "Orbit the camera over --frames even when the scene is animated");
  sub->callback([&action, a] { action = [a] { return do_render(*a); }; });
}

}  // namespace relief::cli
