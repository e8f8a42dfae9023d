// The accuracy/cost sweep behind `relief bench` (issue 8): techniques x step settings x view
// angles x height fields, each row measured against the `exact` reference on the same fragments.
//
// One row = one height field seen at one view angle, drawn with one technique and step setting,
// at one LOD mode: `level0` (the depth map without mips: every search samples the field `exact`
// intersects, so the error is the search's own) or `as-rendered` (the depth map with its mip
// chain and the material's sampler, what a user's render samples; errors are still measured
// against `exact` on level 0, the true surface). The view is an orthographic camera over a flat
// quad carrying the field, so every
// fragment's ray meets the surface at exactly the row's angle from the normal; the frame spans
// one map tile across and 1 / cos(angle) tiles along the view (azimuth 35 degrees, so rays do not
// run along the map's axes). The quad's material keeps self-shadow and depth correction on, under
// the field's sun; no shadow maps.
//
// Per row, on the CPU backend:
//   cost      main-pass wall time / covered pixels (for a layered technique, `shells`, all its
//             layers' work at a pixel is that pixel's cost), median, min and max of `repeats`
//             frames after `warmup` frames (ns per fragment); on `gl` the same of the GLSL twin's
//             pass (wall time up to glFinish), and cpu / gl of the medians.
//   work      texture fetches and search steps per fragment, mean and p99, counted per fragment
//             by a counting pass (each covered fragment shaded alone, its WorkCounters kept).
//   accuracy  against `exact` at the same pixels (hit-uv and hit-depth AOVs): hit error
//             |uv - uv_exact| in texels, depth error |t - t_exact| (ray depth, [0, 1]) mean and
//             p99; wrong_layer: the fraction of fragments whose hit lies past exact's with air
//             between them (exact says the hit is occluded: a thin structure stepped over), the
//             segment sampled every 1/16 texel; air and below: the fraction of fragments whose hit
//             (uv, t) lies more than half a texel of height above (D(uv) - t > tol) or below
//             (t - D(uv) > tol) the level-0 bilinear surface D at its own uv, tol = 0.5 /
//             (width_texels * depth_scale) depth units; image RMSE and PSNR (render/compare.h,
//             sRGB) of the shaded colour; shadow_err: the fraction of lit-by-the-sun fragments
//             (the sun adds >= 0.05 luminance in both) whose shadowed/lit state differs from
//             exact's at the same pixel, read from frames with self-shadow on, off and without
//             lights; shadow_ray_err: the same state against HeightField::shadowed from the
//             row's own hit toward the same light (the shadow ray's error alone).
// p99 is the nearest-rank 99th percentile. PSNR of identical images is reported as kPsnrCap.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "base/status.h"
#include "plugins/plugin.h"
#include "rasterizer/image.h"
#include "rasterizer/texture.h"
#include "render/render.h"
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
  // The depth map as a scene samples it: the same level 0 with its mip chain (the material's own
  // when it has one, else an average chain), for Options::lods "as-rendered".
  TexturePtr depth_mips;
  const Texture& depth() const { return *material.textures.at("depth"); }
  float depth_scale() const { return material.params.at("depth_scale"); }
};

// The built-in fields: `bricks` (the `plane` scene's map), `pattern` (make_pattern_depth), the
// generated `thin`, `spikes` and `ramp` (make_generated_depth), and the `fur` and `grass` scenes'
// strand fields (bake/fur_field.h, docs/fur.md), in that order.
Result<std::vector<Field>> builtin_fields();
// The names of builtin_fields(), in order.
const std::vector<std::string>& builtin_field_names();
// One of them by name. Error: not a built-in field's name.
Result<Field> builtin_field(const std::string& name);
// A generated depth map (R32F, size x size texels, size a power of two >= 16, no mips),
// deterministic (no library random numbers): `thin` (depth-1 floor, one-texel depth-0 walls every
// 8 texels, scattered one-texel pillars near the top), `spikes` (isolated cones and square
// pyramids over a depth-1 floor, flat tips 1 to 3 texels wide at depth 0), `ramp` (depth rising
// smoothly from 0.1 to 0.7 across u, plus a sharp 0.3 step at v = 1/2; the tile's repeat adds the
// steps back at u = 0 and v = 0). Error: another name or size.
Result<Texture> make_generated_depth(const std::string& name, int size);
// The field of make_generated_depth(name, size): depth_scale 0.05 (as `pattern`), a trilinear
// repeat sampler, the colour and normal map field_of_material derives. builtin_field uses 256.
Result<Field> generated_field(const std::string& name, int size);
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
// The settings of one technique: one per entry of `steps` when its schema has `steps` or, for a
// technique drawn as shells, `layers` (and
// `min_steps` = steps, a fixed count; `binary_steps` keeps its default, or is `binary_steps`
// when that is >= 0), else its defaults; for a technique with a `lod` parameter (the searches'
// SearchLod, plugins/relief_shell.h) those again for each of `search_lods` (quad, zero,
// max-mip; labels gain " lod=zero" etc. except for kSearchLodDefault). Empty: the default LOD.
inline constexpr const char* kSearchLodDefault = "quad";
std::vector<Setting> settings_for(const PluginDescriptor& plugin, const std::vector<int>& steps,
                                  int binary_steps = -1,
                                  const std::vector<std::string>& search_lods = {});

