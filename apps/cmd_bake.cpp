// `relief bake`: normal maps and cone maps from a depth (or height) image.
//   relief bake DEPTH_IMAGE -o OUT (--normal | --cone conservative|quad|relaxed) [--height]
//               [--depth-scale s (--normal only)] [--normal-convention gltf|directx] [--max-ratio
//               R] [--wrap] [--bilinear] [--threads N]
// Output by extension through scene/image_io.h:
//   --normal: RGB = n * 0.5 + 0.5 (tangent space, bake/normal_map.h; green toward the image top as
//             glTF has it, toward the bottom with --normal-convention directx), stored linear: .exr
//             float, .png / .tif with the bytes of the RGBA8 texture (8-bit PNG readers that keep
//             bytes as linear, as load_texture does by default, get exactly normal_map_from_depth's
//             texels).
//   --cone conservative|relaxed: one channel, .exr/.tif 32-bit float, .png 16-bit (ratio * 65535,
//             rounded down so a stored cone is never wider than the baked one; needs max-ratio <=
//             1).
//   --cone quad: RGBA = ratios (+u, -u, +v, -v); .exr float, .png 8-bit (rounded down; <= 1).
// Errors are one line (relief: ...) with exit 2 for usage and 1 for input; no output is left
// behind.
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "apps/commands.h"
#include "apps/output.h"
#include "bake/cone_map.h"
#include "bake/fur_field.h"
#include "bake/normal_map.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "scene/image_io.h"

