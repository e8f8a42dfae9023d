// `relief render`: frames of a built-in scene (or a scene file) to images, with optional AOVs,
// per-pass statistics and the plan. One frame by default; `--frames LIST` renders a list (the
// scene's animation, else a camera turntable), `--shard I/N` a block of it (apps/frames.h).
// Farm use (README.md, "Render farms"): --skip-existing and --placeholder resume a range and
// share it between nodes; --log-json prints one JSON line a frame; --quiet prints errors only.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/environment_option.h"
#include "apps/frames.h"
#include "apps/output.h"
#include "apps/scene_source.h"
#include "apps/version.h"
#include "gl/gl_backend.h"
#include "plugins/registry.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "rasterizer/tone_map.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "render/renderer.h"
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
  std::string shadow_size = "light";
  bool whole_shadow_maps = false;
  std::string gl_interpolation = "gpu";
  std::string frames;  // LIST (apps/frames.h)
  std::string shard;   // I/N
  bool skip_existing = false;
  bool placeholder = false;  // implies skip_existing
  bool quiet = false;
  bool log_json = false;
  std::string spp = "1";
  std::string exposure = "0";
  EnvironmentArgs env;  // --env, --env-intensity, --env-rotation
  // --height-ao RAYS, --height-ao-radius, --height-ao-strength: set only when given
  std::optional<int> height_ao;
  std::optional<float> height_ao_radius, height_ao_strength;
  std::string tonemap;         // --tonemap
  bool tonemap_given = false;  // else the default of the scene's source
  std::string alpha = "none";  // --alpha (apps/output.h OutputAlpha)
  double fps = 24.0;
  std::string animation;
  bool turntable = false;
  bool allow_outside_scene_dir = false;
  bool strict = false;
};

// The derived maps (cone maps) one frame's plan baked or found in the cache, for --stats.
nlohmann::json bake_json(const BakeStats& bake) {
  return {{"ms", bake.bake_ms},
          {"cache_ms", bake.cache_ms},
          {"baked", bake.baked},
          {"memory_cache_hits", bake.memory_hits},
          {"disk_cache_hits", bake.disk_hits}};
}

nlohmann::json stats_json(const RenderResult& r, const std::string& scene, int width, int height) {
  nlohmann::json j;
  j["build"] = build_info_json();
  j["scene"] = scene;
  j["width"] = width;
  j["height"] = height;
  j["device"] = r.device;
  j["frame_ms"] = r.frame_ms;
  j["prepare_ms"] = r.prepare_ms;
  j["compile_ms"] = r.compile_ms;
  j["upload_ms"] = r.upload_ms;
  j["readback_ms"] = r.readback_ms;
  j["geometry_ms"] = r.geometry_ms;
  j["geometry_reused"] = r.geometry_reused;
  j["geometry_prepared"] = r.geometry_prepared;
  j["target_ms"] = r.target_ms;
  j["other_ms"] = unaccounted_ms(r);
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
    pj["tiles"] = s.tiles;
    pj["tiles_drawn"] = s.tiles_drawn;
    pj["fragments_shaded"] = s.work.fragments;
    pj["fragments_discarded"] = s.work.discarded;
    pj["texture_fetches"] = s.work.texture_fetches;
    pj["search_steps"] = s.work.search_steps;
    pj["shadow_steps"] = s.work.shadow_steps;
    j["passes"].push_back(pj);
  }
  return j;
}

