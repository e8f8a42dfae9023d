// `--env FILE|none`, `--env-intensity` and `--env-rotation`: the image-based light of a render
// (docs/environment.md). Shared by the commands that render a scene.
#pragma once

#include <string>

#include "base/status.h"
#include "render/render.h"

namespace CLI {
class App;
}

namespace relief::cli {

struct EnvironmentArgs {
  std::string env;  // a .hdr/.exr path, "none", or empty (the default)
  double intensity = 1.0;
  double rotation_deg = 0.0;
};

// Adds the three options to a subcommand.
void add_environment_options(CLI::App& sub, EnvironmentArgs& a);

// Checks the values and, for a file, loads and bakes it (cached for the process) into `opt`;
// "none" turns the studio environment of a scene without lights off. Errors are usage errors
// naming the flag, or the loader's one line naming the file. A file with NaN, infinite or negative
// texels loads with them as 0 and one warning line on stderr.
Status apply_environment_options(const EnvironmentArgs& a, RenderOptions& opt);

}  // namespace relief::cli
