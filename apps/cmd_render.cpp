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
#include "apps/frames.h"
#include "apps/output.h"
#include "apps/scene_source.h"
#include "apps/version.h"
#include "plugins/registry.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "render/derived_maps.h"
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
  std::string frames;  // LIST (apps/frames.h)
  std::string shard;   // I/N
  bool skip_existing = false;
  bool placeholder = false;  // implies skip_existing
  bool quiet = false;
  bool log_json = false;
  std::string spp = "1";
  std::string exposure = "0";
  std::string alpha = "none";  // --alpha (apps/output.h OutputAlpha)
  double fps = 24.0;
  std::string animation;
  bool turntable = false;
  bool allow_outside_scene_dir = false;
  bool strict = false;
};

// The derived maps (cone maps) one frame's plan asked for: the counters' growth over make_plan.
struct BakeStats {
  int baked = 0, memory_hits = 0, disk_hits = 0;
  double bake_ms = 0.0, cache_ms = 0.0;
  static BakeStats since(const DerivedMapCounters& before) {
    const DerivedMapCounters now = derived_map_counters();
    return {now.baked - before.baked, now.memory_hits - before.memory_hits,
            now.disk_hits - before.disk_hits, now.bake_ms - before.bake_ms,
            now.cache_ms - before.cache_ms};
  }
  int cached() const { return memory_hits + disk_hits; }
  nlohmann::json json() const {
    return {{"ms", bake_ms},
            {"cache_ms", cache_ms},
            {"baked", baked},
            {"memory_cache_hits", memory_hits},
            {"disk_cache_hits", disk_hits}};
  }
};

