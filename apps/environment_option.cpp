#include "apps/environment_option.h"

#include <cmath>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "rasterizer/safe_file.h"
#include "render/derived_maps.h"
#include "scene/image_io.h"

namespace relief::cli {

// The largest --env-intensity: a scale factor on radiance, far above any exposure need (2^24,
// --exposure's own bound); a typo such as 1e30 is refused rather than turned into Inf.
constexpr double kMaxEnvironmentIntensity = 16777216.0;

void add_environment_options(CLI::App& sub, EnvironmentArgs& a) {
  sub.add_option("--env", a.env,
                 "Image-based light: an equirectangular .hdr or .exr (2:1), or 'none'; without it "
                 "a scene with no lights gets the built-in studio environment "
                 "(docs/environment.md)");
  sub.add_option("--env-intensity", a.intensity, "Environment radiance scale")
      ->capture_default_str();
  sub.add_option("--env-rotation", a.rotation_deg,
                 "Environment turn about +Y in degrees (right-handed)")
      ->capture_default_str();
}

Status apply_environment_options(const EnvironmentArgs& a, RenderOptions& opt) {
  if (!std::isfinite(a.intensity) || a.intensity < 0.0 || a.intensity > kMaxEnvironmentIntensity)
    return Status::usage("--env-intensity: expected a number in [0, 16777216]");
  if (!std::isfinite(a.rotation_deg) || std::fabs(a.rotation_deg) > 1e6)
    return Status::usage("--env-rotation: expected a number of degrees in [-1e6, 1e6]");
  opt.env_view = environment_view(static_cast<float>(std::fmod(a.rotation_deg, 360.0)),
                                  static_cast<float>(a.intensity));
  if (a.env.empty()) return {};
  if (a.env == "none") {
    opt.studio_environment = false;
    return {};
  }
  long long replaced = 0;
  Result<Image> img = load_environment(a.env, &replaced);
  if (!img.ok()) return img.status();
  if (replaced > 0)
    std::fprintf(stderr, "relief: warning: %s: %lld NaN, infinite or negative texels read as 0\n",
                 printable(a.env).c_str(), replaced);
  Result<DerivedEnvironment> d = derived_environment(*img);
  if (!d.ok()) return Status::error(printable(a.env) + ": " + d.status().message());
  opt.environment = d->maps;
  opt.environment_name = "'" + printable(a.env) + "', " + d->note;
  return {};
}

}  // namespace relief::cli