// The scene for one field at one view angle (degrees from the normal), width x height pixels;
// `as_rendered`: the depth map with its mips (Field::depth_mips) instead of level 0 alone.
Scene view_scene(const Field& field, double angle_deg, int width, int height,
                 bool as_rendered = false);
// The view's sun in the quad's tangent space (x = u, y = v, z = normal): the texture-space light
// step dl of shaders_cpp/ray.h light_step and L.z; lz <= 0 when the sun is below the surface.
glm::dvec2 view_light_step(const Field& field, double* lz = nullptr);
// Half a texel of height in depth units: 0.5 / (level-0 width * depth_scale). Depth 1 spans
// depth_scale uv units and a texel is 1 / width uv.
double half_texel_depth(const Field& field);

inline constexpr const char* kLodLevel0 = "level0";
inline constexpr const char* kLodAsRendered = "as-rendered";
// The texture-space ray step ds of that view (shaders_cpp/ray.h): uv at depth t is uv0 + t * ds.
glm::dvec2 view_ray_step(const Field& field, double angle_deg);

struct Options {
  int width = 256;
  int height = 256;
  int threads = 0;
  std::vector<double> angles = {0, 30, 60, 75, 85, 89};
  bool cpu = true;
  bool gl = false;
  GlInterpolation gl_interpolation = GlInterpolation::kGpu;  // how the twins interpolate
  int warmup = 1;
  int repeats = 5;
  // LOD modes, each a set of rows: kLodLevel0 and/or kLodAsRendered (in this order).
  std::vector<std::string> lods = {kLodLevel0};
  bool keep_images = false;  // keep colour images and heat maps of every row (the HTML report)
  int thumbnail = 128;       // kept images are box-filtered down to at most this width
  // Self-shadow rays on (the fields' materials ask for them). Off, the fetches are the search's
  // plus the shading's, and no self-shadow disagreement is measured (shadow_compared 0).
  bool self_shadow = true;
  // With `gl` and `relief` among the settings: the appendix yardstick at every field and angle
  // (AppendixRow).
  bool appendix = true;
  // Called after each row (and each reference): rows done, rows in all, what was just done.
  std::function<void(int, int, const std::string&)> progress;
};

struct Row {
  std::string field, technique, setting;
  int steps = 0;
  double angle = 0.0;
  std::string lod = kLodLevel0;
  long fragments = 0;
  double ns_median = 0, ns_min = 0, ns_max = 0;
  // GL: -1 when not run; gl_note says why (no twin, no context).
  double gl_ns_median = -1, gl_ns_min = -1, gl_ns_max = -1, cpu_gl_ratio = -1;
  std::string gl_note;
  double fetches_mean = 0, fetches_p99 = 0, steps_mean = 0, steps_p99 = 0;
  double hit_err_mean = 0, hit_err_p99 = 0, depth_err_mean = 0, depth_err_p99 = 0;
  double hit_err_over1_frac = 0;  // fragments whose hit is more than one texel from exact's
  double wrong_layer_frac = 0, air_frac = 0, below_frac = 0, rmse = 0, psnr_db = 0;
  // fragments in the air or on a wrong layer (either; the union of the two): wrong occlusion
  double wrong_occlusion_frac = 0;
  long shadow_compared = 0;
  double shadow_err = 0, shadow_ray_err = 0;
};