// A progress bar on stderr, drawn only when stderr is a terminal, not --quiet, and more than one
// frame renders.
class Progress {
 public:
  Progress(size_t total, bool quiet)
      : total_(total), on_(total > 1 && !quiet && ::isatty(STDERR_FILENO)) {
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

// The cone-map bakes of a first render: a line naming the map and a bar on stderr, only on a
// terminal and not --quiet (render/derived_maps.h reports them). Installed for its lifetime.
class BakeProgress {
 public:
  BakeProgress(bool quiet, Progress& frames) : frames_(frames) {
    if (quiet || !::isatty(STDERR_FILENO)) return;
    set_derived_map_progress([this](const std::string& what, float f) { draw(what, f); });
    on_ = true;
  }
  ~BakeProgress() {
    if (on_) set_derived_map_progress(nullptr);
  }

 private:
  void draw(const std::string& what, float f) {
    const auto now = std::chrono::steady_clock::now();
    if (f <= 0.0f) {
      frames_.clear();
      t0_ = now;
      last_pct_ = -1;
      std::fprintf(stderr, "baking %s (first use; cached afterwards)\n", what.c_str());
    }
    const int pct = static_cast<int>(f * 100.0f);
    if (pct == last_pct_) return;
    last_pct_ = pct;
    const double s = std::chrono::duration<double>(now - t0_).count();
    const int width = 30, fill = std::clamp(pct * width / 100, 0, width);
    std::fprintf(stderr, "\r\033[K[%s%s] %3d%%, %.1f s", std::string(fill, '#').c_str(),
                 std::string(width - fill, '.').c_str(), pct, s);
    if (f >= 1.0f) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  Progress& frames_;
  bool on_ = false;
  std::chrono::steady_clock::time_point t0_;
  int last_pct_ = -1;
};

// --skip-existing: an output is there when it is a regular file, not empty unless
// `empty_counts` (--placeholder: an empty file is a claim of another run).
bool output_there(const std::string& path, bool empty_counts) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  return st.st_size > 0 || empty_counts;
}

bool output_empty(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_size == 0;
}

// --placeholder: the empty file created at a frame's image path with O_CREAT | O_EXCL before the
// frame renders, so that of several runs over one folder exactly one renders it. The rendered
// image replaces it atomically (rename); release() just before that keeps it. While held, a
// failure of the frame (the destructor) or SIGTERM / SIGINT / SIGHUP removes it again.
class Claim {
 public:
  // Creates the claim: true when this run holds it, false when `path` already exists (another
  // run's claim or output); an error for anything else, naming `path`.
  Result<bool> take(const std::string& path) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      if (errno == EEXIST) return false;
      return Status::error(printable(path) +
                           ": cannot create the --placeholder claim: " + std::strerror(errno));
    }
    struct stat st;
    const bool stat_ok = ::fstat(fd, &st) == 0;
    ::close(fd);
    path_ = path;
    if (stat_ok) dev_ = st.st_dev, ino_ = st.st_ino;
    std::error_code ec;
    const std::filesystem::path abs = std::filesystem::absolute(path, ec);
    slot_ = register_signal_removal(ec ? path : abs.string());
    return true;
  }
  void release() {
    unregister_signal_removal(slot_);
    slot_ = -1;
    path_.clear();
  }
  ~Claim() {
    if (path_.empty()) return;
    unregister_signal_removal(slot_);
    struct stat st;  // only our own empty file, never an output put there since
    if (::stat(path_.c_str(), &st) == 0 && st.st_dev == dev_ && st.st_ino == ino_ &&
        st.st_size == 0)
      ::unlink(path_.c_str());
  }

