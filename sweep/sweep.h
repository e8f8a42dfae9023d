// The accuracy/cost sweep behind `relief bench` (issue 8): techniques x step settings x view
// angles x height fields, each row measured against the `exact` reference on the same fragments.
//
// One row = one height field seen at one view angle, drawn with one technique and step setting.
// The view is an orthographic camera over a flat quad carrying the field (level 0 only, no mips:
// every search samples the field `exact` intersects, so the error is the search's own), so every
// fragment's ray meets the surface at exactly the row's angle from the normal; the frame spans
// one map tile across and 1 / cos(angle) tiles along the view (azimuth 35 degrees, so rays do not
// run along the map's axes). The quad's material keeps self-shadow and depth correction on, under
// the field's sun; no shadow maps.
//
// Per row, on the CPU backend:
//   cost      main-pass wall time / covered fragments, median, min and max of `repeats` frames
//             after `warmup` frames (ns per fragment); on `gl` the same of the GLSL twin's pass
//             (wall time up to glFinish), and cpu / gl of the medians.
//   work      texture fetches and search steps per fragment, mean and p99, counted per fragment
//             by a counting pass (each covered fragment shaded alone, its WorkCounters kept).
//   accuracy  against `exact` at the same pixels (hit-uv and hit-depth AOVs): hit error
//             |uv - uv_exact| in texels, depth error |t - t_exact| (ray depth, [0, 1]) mean and
//             p99; wrong_layer: the fraction of fragments whose hit lies past exact's with air
//             between them (exact says the hit is occluded: a thin structure stepped over), the
//             segment sampled every 1/16 texel; image RMSE and PSNR (render/compare.h, sRGB) of the
//             shaded colour; self-shadow disagreement: the fraction of lit-by-the-sun fragments
//             (the sun adds >= 0.05 luminance in both) whose shadowed/lit state differs from
//             exact's, read from frames with self-shadow on, off and without lights.
// p99 is the nearest-rank 99th percentile. PSNR of identical images is reported as kPsnrCap.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "plugins/plugin.h"
#include "rasterizer/image.h"
#include "rasterizer/status.h"
#include "rasterizer/texture.h"
#include "scene/scene.h"