// The second yardstick (issue 26; docs/accuracy.md, "The appendix yardstick"): the relief paper's
// own appendix shader on GL (gl/appendix_relief.h: kAppendixLinearSteps - 1 linear samples and
// kAppendixBinarySteps halvings, every one taken; textureLod 0; one RGBA8 texture; diffuse only)
// against the CPU backend's `relief` with the same effects off (no self-shadow, no depth write, no
// shadow maps), the same steps (steps = min_steps = 10, binary_steps = 5), the search at level 0
// (lod=zero), the same texture (the field's depth and normal maps) and the same view, one per
// field and view angle (level 0 rows). CPU and GL frames alternate: warm-up frames of both, then
// `repeats` pairs. Its ns per fragment divide each side's frame time (the CPU's main pass, GL's
// clear + draw + glFinish) by the CPU's covered pixels.
inline constexpr int kAppendixLinearSteps = 10;
inline constexpr int kAppendixBinarySteps = 5;
// The CPU side of that yardstick: `view` (a view_scene) with every material's self-shadow and
// depth write off, and the options of `relief` 10+5 lod=zero without shadows or self-shadow at
// width x height (bench_raster's BM_Raster_ReliefLean draws the same frame).
struct AppendixLean {
  Scene scene;
  RenderOptions options;
};
AppendixLean appendix_lean(const Scene& view, int width, int height);
struct AppendixRow {
  std::string field;
  double angle = 0.0;
  long fragments = 0;
  double cpu_ns_median = 0, cpu_ns_min = 0, cpu_ns_max = 0;
  // -1 when GL did not run; note says why
  double gl_ns_median = -1, gl_ns_min = -1, gl_ns_max = -1;
  double speedup = -1;  // gl / cpu of the medians: how many times faster the CPU backend is
  // pixels both cover whose two hits lie within one texel (the searches agree: the comparison is
  // like for like), of the pixels both cover
  double same_hit_frac = 0;
  std::string note;
};

// Images of one row for the report: the shaded colour and its heat map against exact (both at
// most Options::thumbnail wide).
struct RowImages {
  size_t row = 0;
  Image color, heat;
};

struct SweepResult {
  std::vector<Row> rows;
  std::vector<RowImages> images;      // with Options::keep_images
  std::vector<AppendixRow> appendix;  // the appendix yardstick (Options::appendix)
  std::string cpu_device, gl_device;
  std::vector<std::string> notes;  // techniques skipped on gl, and why
};

// Runs every setting on every field at every angle (exact is run once per view as the
// reference; its own rows come from its settings like any other). Errors: a plan or render that
// fails, names the row.
Result<SweepResult> run_sweep(const std::vector<Field>& fields,
                              const std::vector<Setting>& settings, const Options& options);

// ---- output (sweep/tables.cpp) ----
// The documented columns of --csv and of each row object of --json, in order.
const std::vector<std::string>& columns();
std::string to_csv(const std::vector<Row>& rows);
// {"command", "machine", "options", "rows": [...], "notes"}.
struct RunInfo {
  std::string command;  // the exact command line
  std::string machine;  // CPU model, cores, load
  Options options;
  // Build metadata (version, commit, SIMD path, date, CPU...), in order: the report's table and
  // the JSON's "build" object.
  std::vector<std::pair<std::string, std::string>> build;
};
std::string to_json(const SweepResult& result, const RunInfo& info);
// A fixed-width table for the terminal (GL columns when any row ran on gl).
std::string format_table(const std::vector<Row>& rows);
// The appendix yardstick's rows as a terminal table (empty without rows).
std::string format_appendix_table(const std::vector<AppendixRow>& rows);
// "cpu model, N cores, load average a b c" from /proc.
std::string machine_description();

// ---- the HTML report (sweep/report.cpp) ----
// One self-contained page (no external scripts or styles): build metadata, machine and command;
// per field, LOD mode and view angle two inline SVG plots (mean and p99 hit error against ns per
// fragment, log scales, one colour per technique, the step count at each point, the Pareto front,
// a legend; GL times as hollow markers); angle x setting tables as docs/accuracy.md; the kept
// images and heat maps as data: URIs, one strip per setting; and every row in a sortable table
// (inline JS) with numbers to 3 significant digits and "n/a" where GL did not run. Written
// atomically to DIR/index.html (DIR is created).
Status write_report(const std::string& dir, const SweepResult& result, const RunInfo& info);
// The (ns, p99) Pareto front of `rows`: indices of rows no other row beats on both, by ns.
std::vector<size_t> pareto_front(const std::vector<Row>& rows);
// A number for people: 3 significant digits (whole numbers as they are), no exponent below 1e6; |v|
// < 1e-6 (not 0) as "<1e-6", 0 as "0", non-finite as "n/a".
std::string format_number(double v);

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