 private:
  std::string path_;
  dev_t dev_ = 0;
  ino_t ino_ = 0;
  int slot_ = -1;
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

// One frame's outputs in order: the image, the AOVs, the statistics.
std::vector<std::string> frame_outputs(const OutputNames& names, bool named, int frame) {
  auto name_of = [&](const std::string& n) { return named ? format_frame_name(n, frame) : n; };
  std::vector<std::string> files{name_of(names.image)};
  for (const auto& [aov, file] : names.aovs) files.push_back(name_of(file));
  if (!names.stats.empty()) files.push_back(name_of(names.stats));
  return files;
}

// --log-json: one line a frame on stdout (docs: README.md, "Render farms").
void log_frame(int frame, const char* status, const std::vector<std::string>& outputs, double ms,
               const nlohmann::json& extra = nlohmann::json::object()) {
  nlohmann::json j = {{"frame", frame}, {"status", status}, {"outputs", outputs}, {"ms", ms}};
  for (const auto& [k, v] : extra.items()) j[k] = v;
  const std::string line = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  std::fputs(line.c_str(), stdout);
  std::fflush(stdout);
}

// --skip-existing: why a frame with these outputs is skipped ("exists": every output is there;
// "claimed": --placeholder and its image is empty, another run's claim), or nullptr.
const char* skip_reason(const std::vector<std::string>& files, bool placeholder) {
  if (placeholder && output_empty(files[0])) return "claimed";
  for (const std::string& file : files)
    if (!output_there(file, placeholder)) return nullptr;
  return "exists";
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Everything `relief render` knows before it loads the scene, checked in the order the errors are
// reported.
struct RenderJob {
  std::string scene_name;
  RenderOptions opt;  // at the supersampled size (k times the output's)
  BackendConfig backend;
  OutputNames names;
  FrameList list{{0}};
  bool named = false;  // --frames given: output names take the frame pattern
  Shard shard;
  int spp = 1;
  int k = 1;  // supersampling grid side
  float exposure = 0.0f;
  ToneCurve tone = ToneCurve::kNone;  // for 8-bit outputs (scene/image_io.h image_is_8bit)
  bool tone_asked = false;            // --tonemap given (else the default of the scene's source)
  OutputAlpha alpha_mode = OutputAlpha::kNone;
  std::vector<int> frames;  // this shard's
  bool skip_existing = false;
};

// --param key=value into opt.params.
Status parse_params(const std::vector<std::string>& params, RenderOptions& opt) {
  for (const std::string& kv : params) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      return Status::usage("--param: expected key=value, got '" + kv + "'");
    opt.params[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return {};
}

// --aov NAME=FILE into opt.aovs and names.aovs.
Status parse_aovs(const std::vector<std::string>& aovs, RenderOptions& opt, OutputNames& names) {
  for (const std::string& kv : aovs) {
    const size_t eq = kv.find('=');
    const std::string name = kv.substr(0, eq);
    if (eq == std::string::npos || eq + 1 >= kv.size())
      return Status::usage("--aov: expected NAME=FILE, got '" + kv + "'");
    bool known = name == "depth";
    for (int i = 0; i < kAovCount; ++i)
      if (name == kAovNames[i]) {
        known = true;
        opt.aovs |= aov_bit(static_cast<Aov>(i));
      }
    if (!known)
      return Status::usage("--aov: unknown AOV '" + name +
                           "' (depth, uv, hit_depth, steps, normal)");
    if (names.aovs.count(name))
      return Status::usage("--aov: '" + name + "' is given twice (one file per AOV)");
    names.aovs[name] = kv.substr(eq + 1);
  }
  return {};
}

// Size, threads, tile size, technique, effects, parameters and AOVs.
Status parse_frame_options(const RenderArgs& a, RenderJob& job) {
  RenderOptions& opt = job.opt;
  RELIEF_RETURN_IF_ERROR(parse_size(a.size, opt.width, opt.height));
  if (a.threads < 0 || a.threads > 256) return Status::usage("--threads: expected 0..256");
  if (a.tile_size < 8 || a.tile_size > 512 || a.tile_size % 2)
    return Status::usage("--tile-size: expected an even number in 8..512");
  job.backend.threads = a.threads;
  job.backend.tile_size = a.tile_size;
  job.backend.gpu = a.gpu;
  job.backend.count_work = !a.stats.empty();  // the GL backend counts only when asked
  Result<GlInterpolation> interpolation = parse_gl_interpolation(a.gl_interpolation);
  if (!interpolation.ok()) return interpolation.status();
  job.backend.gl_interpolation = *interpolation;
  opt.technique = a.technique;
  opt.scalar_lanes = a.scalar;
  opt.shadows = !a.no_shadows;
  opt.self_shadow = !a.no_self_shadow;
  opt.shadow = a.shadow;
  if (a.shadow_size != "view" && a.shadow_size != "light")
    return Status::usage("--shadow-size: expected view or light, got '" + a.shadow_size + "'");
  opt.shadow_size = a.shadow_size == "view" ? ShadowSize::kView : ShadowSize::kLight;
  opt.shadow_on_demand = !a.whole_shadow_maps;
  RELIEF_RETURN_IF_ERROR(parse_params(a.params, opt));
  RELIEF_RETURN_IF_ERROR(apply_environment_options(a.env, opt));
  opt.height_ao_rays = a.height_ao;
  opt.height_ao_radius = a.height_ao_radius;
  opt.height_ao_strength = a.height_ao_strength;
  job.names = OutputNames{a.output, {}, a.stats};
  return parse_aovs(a.aovs, opt, job.names);
}

// --tonemap, or its default: pbr-neutral for a glTF file (the Khronos glTF Sample Viewer's
// default), none for a built-in scene (its look before tone curves).
Status parse_tonemap(const RenderArgs& a, RenderJob& job) {
  const std::string& text = a.tonemap;
  job.tone_asked = a.tonemap_given;
  if (!job.tone_asked) {
    job.tone = is_scene_path(job.scene_name) ? ToneCurve::kPbrNeutral : ToneCurve::kNone;
    return {};
  }
  if (!parse_tone_curve(text, job.tone))
    return Status::usage("--tonemap: expected none, aces or pbr-neutral, got '" + printable(text) +
                         "'");
  return {};
}

// The output transform for --explain: exposure, the tone curve and why, the encoding.
std::string explain_output(const RenderJob& job, const std::string& image_file) {
  char ev[32];
  std::snprintf(ev, sizeof ev, "%+g", job.exposure);
  std::string out = "output transform: exposure " + std::string(ev) + " EV, ";
  const std::string curve = tone_curve_name(job.tone);
  const std::string why =
      job.tone_asked ? "asked by --tonemap"
                     : (is_scene_path(job.scene_name)
                            ? "the default for a glTF file, as the Khronos glTF Sample Viewer's"
                            : "the default for a built-in scene: its look before tone curves");
  if (image_is_8bit(image_file))
    out +=
        "tone curve " + curve + " (" + why + "), then 8-bit sRGB (" + printable(image_file) + ")\n";
  else
    out += "no tone curve: " + printable(image_file) + " is a linear file (float or 16-bit), " +
           curve + " (" + why + ") applies to 8-bit outputs only\n";
  return out;
}

// Frames, shards, samples, exposure, tone curve, alpha, fps, backend and the output files: all
// checked before anything renders.
Status parse_frames_and_outputs(const RenderArgs& a, RenderJob& job) {
  job.named = !a.frames.empty();
  if (job.named) {
    Result<FrameList> r = parse_frames(a.frames);
    if (!r.ok()) return Status::usage(r.status().message());
    job.list = std::move(r).value();
  }
  if (!a.shard.empty()) {
    if (!job.named) return Status::usage("--shard: needs --frames (the list to split)");
    Result<Shard> r = parse_shard(a.shard);
    if (!r.ok()) return Status::usage(r.status().message());
    job.shard = *r;
  }
  Result<int> spp = parse_spp(a.spp);
  if (!spp.ok()) return Status::usage(spp.status().message());
  job.spp = *spp;
  const int k = job.k = static_cast<int>(std::lround(std::sqrt(*spp)));
  const RenderOptions& opt = job.opt;
  if (static_cast<long long>(opt.width) * k > kMaxTargetSize ||
      static_cast<long long>(opt.height) * k > kMaxTargetSize ||
      static_cast<long long>(opt.width) * opt.height * k * k > kMaxTargetPixels)
    return Status::usage("--spp: " + a.spp + " samples at " + a.size + " render " +
                         std::to_string(opt.width * k) + "x" + std::to_string(opt.height * k) +
                         ", over the limit of " + std::to_string(kMaxTargetSize) + " a side and " +
                         std::to_string(kMaxTargetPixels) + " pixels");
  Result<float> exposure = parse_exposure(a.exposure);
  if (!exposure.ok()) return Status::usage(exposure.status().message());
  job.exposure = *exposure;
  RELIEF_RETURN_IF_ERROR(parse_tonemap(a, job));
  Status s = parse_output_alpha(a.alpha, job.alpha_mode);
  if (!s.ok()) return Status::usage(s.message());
  if (!(a.fps > 0.0 && a.fps <= 1000.0))
    return Status::usage("--fps: expected a number of frames per second in (0, 1000]");
  if (a.backend != "cpu" && a.backend != "gl")
    return Status::usage("--backend: expected cpu or gl, got '" + a.backend + "'");
  s = job.names.check(job.named && job.list.count() > 1);
  if (!s.ok()) return Status::usage(s.message());
  job.frames = shard_frames(job.list, job.shard);
  return job.names.check_files(job.frames, job.named);
}

Result<RenderJob> make_render_job(const RenderArgs& a) {
  RenderJob job;
  // The scene path first: "scenes: is a directory" before any question about the outputs.
  job.scene_name = a.scene.empty() ? default_scene_source() : a.scene;
  RELIEF_RETURN_IF_ERROR(check_scene_source(job.scene_name));
  if (a.output.empty()) return Status::usage("--output is required (e.g. -o frame.png)");
  RELIEF_RETURN_IF_ERROR(parse_frame_options(a, job));
  RELIEF_RETURN_IF_ERROR(parse_frames_and_outputs(a, job));
  job.opt.width *= job.k;
  job.opt.height *= job.k;
  job.skip_existing = a.skip_existing || a.placeholder;
  return job;
}

// The frames of a `relief render` run, one after the other, through one Renderer.
class FrameLoop {
 public:
  FrameLoop(const RenderArgs& a, const RenderJob& job, Scene& scene, Renderer& renderer,
            std::vector<GltfIgnored> ignored)
      : a_(a),
        job_(job),
        scene_(scene),
        renderer_(renderer),
        ignored_(std::move(ignored)),
        human_(a.log_json ? stderr : stdout),
        progress_(job.frames.size(), a.quiet),
        bake_progress_(a.quiet, progress_) {}

  // Poses every frame's scene, renders it and writes its outputs; the exit code.
  int run(const PoseOptions& pose) {
    pose_ = pose;
    anim_ = scene_.animation;
    const bool has_clips = anim_ && !anim_->clips.empty();
    // Turntable: with --frames when the scene has no animation (or with --turntable). The angle
    // is the frame's place in the whole list's span, so every shard and rerun agrees.
    turntable_ = job_.named && (a_.turntable || !has_clips);
    glm::dvec3 lo, hi;
    scene_bounds(scene_, lo, hi);
    centre_ = (lo + hi) * 0.5;
    loaded_cameras_ = scene_.cameras;
    const auto run_t0 = std::chrono::steady_clock::now();
    for (size_t fi = 0; fi < job_.frames.size(); ++fi)
      if (const int rc = frame(fi); rc != 0) return rc;
    progress_.clear();  // the summary gets a line of its own
    summary(run_t0);
    return 0;
  }

 private:
  // One frame: skipped, or posed, rendered and written.
  int frame(size_t fi) {
    const int f = job_.frames[fi];
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<std::string> files = frame_outputs(job_.names, job_.named, f);
    // A failed frame: its JSON line, then the one error line on stderr.
    auto frame_failed = [&](const Status& st) {
      progress_.clear();
      if (a_.log_json) log_frame(f, "failed", files, ms_since(t0), {{"error", st.message()}});
      return fail(st.message(), st.exit_code());
    };
    Claim claim;
    if (job_.skip_existing) {
      Result<const char*> why = skip_or_claim(files, claim);
      if (!why.ok()) return frame_failed(why.status());
      if (*why) {
        ++skipped_;
        if (a_.log_json) log_frame(f, "skipped", files, ms_since(t0), {{"reason", *why}});
        progress_.draw(fi + 1);
        return 0;
      }
    }
    const double time_s = f / a_.fps;
    const PoseStats ps = pose_frame(f, time_s);
    Result<Frame> fr = renderer_.render(scene_, job_.opt);
    if (!fr.ok()) return frame_failed(fr.status());
    if (a_.explain && fi == 0) {
      std::fprintf(human_, "%s", fr->plan.explain().c_str());
      std::fprintf(human_, "%s",
                   explain_ignored(scene_, ignored_, is_scene_path(job_.scene_name)).c_str());
      std::fprintf(human_, "%s", explain_output(job_, files[0]).c_str());
    }
    const auto t_out = std::chrono::steady_clock::now();
    Status s = write_outputs(*fr, files, f, time_s, ps, claim);
    if (!s.ok()) return frame_failed(s);
    const double output_ms = ms_since(t_out), total_ms = ms_since(t0);
    frame_ms_.push_back(total_ms);
    progress_.clear();
    report_frame(*fr, f, files, ps, output_ms, total_ms);
    progress_.draw(fi + 1);
    renderer_.recycle(std::move(fr).value());  // the next frame reuses its buffers
    return 0;
  }

  // --skip-existing / --placeholder: why the frame is skipped (nullptr: render it), taking the
  // placeholder claim when it is not.
  Result<const char*> skip_or_claim(const std::vector<std::string>& files, Claim& claim) {
    const char* why = skip_reason(files, a_.placeholder);
    if (!why && a_.placeholder) {
      Result<bool> took = claim.take(files[0]);
      if (!took.ok()) return took.status();
      // Not taken: another run claimed it since (or the image is there but another output is
      // not, deleted since: then it is rendered again).
      if (!*took && output_empty(files[0])) why = "claimed";
    }
    return why;
  }

  // The scene at frame f: its animation at time_s, the turntable camera.
  PoseStats pose_frame(int f, double time_s) {
    const int cam = job_.opt.camera;
    if (turntable_) scene_.cameras[cam] = loaded_cameras_[cam];
    PoseStats ps;
    if (anim_) ps = pose_scene(*anim_, pose_, time_s, scene_);
    if (turntable_) {
      const FrameList& list = job_.list;
      const double angle = 2.0 * M_PI * (f - list.first()) / (list.last() - list.first() + 1);
      scene_.cameras[cam] = orbit_camera(scene_.cameras[cam], centre_, angle);
    }
    return ps;
  }

  // Every output of the frame is written in full to its temporary, then all are renamed. The
  // image is staged (and renamed) last, so a non-empty image means a complete frame.
  Status write_outputs(const Frame& fr, const std::vector<std::string>& files, int f, double time_s,
                       const PoseStats& ps, Claim& claim) {
    const int k = job_.k;
    const Framebuffer& fb = fr.result.framebuffer;
    Image color = box_downsample(fb.color, k);
    if (job_.exposure != 0.0f) apply_exposure(color, std::exp2(job_.exposure));
    if (image_is_8bit(files[0])) apply_tone_curve(color, job_.tone);  // float files stay linear
    apply_output_alpha(color, job_.alpha_mode);
    StagedFiles out;
    auto stage = [&out](const std::string& file, const Result<std::vector<unsigned char>>& bytes) {
      if (!bytes.ok()) return bytes.status();
      return out.stage(
          file, std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
    };
    size_t file_index = 1;
    for (const auto& [name, pattern] : job_.names.aovs) {
      const std::string& file = files[file_index++];
      Status s;
      if (name == "depth") {
        s = stage(file, encode_plane(file, point_downsample(fb.depth, k)));
      } else {
        for (int i = 0; i < kAovCount; ++i)
          if (name == kAovNames[i])
            s = stage(file,
                      encode_image(file, point_downsample(fb.aov_image(static_cast<Aov>(i)), k)));
      }
      RELIEF_RETURN_IF_ERROR(s);
    }
    if (!job_.names.stats.empty())
      RELIEF_RETURN_IF_ERROR(
          out.stage(files.back(), frame_stats(fr, f, time_s, ps).dump(2) + "\n"));
    // The image last: once it is there (not empty), every output of the frame is.
    const std::string& image_file = files[0];
    RELIEF_RETURN_IF_ERROR(
        stage(image_file, encode_image(image_file, color, output_channels(job_.alpha_mode),
                                       job_.alpha_mode == OutputAlpha::kPremultiplied)));
    claim.release();  // the outputs are renamed into place next, the image over the claim
    return out.commit();
  }

  // --stats: the frame's passes, plan, bakes and pose as JSON.
  nlohmann::json frame_stats(const Frame& fr, int f, double time_s, const PoseStats& ps) const {
    nlohmann::json j =
        stats_json(fr.result, job_.scene_name, job_.opt.width / job_.k, job_.opt.height / job_.k);
    for (const PassPlan& p : fr.plan.passes) j["plan"]["passes"][p.name] = p.reason;
    j["plan"]["skipped"] = fr.plan.skipped;
    j["frame"] = f;
    j["time_s"] = time_s;
    j["spp"] = job_.spp;
    j["exposure"] = job_.exposure;
    j["tonemap"] = tone_curve_name(job_.tone);
    j["tonemap_applied"] = job_.tone != ToneCurve::kNone && image_is_8bit(job_.names.image);
    j["bake"] = bake_json(fr.bake);
    if (anim_) {
      j["pose"]["deform_ms"] = ps.deform_ms;
      j["pose"]["refit_ms"] = ps.refit_ms;
      j["pose"]["deformed_vertices"] = ps.vertices;
      j["pose"]["refitted_meshes"] = ps.refitted_meshes;
    }
    return j;
  }

  // The frame's --log-json line, or its line on stdout (not --quiet).
  void report_frame(const Frame& fr, int f, const std::vector<std::string>& files,
                    const PoseStats& ps, double output_ms, double total_ms) const {
    const BakeStats& bake = fr.bake;
    const RenderResult& r = fr.result;
    if (a_.log_json) {
      log_frame(f, "rendered", files, total_ms,
                {{"frame_ms", r.frame_ms},
                 {"output_ms", output_ms},
                 {"bake_ms", bake.bake_ms},
                 {"baked", bake.baked},
                 {"cached", bake.cached()}});
      return;
    }
    if (a_.quiet) return;
    std::printf("%s: %dx%d %s on %s, frame %.1f ms", files[0].c_str(), job_.opt.width / job_.k,
                job_.opt.height / job_.k, job_.scene_name.c_str(), r.device.c_str(), r.frame_ms);
    if (bake.baked > 0)
      std::printf(", derived-map bake %.0f ms (baked %d, cached %d)", bake.bake_ms, bake.baked,
                  bake.cached());
    else if (bake.disk_hits > 0)
      std::printf(", cone maps from the disk cache %.1f ms (%d)", bake.cache_ms, bake.disk_hits);
    std::printf(", output %.1f ms", output_ms);
    if (anim_ && !anim_->deformers.empty())
      std::printf(", deform %.2f ms (%lld vertices)", ps.deform_ms, ps.vertices);
    if (ps.refitted_meshes) std::printf(", refit %.2f ms", ps.refit_ms);
    std::printf("\n");
    std::fflush(stdout);
  }

  // The run's summary line (more than one frame, or frames skipped; not --quiet).
  void summary(std::chrono::steady_clock::time_point run_t0) {
    const std::vector<int>& frames = job_.frames;
    if ((frames.size() <= 1 && !skipped_) || a_.quiet) return;
    const double run_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run_t0).count();
    std::fprintf(human_, "%zu frame%s (%d-%d, shard %d/%d) in %.2f s", frames.size(),
                 frames.size() == 1 ? "" : "s", frames.front(), frames.back(), job_.shard.index,
                 job_.shard.count, run_s);
    if (!frame_ms_.empty()) {
      std::sort(frame_ms_.begin(), frame_ms_.end());
      std::fprintf(human_, ", median %.1f ms a frame", frame_ms_[frame_ms_.size() / 2]);
    }
    if (job_.skip_existing)
      std::fprintf(human_, "; rendered %zu, skipped %d (outputs there or claimed)",
                   frame_ms_.size(), skipped_);
    std::fprintf(human_, "\n");
  }

  const RenderArgs& a_;
  const RenderJob& job_;
  Scene& scene_;
  Renderer& renderer_;
  std::vector<GltfIgnored> ignored_;
  FILE* human_;  // --log-json keeps stdout for JSON lines
  Progress progress_;
  BakeProgress bake_progress_;
  PoseOptions pose_;
  std::shared_ptr<const SceneAnimation> anim_;
  bool turntable_ = false;
  glm::dvec3 centre_{0.0};
  std::vector<Camera> loaded_cameras_;
  std::vector<double> frame_ms_;
  int skipped_ = 0;
};

// --skip-existing with every output of every frame there: nothing to render, not even the scene
// is loaded. Reports the skips; false when something has to render.
bool all_frames_skipped(const RenderArgs& a, const RenderJob& job) {
  const std::vector<int>& frames = job.frames;
  if (!job.skip_existing || frames.empty() ||
      !std::all_of(frames.begin(), frames.end(), [&](int f) {
        return skip_reason(frame_outputs(job.names, job.named, f), a.placeholder) != nullptr;
      }))
    return false;
  for (int f : frames)
    if (a.log_json) {
      const std::vector<std::string> files = frame_outputs(job.names, job.named, f);
      log_frame(f, "skipped", files, 0.0, {{"reason", skip_reason(files, a.placeholder)}});
    }
  if (!a.quiet)
    std::fprintf(a.log_json ? stderr : stdout,
                 "%zu frame%s (%d-%d, shard %d/%d): rendered 0, skipped %zu (outputs there "
                 "or claimed)\n",
                 frames.size(), frames.size() == 1 ? "" : "s", frames.front(), frames.back(),
                 job.shard.index, job.shard.count, frames.size());
  return true;
}

int do_render(const RenderArgs& a) {
  Result<RenderJob> made = make_render_job(a);
  if (!made.ok()) return fail(made.status().message(), made.status().exit_code());
  RenderJob& job = *made;
  if (all_frames_skipped(a, job)) return 0;
  for (const std::string& p : a.plugins) {
    Status ls = load_plugin_arg(p);
    if (!ls.ok()) return fail(ls.message(), ls.exit_code());
  }
  std::vector<GltfIgnored> ignored;
  Result<Scene> scene =
      load_scene_source(job.scene_name, a.allow_outside_scene_dir, a.strict, &ignored);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  Result<int> camera = resolve_camera(*scene, a.camera);
  if (!camera.ok()) return fail(camera.status().message(), camera.status().exit_code());
  job.opt.camera = *camera;
  Result<int> clip = resolve_clip(*scene, a.animation);
  if (!clip.ok()) return fail(clip.status().message(), clip.status().exit_code());
  PoseOptions pose;
  pose.clip = *clip;
  pose.technique = a.technique;

  Result<std::unique_ptr<Backend>> backend = make_backend(a.backend, job.backend);
  if (!backend.ok()) return fail(backend.status().message(), backend.status().exit_code());
  if (job.frames.empty()) {
    if (!a.quiet)
      std::fprintf(a.log_json ? stderr : stdout, "shard %d/%d: no frames (the list has %d)\n",
                   job.shard.index, job.shard.count, job.list.count());
    return 0;
  }
  Renderer renderer(std::move(backend).value());
  FrameLoop loop(a, job, *scene, renderer, std::move(ignored));
  return loop.run(pose);
}

}  // namespace

void register_render(CLI::App& app, Action& action) {
  auto a = std::make_shared<RenderArgs>();
  auto* sub =
      app.add_subcommand("render", "Render a scene (one frame or a --frames list) to images");
  sub->add_option("scene", a->scene,
                  "Built-in scene name (see `relief scenes`) or .gltf/.glb file");
  sub->add_option("-o,--output", a->output,
                  "Output image (.png 8-bit sRGB, .exr float, .tif); required");
  sub->add_option("--size", a->size, "Image size WxH")->capture_default_str();
  sub->add_flag("--allow-outside-scene-dir", a->allow_outside_scene_dir, kAllowOutsideSceneDirHelp);
  sub->add_flag("--strict", a->strict, kStrictHelp);
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
  sub->add_option("--plugin", a->plugins, "Load an external plugin (.so; a bare name is ./NAME)");
  sub->add_option("--stats", a->stats,
                  "Write per-pass counters, timings, cone-map bakes and the build as JSON");
  sub->add_option("--backend", a->backend, "cpu or gl")->capture_default_str();
  sub->add_option("--gpu", a->gpu, "GL backend: EGL device index (-1 = first usable)");
  sub->add_option("--gl-interpolation", a->gl_interpolation,
                  "GL backend: gpu (GL interpolates world-space vertices kept on the GPU across "
                  "frames) or cpu-planes (the CPU rasterizer's planes of every triangle, "
                  "uploaded each pass: both backends shade the same numbers)")
      ->capture_default_str();
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
  sub->add_option("--shadow-size", a->shadow_size,
                  "Shadow-map texels per side: light (the light's shadow_resolution) or view (at "
                  "most that, no more than a texel per pixel of this view: faster small frames, "
                  "coarser shadow detail)")
      ->capture_default_str();
  sub->add_flag("--whole-shadow-maps", a->whole_shadow_maps,
                "CPU: draw every texel of each shadow map before the main pass, instead of the "
                "tiles the main pass's lookups reach (the image is the same; for timing)");
  sub->add_option("--frames", a->frames,
                  "Frames: N, A-B, A-B:STEP, comma-separated (1,5,10-20,30-90:3): the scene's "
                  "animation at --fps, else a turntable (the camera orbits the scene's centre "
                  "once from the first to the last frame); names take %04d");
  sub->add_option("--shard", a->shard,
                  "Render only block I/N of the --frames list (I from 0; Slurm arrays, Kubernetes "
                  "indexed jobs)");
  sub->add_flag("--skip-existing", a->skip_existing,
                "Skip a frame whose outputs (image, every --aov, --stats) all exist and are not "
                "empty (resume a range)");
  sub->add_flag("--placeholder", a->placeholder,
                "Claim each frame first with an empty image file (O_EXCL) so runs sharing a "
                "folder skip it; implies --skip-existing, an empty file counts as claimed");
  sub->add_flag("-q,--quiet", a->quiet, "Print errors only (and warnings)");
  sub->add_flag("--log-json", a->log_json,
                "One JSON line a frame on stdout: frame, status (rendered, skipped, failed), "
                "outputs, ms, frame_ms, bake_ms; other lines go to stderr");
  sub->add_option("--spp", a->spp,
                  "Samples per pixel, a square k*k: rendered at k times the size and box-filtered")
      ->capture_default_str();
  sub->add_option("--exposure", a->exposure,
                  "Exposure in stops: linear colour times 2^EV before the output transform")
      ->capture_default_str();
  add_environment_options(*sub, a->env);
  sub->add_option_function<int>(
      "--height-ao", [a](const int& v) { a->height_ao = v; },
      "Height-field ambient occlusion on every relief material: RAYS directions (0 off, at most "
      "16; docs/effects.md)");
  sub->add_option_function<float>(
      "--height-ao-radius", [a](const float& v) { a->height_ao_radius = v; },
      "Height-field AO search radius in uv units, [0, 1] (default the material's, 0.05)");
  sub->add_option_function<float>(
      "--height-ao-strength", [a](const float& v) { a->height_ao_strength = v; },
      "Height-field AO strength, [0, 1] (default the material's, 1)");
  sub->add_option("--tonemap", a->tonemap,
                  "Tone curve for 8-bit outputs (.png): none (clamp), aces (ACES filmic, Hill's "
                  "fit) or pbr-neutral (Khronos PBR Neutral); default pbr-neutral for a glTF "
                  "file, none for a built-in scene; .exr and .tif stay linear (docs/effects.md)")
      ->each([a](const std::string&) { a->tonemap_given = true; });
  sub->add_option("--alpha", a->alpha,
                  "Output alpha: none (RGB), straight or premultiplied (RGBA; docs/aovs.md)")
      ->capture_default_str();
  sub->add_option("--fps", a->fps, "Frames per second of the animation clock (frame f at f/fps s)")
      ->capture_default_str();
  sub->add_option("--animation", a->animation, "Animation by name or index (default: the first)");
  sub->add_flag("--turntable", a->turntable,
                "Orbit the camera over --frames even when the scene is animated");
  sub->callback([&action, a] { action = [a] { return do_render(*a); }; });
}

}  // namespace relief::cli