namespace relief::sweep {

inline constexpr double kPsnrCap = 100.0;
inline constexpr double kAzimuthDeg = 35.0;

// A height field to sweep: its material (level-0 depth in [0, 1], 1 deepest; colour and normal
// maps; depth_scale, the relief depth in uv units; sampler; self-shadow and depth correction on)
// and the scene's sun, ambient and background it is lit with.
struct Field {
  std::string name;
  Material material;
  Light sun;
  glm::vec3 ambient{0.08f};
  glm::vec4 background{0.05f, 0.06f, 0.08f, 1.0f};
  const Texture& depth() const { return *material.textures.at("depth"); }
  float depth_scale() const { return material.params.at("depth_scale"); }
};

// The built-in fields: `bricks` (the `plane` scene's map) and `pattern` (make_pattern_depth).
Result<std::vector<Field>> builtin_fields();
// The field of a scene's material: its depth (level 0), colour (depth-coded when it has none),
// normal map (baked from depth when it has none), depth_scale (the plugins' default when unset)
// and sampler, lit by the scene's first directional light (the `plane` scene's sun when it has
// none). Error: the material has no depth map.
Result<Field> field_of_material(const Scene& scene, int material);
// A depth image (first channel; `height`: 1 = top, converted to depth) with a colour that follows
// depth and a normal map baked from it. Errors name the file.
Result<Field> field_from_file(const std::string& path, float depth_scale, bool height);

// One technique at one setting: parameter overrides and a label such as "relief 16+8".
struct Setting {
  std::string technique;
  std::map<std::string, std::string> params;
  std::string label;
  int steps = 0;  // the swept step count (0: the technique has none)
};

// Registered techniques that search a depth map (a required `depth` slot), sorted by name.
std::vector<std::string> sweep_techniques();
// The settings of one technique: one per entry of `steps` when its schema has `steps` (and
// `min_steps` = steps, a fixed count; `binary_steps` keeps its default), else its defaults.
std::vector<Setting> settings_for(const PluginDescriptor& plugin, const std::vector<int>& steps);

// The scene for one field at one view angle (degrees from the normal), width x height pixels.
Scene view_scene(const Field& field, double angle_deg, int width, int height);
// The texture-space ray step ds of that view (shaders_cpp/ray.h): uv at depth t is uv0 + t * ds.
glm::dvec2 view_ray_step(const Field& field, double angle_deg);

struct Options {
  int width = 256;
  int height = 256;
  int threads = 0;
  std::vector<double> angles = {0, 30, 60, 75, 85, 89};
  bool cpu = true;
  bool gl = false;
  int warmup = 1;
  int repeats = 5;
  bool keep_images = false;  // keep colour images and heat maps (the HTML report)
  // Self-shadow rays on (the fields' materials ask for them). Off, the fetches are the search's
  // plus the shading's, and no self-shadow disagreement is measured (shadow_compared 0).
  bool self_shadow = true;
  // Called after each row (and each reference): rows done, rows in all, what was just done.
  std::function<void(int, int, const std::string&)> progress;
};

struct Row {
  std::string field, technique, setting;
  int steps = 0;
  double angle = 0.0;
  long fragments = 0;
  double ns_median = 0, ns_min = 0, ns_max = 0;
  // GL: -1 when not run; gl_note says why (no twin, no context).
  double gl_ns_median = -1, gl_ns_min = -1, gl_ns_max = -1, cpu_gl_ratio = -1;
  std::string gl_note;
  double fetches_mean = 0, fetches_p99 = 0, steps_mean = 0, steps_p99 = 0;
  double hit_err_mean = 0, hit_err_p99 = 0, depth_err_mean = 0, depth_err_p99 = 0;
  double wrong_layer_frac = 0, rmse = 0, psnr_db = 0;
  long shadow_compared = 0;
  double shadow_disagree_frac = 0;
};

// Images of one row for the report: the shaded colour and its heat map against exact.
struct RowImages {
  size_t row = 0;
  Image color, heat;
};

struct SweepResult {
  std::vector<Row> rows;
  std::vector<RowImages> images;  // with Options::keep_images
  std::string cpu_device, gl_device;
  std::vector<std::string> notes;  // techniques skipped on gl, and why
};

// Runs every setting on every field at every angle (exact is run once per view as the
// reference; its own rows come from its settings like any other). Errors: a plan or render that
// fails, names the row.
Result<SweepResult> run_sweep(const std::vector<Field>& fields,
                              const std::vector<Setting>& settings, const Options& options);

// ---- output (sweep/output.cpp) ----
// The documented columns of --csv and of each row object of --json, in order.
const std::vector<std::string>& columns();
std::string to_csv(const std::vector<Row>& rows);
// {"command", "machine", "options", "rows": [...], "notes"}.
struct RunInfo {
  std::string command;  // the exact command line
  std::string machine;  // CPU model, cores, load
  Options options;
};
std::string to_json(const SweepResult& result, const RunInfo& info);
// A fixed-width table for the terminal (GL columns when any row ran on gl).
std::string format_table(const std::vector<Row>& rows);
// "cpu model, N cores, load average a b c" from /proc.
std::string machine_description();

// ---- the HTML report (sweep/report.cpp) ----
// One self-contained page: the machine and command, a table of the rows, an inline SVG plot of
// p99 hit error against ns per fragment per field with its Pareto front, and the kept images and
// heat maps as data: URIs. Written atomically to DIR/index.html (DIR is created).
Status write_report(const std::string& dir, const SweepResult& result, const RunInfo& info);
// The (ns, p99) Pareto front of `rows`: indices of rows no other row beats on both, by ns.
std::vector<size_t> pareto_front(const std::vector<Row>& rows);

// ---- adaptive quality (sweep/target.cpp) ----
// View angles (degrees from the normal) under which `camera` sees the instances of `material`:
// sampled on a barycentric grid of each visible front-facing triangle, each sample weighted by the
// screen area it stands for (cos / distance^2), summarised as the pixel-weighted 10th, 50th and
// 90th percentiles and the largest, rounded to whole degrees, deduplicated, at most 89.
std::vector<double> scene_view_angles(const Scene& scene, int material, int camera, int width,
                                      int height);

struct Pick {
  bool found = false;
  std::string technique, setting;  // setting: the Setting's label
  double ns = 0.0;                 // mean over the angles of the median ns per fragment
  double worst_p99 = 0.0;          // largest p99 hit error over the angles
  std::string why;                 // the measured rows behind the choice, several lines
};
// The cheapest setting (mean ns per fragment over `angles`) whose p99 hit error is under
// `target` (texels) at every angle of `field` in `rows`. `why` lists the choice's rows and, for
// each cheaper setting, the angle where it failed.
Pick pick_cheapest(const std::vector<Row>& rows, const std::string& field,
                   const std::vector<double>& angles, double target);

}  // namespace relief::sweep