namespace relief::cli {
namespace {

struct BakeArgs {
  std::string input;
  std::string output;
  bool normal = false;
  std::string cone;
  bool height = false;
  float depth_scale = 0.1f;
  bool depth_scale_given = false;  // --depth-scale on the command line
  std::string normal_convention = "gltf";
  bool normal_convention_given = false;
  float max_ratio = 1.0f;
  bool wrap = false;
  bool bilinear = false;
  int threads = 0;
  bool dual = false;  // --dual: the input is a glTF mesh, -o a prefix (apps/cmd_bake_dual.cpp)
  bool allow_outside_scene_dir = false;  // --dual: its URIs may leave its folder
  int size = 256;
  bool size_given = false;
  float grow = 1.0f;
  std::string fur;  // --fur fur|grass: a generated field, -o a prefix (apps/cmd_bake_fur.cpp)
  FurFieldOptions fur_options;  // the values of --density, --radius, --jitter
  std::string seed;             // --seed as written: parsed here, as CLI11 wraps -1 and 2^64
  bool fur_given[4] = {};       // which of those four the command line gave
};

std::string lower_ext(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

// Progress: a bar redrawn on a terminal, nothing until the end otherwise.
class ProgressBar {
 public:
  explicit ProgressBar(std::string label) : label_(std::move(label)), tty_(isatty(2) != 0) {}
  void update(float f) {
    if (!tty_) return;
    const int pct = static_cast<int>(f * 100.0f);
    if (pct == last_) return;
    last_ = pct;
    const int filled = pct * 30 / 100;
    std::fprintf(stderr, "\r%s [%.*s%*s] %3d%%", label_.c_str(), filled,
                 "##############################", 30 - filled, "", pct);
    if (pct >= 100) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

 private:
  std::string label_;
  bool tty_;
  int last_ = -1;
};

}  // namespace

int run_bake_dual(const std::string& mesh_path, const std::string& prefix, int size, float grow,
                  int threads, bool allow_outside_scene_dir);

int run_bake_fur(const FurFieldOptions& options, const std::string& prefix, float depth_scale);

namespace {

// --fur KIND: the field's options (the kind's defaults where a flag is absent) and what must not
// come with it; 0 after the bake, else its exit code.
int run_bake_fur_args(const BakeArgs& a) {
  if (!a.input.empty() || a.normal || !a.cone.empty() || a.dual)
    return fail(
        "bake: --fur makes a field from nothing; it takes no depth image, --normal, --cone "
        "or --dual",
        2);
  FurFieldOptions o = fur_field_defaults(a.fur == "grass" ? FurKind::kGrass : FurKind::kFur);
  if (a.size_given) o.size = a.size;
  if (a.fur_given[0]) o.density = a.fur_options.density;
  if (a.fur_given[1]) o.radius = a.fur_options.radius;
  if (a.fur_given[2]) o.jitter = a.fur_options.jitter;
  if (a.fur_given[3]) {
    const char* end = a.seed.data() + a.seed.size();
    const auto [p, ec] = std::from_chars(a.seed.data(), end, o.seed);
    if (a.seed.empty() || ec != std::errc() || p != end)
      return fail("bake --fur: --seed must be an integer in 0..18446744073709551615", 2);
  }
  return run_bake_fur(o, a.output, a.depth_scale_given ? a.depth_scale : 0.06f);
}

// The checks of the arguments before any input is read: 0 when they pass, else the exit code
// (2 for usage) after fail()'s one line. `ext` is the output's lower-case extension.
int check_bake_args(const BakeArgs& a, const std::string& ext) {
  if (a.normal == !a.cone.empty())
    return fail("bake: choose exactly one of --normal or --cone KIND", 2);
  if (a.depth_scale_given && !a.normal)
    return fail(
        "bake: --depth-scale applies to --normal only (a cone map is in depth-map units: "
        "ratios of texels to depth 0..1; the material's depth_scale applies at render "
        "time)",
        2);
  if (a.normal_convention_given && !a.normal)
    return fail("bake: --normal-convention applies to --normal only", 2);
  if (!(a.depth_scale > 0.0f) || !std::isfinite(a.depth_scale))
    return fail("bake: --depth-scale must be a positive finite number", 2);
  if (!(a.max_ratio > 0.0f) || !std::isfinite(a.max_ratio) || a.max_ratio > 65504.0f)
    return fail("bake: --max-ratio must be positive, finite and at most 65504", 2);
  if (a.threads < 0) return fail("bake: --threads must be >= 0 (0: all cores)", 2);
  if (a.bilinear && a.cone.empty()) return fail("bake: --bilinear applies to --cone only", 2);
  if (ext != ".png" && ext != ".exr" && ext != ".tif" && ext != ".tiff")
    return fail(a.output + ": unsupported output extension '" + ext +
                    "', expected .png, .exr, .tif or .tiff",
                2);
  if (!a.cone.empty() && a.max_ratio > 1.0f && ext != ".exr")
    return fail("bake: --max-ratio above 1 needs a float output (.exr); integer images hold [0, 1]",
                2);
  // The output can be written (its folder exists and is writable, it is no directory) before
  // anything is baked; the write itself is atomic and checked (rasterizer/output_file.h).
  if (Status o = check_output_path(a.output); !o.ok()) return fail(o.message(), o.exit_code());
  return 0;
}

// A depth map has one channel: grey stored as RGB is fine, colour (R, G, B differ) is not. 0 when
// `input` loads and is no colour image, else the exit code after fail()'s line.
int check_one_channel(const std::string& input) {
  Result<Texture> full = load_texture(input);
  if (!full.ok()) return fail(full.status().message(), full.status().exit_code());
  const Texture& t = full.value();
  if (format_channels(t.format()) >= 3)
    for (int y = 0; y < t.height(0); ++y)
      for (int x = 0; x < t.width(0); ++x) {
        const glm::vec4 c = t.fetch(0, x, y);
        if (c.x != c.y || c.x != c.z)
          return fail(printable(input) +
                          ": a colour image (R, G and B differ); a depth map has one channel",
                      1);
      }
  return 0;
}

// --normal: the normal map of depth map `d`, written to a.output as its extension `ext` asks.
Status bake_normal(const BakeArgs& a, const Texture& d, const std::string& ext) {
  const int w = d.width(0), h = d.height(0);
  const NormalConvention convention =
      a.normal_convention == "directx" ? NormalConvention::kDirectX : NormalConvention::kGltf;
  Image img(w, h);
  if (ext == ".exr") {
    Texture n = normal_map_from_depth_float(d, a.depth_scale, a.wrap, convention);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        glm::vec4 v = n.fetch(0, x, y);
        img.at(x, y) = glm::vec4(glm::vec3(v) * 0.5f + 0.5f, 1.0f);
      }
  } else {
    Texture n = normal_map_from_depth(d, a.depth_scale, a.wrap, convention);
    const MipLevel& l0 = n.level(0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const uint8_t* p = &l0.data[(static_cast<size_t>(y) * w + x) * 4];
        // PNG: the encoder applies sRGB, so hand it values that encode to the texel's bytes.
        // TIFF is 16-bit linear: the 8-bit values as they are.
        for (int c = 0; c < 3; ++c)
          img.at(x, y)[c] = ext == ".png" ? srgb_decoded_byte(p[c]) : p[c] / 255.0f;
        img.at(x, y).w = 1.0f;
      }
  }
  return write_image(a.output, img);
}

// The four ratios of a quad cone map as an image for `ext`: float in .exr, rounded down to the
// 8 (.png) or 16 bits (.tif) the file holds.
Image quad_cone_image(const ConeRatios& r, int w, int h, const std::string& ext) {
  Image img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 4; ++c) {
        const float v = r.at(x, y, c);
        if (ext == ".exr") {
          img.at(x, y)[c] = v;
        } else if (ext == ".png") {
          const int b = static_cast<int>(std::floor(v * 255.0f));
          img.at(x, y)[c] = c < 3 ? srgb_decoded_byte(b) : b / 255.0f;  // alpha is linear
        } else {
          img.at(x, y)[c] = std::floor(v * 65535.0f) / 65535.0f;
        }
      }
  return img;
}

// --cone KIND: the cone map of depth map `d` with a progress bar, written to a.output as its
// extension `ext` asks; `what` names the map ("relaxed cone map").
Status bake_cone(const BakeArgs& a, const Texture& d, const std::string& ext, std::string& what) {
  const int w = d.width(0), h = d.height(0);
  ConeBakeOptions o;
  if (a.cone == "conservative")
    o.kind = ConeKind::kConservative;
  else if (a.cone == "quad")
    o.kind = ConeKind::kQuad;
  else
    o.kind = ConeKind::kRelaxed;
  o.max_ratio = a.max_ratio;
  o.wrap = a.wrap;
  o.bilinear = a.bilinear;
  o.threads = a.threads;
  what = std::string(cone_kind_name(o.kind)) + " cone map";
  ProgressBar bar("baking " + what);
  o.progress = [&bar](float f) { bar.update(f); };
  ConeRatios r = bake_cone_ratios(d, o);
  if (r.channels != 1) return write_image(a.output, quad_cone_image(r, w, h, ext));
  Plane p(w, h);
  for (size_t i = 0; i < p.values.size(); ++i)
    p.values[i] = ext == ".png" ? std::floor(r.values[i] * 65535.0f) / 65535.0f : r.values[i];
  return write_plane(a.output, p);
}

int run_bake(const BakeArgs& a) {
  if (!a.fur.empty()) return run_bake_fur_args(a);
  if (a.fur_given[0] || a.fur_given[1] || a.fur_given[2] || a.fur_given[3])
    return fail("bake: --density, --radius, --jitter and --seed apply to --fur only", 2);
  if (a.input.empty()) return fail("bake: a depth image is required (or --fur KIND)", 2);
  if (a.dual)
    return run_bake_dual(a.input, a.output, a.size, a.grow, a.threads, a.allow_outside_scene_dir);
  const std::string ext = lower_ext(a.output);
  if (int code = check_bake_args(a, ext)) return code;
  if (int code = check_one_channel(a.input)) return code;
  TextureLoadOptions lo;
  lo.first_channel_only = true;
  lo.height_to_depth = a.height;
  lo.unit_range = true;
  Result<Texture> depth = load_texture(a.input, lo);
  if (!depth.ok()) return fail(depth.status().message(), depth.status().exit_code());
  const Texture& d = depth.value();
  const auto t0 = std::chrono::steady_clock::now();
  std::string what = "normal map";
  const Status st = a.normal ? bake_normal(a, d, ext) : bake_cone(a, d, ext, what);
  if (!st.ok()) return fail(st.message(), st.exit_code());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("baked %s %dx%d in %.2f s -> %s\n", what.c_str(), d.width(0), d.height(0), secs,
              a.output.c_str());
  return 0;
}

}  // namespace

void register_bake(CLI::App& app, Action& action) {
  auto args = std::make_shared<BakeArgs>();
  auto* sub = app.add_subcommand("bake", "Bake a normal map or a cone map from a depth image");
  sub->add_option("depth_image", args->input,
                  "Depth map (0 = top, 1 = deepest); see --height (none with --fur)");
  sub->add_option("-o,--output", args->output, "Output image (.exr float, .png, .tif)")->required();
  sub->add_flag("--normal", args->normal, "Bake a tangent-space normal map");
  sub->add_option("--cone", args->cone, "Bake a cone map: conservative, quad or relaxed")
      ->check(CLI::IsMember({"conservative", "quad", "relaxed"}));
  sub->add_flag("--height", args->height, "The input is a height map (1 = top): depth = 1 - h");
  CLI::Option* depth_scale =
      sub->add_option("--depth-scale", args->depth_scale,
                      "--normal only: relief depth in uv units (default 0.1); cone maps do not "
                      "depend on it");
  CLI::Option* convention =
      sub->add_option("--normal-convention", args->normal_convention,
                      "--normal only: gltf (default; green = +Y toward the image top, as glTF, "
                      "Blender and OpenGL tools read) or directx (green flipped)")
          ->check(CLI::IsMember({"gltf", "directx"}));
  sub->add_option("--max-ratio", args->max_ratio, "Clamp cone ratios (default 1)");
  sub->add_flag("--wrap", args->wrap, "The map tiles (wrap at the borders); default clamp");
  sub->add_flag("--bilinear", args->bilinear,
                "Cones safe for the bilinear surface (the cone plugins' maps)");
  sub->add_option("--threads", args->threads, "Worker threads (0: all cores)");
  sub->add_flag("--dual", args->dual,
                "Dual-depth relief textures of a glTF mesh: -o PREFIX gets PREFIX_front.exr, "
                "PREFIX_back.exr and their normal maps");
  sub->add_flag("--allow-outside-scene-dir", args->allow_outside_scene_dir,
                "--dual: let the glTF file's URIs lead outside its folder (.., symlinks)");
  CLI::Option* size = sub->add_option(
      "--size", args->size, "--dual: map size in texels (default 256); --fur: field size (512)");
  sub->add_option("--fur", args->fur,
                  "Generate a tileable fur or grass field: -o PREFIX gets PREFIX_depth.png, "
                  "PREFIX_base_color.png and PREFIX_normal.png (docs/fur.md)")
      ->check(CLI::IsMember({"fur", "grass"}));
  CLI::Option* fur_flags[] = {
      sub->add_option("--density", args->fur_options.density,
                      "--fur: strands per 100x100 texels (fur 800, grass 90)"),
      sub->add_option("--radius", args->fur_options.radius,
                      "--fur: strand radius in texels, 0.5..32 (fur 1.5, grass 2)"),
      sub->add_option("--jitter", args->fur_options.jitter,
                      "--fur: tip heights vary in [1 - jitter, 1] of full height (fur 0.3, "
                      "grass 0.4)"),
      sub->add_option("--seed", args->seed, "--fur: random seed, 0..2^64-1 (default 1)")};
  sub->add_option("--grow", args->grow,
                  "--dual: the maps' square over the mesh's x-y bounds, times this (>= 1)");
  sub->callback([&action, args, depth_scale, convention, size, fur_flags] {
    args->depth_scale_given = depth_scale->count() > 0;
    args->size_given = size->count() > 0;
    for (int i = 0; i < 4; ++i) args->fur_given[i] = fur_flags[i]->count() > 0;
    args->normal_convention_given = convention->count() > 0;
    action = [args] { return run_bake(*args); };
  });
}

}  // namespace relief::cli