nlohmann::json stats_json(const RenderResult& r, const std::string& scene,
                          const RenderOptions& opt) {
  nlohmann::json j;
  j["build"] = build_info_json();
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

int do_render(const RenderArgs& a) {
  // The scene path first: "scenes: is a directory" before any question about the outputs.
  const std::string scene_name = a.scene.empty() ? default_scene_source() : a.scene;
  if (Status cs = check_scene_source(scene_name); !cs.ok())
    return fail(cs.message(), cs.exit_code());
  if (a.output.empty()) return fail("--output is required (e.g. -o frame.png)", 2);
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
    if (names.aovs.count(name))
      return fail("--aov: '" + name + "' is given twice (one file per AOV)", 2);
    names.aovs[name] = kv.substr(eq + 1);
  }
  // Frames, shards, samples, exposure: all checked before anything renders.
  FrameList list{{0}};
  const bool named = !a.frames.empty();  // output names take the frame pattern
  if (named) {
    Result<FrameList> r = parse_frames(a.frames);
    if (!r.ok()) return fail(r.status().message(), 2);
    list = std::move(r).value();
  }
  Shard shard;
  if (!a.shard.empty()) {
    if (!named) return fail("--shard: needs --frames (the list to split)", 2);
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
  OutputAlpha alpha_mode = OutputAlpha::kNone;
  s = parse_output_alpha(a.alpha, alpha_mode);
  if (!s.ok()) return fail(s.message(), 2);
  if (!(a.fps > 0.0 && a.fps <= 1000.0))
    return fail("--fps: expected a number of frames per second in (0, 1000]", 2);
  if (a.backend != "cpu" && a.backend != "gl")
    return fail("--backend: expected cpu or gl, got '" + a.backend + "'", 2);
  s = names.check(named && list.count() > 1);
  if (!s.ok()) return fail(s.message(), 2);
  const std::vector<int> frames = shard_frames(list, shard);
  s = names.check_files(frames, named);
  if (!s.ok()) return fail(s.message(), s.exit_code());
  opt.width *= k;
  opt.height *= k;
  const bool skip_existing = a.skip_existing || a.placeholder;
  FILE* const human = a.log_json ? stderr : stdout;  // --log-json keeps stdout for JSON lines
  if (skip_existing && !frames.empty() && std::all_of(frames.begin(), frames.end(), [&](int f) {
        return skip_reason(frame_outputs(names, named, f), a.placeholder) != nullptr;
      })) {  // nothing to render: not even the scene is loaded
    for (int f : frames)
      if (a.log_json) {
        const std::vector<std::string> files = frame_outputs(names, named, f);
        log_frame(f, "skipped", files, 0.0, {{"reason", skip_reason(files, a.placeholder)}});
      }
    if (!a.quiet)
      std::fprintf(human,
                   "%zu frame%s (%d-%d, shard %d/%d): rendered 0, skipped %zu (outputs there "
                   "or claimed)\n",
                   frames.size(), frames.size() == 1 ? "" : "s", frames.front(), frames.back(),
                   shard.index, shard.count, frames.size());
    return 0;
  }

  for (const std::string& p : a.plugins) {
    Status ls = load_plugin_arg(p);
    if (!ls.ok()) return fail(ls.message(), ls.exit_code());
  }

  std::vector<GltfIgnored> ignored;
  Result<Scene> scene =
      load_scene_source(scene_name, a.allow_outside_scene_dir, a.strict, &ignored);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  Result<int> camera = resolve_camera(*scene, a.camera);
  if (!camera.ok()) return fail(camera.status().message(), camera.status().exit_code());
  opt.camera = *camera;
  Result<int> clip = resolve_clip(*scene, a.animation);
  if (!clip.ok()) return fail(clip.status().message(), clip.status().exit_code());
  const std::shared_ptr<const SceneAnimation> anim = scene->animation;
  const bool has_clips = anim && !anim->clips.empty();
  // Turntable: with --frames when the scene has no animation (or with --turntable). The angle is
  // the frame's place in the whole list's span, so every shard and rerun agrees.
  const bool turntable = named && (a.turntable || !has_clips);
  glm::dvec3 lo, hi;
  scene_bounds(*scene, lo, hi);
  const glm::dvec3 centre = (lo + hi) * 0.5;
  PoseOptions pose;
  pose.clip = *clip;
  pose.technique = a.technique;

  Result<std::unique_ptr<Backend>> backend = make_backend(a.backend, opt.threads, a.gpu);
  if (!backend.ok()) return fail(backend.status().message(), backend.status().exit_code());
  if (frames.empty()) {
    if (!a.quiet)
      std::fprintf(a.log_json ? stderr : stdout, "shard %d/%d: no frames (the list has %d)\n",
                   shard.index, shard.count, list.count());
    return 0;
  }
  const float exposure_scale = std::exp2(*exposure);
  const std::vector<Camera> loaded_cameras = scene->cameras;
  Progress progress(frames.size(), a.quiet);
  BakeProgress bake_progress(a.quiet, progress);
  std::vector<double> frame_ms;
  int skipped = 0;
  const auto run_t0 = std::chrono::steady_clock::now();
  for (size_t fi = 0; fi < frames.size(); ++fi) {
    const int f = frames[fi];
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<std::string> files = frame_outputs(names, named, f);
    // A failed frame: its JSON line, then the one error line on stderr.
    auto frame_failed = [&](const Status& st) {
      progress.clear();
      if (a.log_json) log_frame(f, "failed", files, ms_since(t0), {{"error", st.message()}});
      return fail(st.message(), st.exit_code());
    };
    Claim claim;
    if (skip_existing) {
      const char* why = skip_reason(files, a.placeholder);
      if (!why && a.placeholder) {
        Result<bool> took = claim.take(files[0]);
        if (!took.ok()) return frame_failed(took.status());
        // Not taken: another run claimed it since (or the image is there but another output is
        // not, deleted since: then it is rendered again).
        if (!*took && output_empty(files[0])) why = "claimed";
      }
      if (why) {
        ++skipped;
        if (a.log_json) log_frame(f, "skipped", files, ms_since(t0), {{"reason", why}});
        progress.draw(fi + 1);
        continue;
      }
    }
    const double time_s = f / a.fps;
    if (turntable) scene->cameras[opt.camera] = loaded_cameras[opt.camera];
    PoseStats ps;
    if (anim) ps = pose_scene(*anim, pose, time_s, *scene);
    if (turntable) {
      const double angle = 2.0 * M_PI * (f - list.first()) / (list.last() - list.first() + 1);
      scene->cameras[opt.camera] = orbit_camera(scene->cameras[opt.camera], centre, angle);
    }
    const DerivedMapCounters counters = derived_map_counters();
    Result<Plan> plan = make_plan(*scene, opt);
    const BakeStats bake = BakeStats::since(counters);
    if (!plan.ok()) return frame_failed(plan.status());
    if (a.explain && fi == 0) {
      std::fprintf(human, "%s", plan->explain().c_str());
      std::fprintf(human, "%s",
                   explain_ignored(*scene, ignored, is_scene_path(scene_name)).c_str());
    }
    Result<RenderResult> r = (*backend)->render(*scene, *plan, opt);
    if (!r.ok()) return frame_failed(r.status());
    const auto t_out = std::chrono::steady_clock::now();

    const std::string& image_file = files[0];
    Image color = box_downsample(r->framebuffer.color, k);
    if (*exposure != 0.0f) apply_exposure(color, exposure_scale);
    apply_output_alpha(color, alpha_mode);
    // Every output of the frame is written in full to its temporary, then all are renamed.
    // The image is staged (and renamed) last, so a non-empty image means a complete frame.
    StagedFiles out;
    auto stage = [&out](const std::string& file, const Result<std::vector<unsigned char>>& bytes) {
      if (!bytes.ok()) return bytes.status();
      return out.stage(
          file, std::string_view(reinterpret_cast<const char*>(bytes->data()), bytes->size()));
    };
    size_t file_index = 1;
    for (const auto& [name, pattern] : names.aovs) {
      const std::string& file = files[file_index++];
      if (name == "depth") {
        s = stage(file, encode_plane(file, point_downsample(r->framebuffer.depth, k)));
      } else {
        for (int i = 0; i < kAovCount; ++i)
          if (name == kAovNames[i])
            s = stage(file,
                      encode_image(file, point_downsample(
                                             r->framebuffer.aov_image(static_cast<Aov>(i)), k)));
      }
      if (!s.ok()) return frame_failed(s);
    }
    if (!names.stats.empty()) {
      const std::string& file = files.back();
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
      j["bake"] = bake.json();
      if (anim) {
        j["pose"]["deform_ms"] = ps.deform_ms;
        j["pose"]["refit_ms"] = ps.refit_ms;
        j["pose"]["deformed_vertices"] = ps.vertices;
        j["pose"]["refitted_meshes"] = ps.refitted_meshes;
      }
      s = out.stage(file, j.dump(2) + "\n");
      if (!s.ok()) return frame_failed(s);
    }
    // The image last: once it is there (not empty), every output of the frame is.
    s = stage(image_file, encode_image(image_file, color, output_channels(alpha_mode),
                                       alpha_mode == OutputAlpha::kPremultiplied));
    if (!s.ok()) return frame_failed(s);
    claim.release();  // the outputs are renamed into place next, the image over the claim
    s = out.commit();
    if (!s.ok()) return frame_failed(s);
    const double output_ms = ms_since(t_out), total_ms = ms_since(t0);
    frame_ms.push_back(total_ms);
    progress.clear();
    if (a.log_json) {
      log_frame(f, "rendered", files, total_ms,
                {{"frame_ms", r->frame_ms},
                 {"output_ms", output_ms},
                 {"bake_ms", bake.bake_ms},
                 {"baked", bake.baked},
                 {"cached", bake.cached()}});
    } else if (!a.quiet) {
      std::printf("%s: %dx%d %s on %s, frame %.1f ms", image_file.c_str(), opt.width / k,
                  opt.height / k, scene_name.c_str(), r->device.c_str(), r->frame_ms);
      if (bake.baked > 0)
        std::printf(", derived-map bake %.0f ms (baked %d, cached %d)", bake.bake_ms, bake.baked,
                    bake.cached());
      else if (bake.disk_hits > 0)
        std::printf(", cone maps from the disk cache %.1f ms (%d)", bake.cache_ms, bake.disk_hits);
      std::printf(", output %.1f ms", output_ms);
      if (anim && !anim->deformers.empty())
        std::printf(", deform %.2f ms (%lld vertices)", ps.deform_ms, ps.vertices);
      if (ps.refitted_meshes) std::printf(", refit %.2f ms", ps.refit_ms);
      std::printf("\n");
      std::fflush(stdout);
    }
    progress.draw(fi + 1);
    (*backend)->recycle(std::move(r).value());  // the next frame reuses its buffers
  }
  progress.clear();  // the summary gets a line of its own
  if ((frames.size() > 1 || skipped) && !a.quiet) {
    const double run_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run_t0).count();
    std::fprintf(human, "%zu frame%s (%d-%d, shard %d/%d) in %.2f s", frames.size(),
                 frames.size() == 1 ? "" : "s", frames.front(), frames.back(), shard.index,
                 shard.count, run_s);
    if (!frame_ms.empty()) {
      std::sort(frame_ms.begin(), frame_ms.end());
      std::fprintf(human, ", median %.1f ms a frame", frame_ms[frame_ms.size() / 2]);
    }
    if (skip_existing)
      std::fprintf(human, "; rendered %zu, skipped %d (outputs there or claimed)", frame_ms.size(),
                   skipped);
    std::fprintf(human, "\n");
  }
  return 0;
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
