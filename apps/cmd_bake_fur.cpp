// `relief bake --fur fur|grass -o PREFIX [--size N] [--density D] [--radius R] [--jitter J]
// [--seed S] [--depth-scale s]`: a generated fur or grass field (bake/fur_field.h) as
//   PREFIX_depth.png       16-bit grey depth, 0 at the strand tips, 1 the skin or ground
//   PREFIX_base_color.png  8-bit sRGB colour, dark at the root, light at the tip
//   PREFIX_normal.png      the wrapped tangent-space normal map for depth_scale s (default 0.06;
//                          glTF convention, the bytes of bake/normal_map.h's RGBA8 texture)
// All three tile. Errors are one line; on failure no output file is left and files already at
// those names are unchanged.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "apps/commands.h"
#include "apps/output.h"
#include "bake/fur_field.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "scene/image_io.h"

namespace relief::cli {
namespace {

// The three maps of `field` staged under `names` (depth, colour, normal), renamed into place
// together.
Status write_fur_maps(const FurField& field, float depth_scale, const std::string names[3]) {
  const int n = field.size;
  Plane depth(n, n);
  Image color(n, n), normal(n, n);
  for (size_t i = 0; i < field.depth.size(); ++i) depth.values[i] = field.depth[i];
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) color.at(x, y) = glm::vec4(field.color[size_t(y) * n + x], 1.0f);
  const Texture n_map = fur_normal_texture(fur_depth_texture(field), depth_scale);
  const MipLevel& l0 = n_map.level(0);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint8_t* p = &l0.data[(static_cast<size_t>(y) * n + x) * 4];
      // The PNG encoder applies sRGB: hand it values that encode to the texel's bytes.
      normal.at(x, y) = glm::vec4(srgb_decoded_byte(p[0]), srgb_decoded_byte(p[1]),
                                  srgb_decoded_byte(p[2]), 1.0f);
    }
  StagedFiles out;
  Status st = stage_encoded(out, names[0], encode_plane(names[0], depth));
  if (st.ok()) st = stage_encoded(out, names[1], encode_image(names[1], color, 3, false));
  if (st.ok()) st = stage_encoded(out, names[2], encode_image(names[2], normal, 3, false));
  if (st.ok()) st = out.commit();
  return st;
}

}  // namespace

int run_bake_fur(const FurFieldOptions& options, const std::string& prefix, float depth_scale) {
  if (Status s = check_fur_field_options(options); !s.ok())
    return fail("bake --fur: " + s.message().substr(s.message().find(':') + 2), s.exit_code());
  if (!(depth_scale > 0.0f) || !std::isfinite(depth_scale))
    return fail("bake --fur: --depth-scale must be a positive finite number", 2);
  if (prefix.empty()) return fail("bake --fur: -o PREFIX must not be empty", 2);
  const std::string names[3] = {prefix + "_depth.png", prefix + "_base_color.png",
                                prefix + "_normal.png"};
  for (const std::string& n : names)  // before the bake: every output can be written
    if (Status o = check_output_path(n); !o.ok()) return fail(o.message(), o.exit_code());
  const auto t0 = std::chrono::steady_clock::now();
  Result<FurField> field = make_fur_field(options);
  if (!field.ok()) return fail(field.status().message(), field.status().exit_code());
  if (Status st = write_fur_maps(*field, depth_scale, names); !st.ok())
    return fail(st.message(), st.exit_code());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("baked %s field %dx%d (%zu strands) in %.2f s -> %s_{depth,base_color,normal}.png\n",
              fur_kind_name(options.kind), options.size, options.size, field->strands.size(), secs,
              prefix.c_str());
  return 0;
}

}  // namespace relief::cli
