// `relief bake --dual MESH.gltf -o PREFIX [--size N] [--grow G] [--threads N]`: dual-depth relief
// textures (Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal
// Surfaces", I3D 2005, section 3.1) of every mesh instance of a glTF scene, rendered
// orthographically along -z with our rasterizer (bake/dual_depth_maps.h) into
//   PREFIX_front.exr, PREFIX_back.exr             depth layers (one float channel: 0 top, 1
//                                                 deepest; absent: front 1, back 0)
//   PREFIX_front_normal.exr, PREFIX_back_normal.exr  outward normals, RGB = n * 0.5 + 0.5, linear,
//                                                 green = -n.y (glTF convention on the quad,
//                                                 whose v runs along +y: bake/normal_map.h)
// and prints the depth_scale for relief_dual on a quad over the maps' box. Errors are one line;
// on failure no output file is left.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "apps/commands.h"
#include "apps/output.h"
#include "bake/dual_depth_maps.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/image_io.h"

namespace relief::cli {

int run_bake_dual(const std::string& mesh_path, const std::string& prefix, int size, float grow,
                  int threads, bool allow_outside_scene_dir) {
  if (size < 1 || size > 8192) return fail("bake --dual: --size must be in 1..8192", 2);
  if (!(grow >= 1.0f) || !std::isfinite(grow) || grow > 100.0f)
    return fail("bake --dual: --grow must be in [1, 100]", 2);
  if (threads < 0) return fail("bake: --threads must be >= 0 (0: all cores)", 2);
  if (prefix.empty()) return fail("bake --dual: -o PREFIX must not be empty", 2);
  const std::string names[4] = {prefix + "_front.exr", prefix + "_back.exr",
                                prefix + "_front_normal.exr", prefix + "_back_normal.exr"};
  for (const std::string& n : names)  // before the bake: every output can be written
    if (Status o = check_output_path(n); !o.ok()) return fail(o.message(), o.exit_code());
  const auto t0 = std::chrono::steady_clock::now();
  GltfLoadOptions load_options;
  load_options.allow_outside_scene_dir = allow_outside_scene_dir;
  Result<Scene> scene = load_scene(mesh_path, load_options);
  if (!scene.ok()) return fail(scene.status().message(), scene.status().exit_code());
  std::vector<glm::vec3> positions, normals;
  std::vector<uint32_t> indices;
  for (const Instance& inst : scene->instances) {
    if (inst.mesh < 0 || inst.mesh >= static_cast<int>(scene->meshes.size())) continue;
    const Mesh& m = scene->meshes[inst.mesh];
    const uint32_t base = static_cast<uint32_t>(positions.size());
    const glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(inst.transform)));
    for (size_t i = 0; i < m.positions.size(); ++i) {
      positions.push_back(glm::vec3(inst.transform * glm::vec4(m.positions[i], 1.0f)));
      normals.push_back(i < m.normals.size() ? nm * m.normals[i] : glm::vec3(0.0f, 0.0f, 1.0f));
    }
    for (uint32_t k : m.indices) indices.push_back(base + k);
  }
  if (indices.empty()) return fail(printable(mesh_path) + ": no triangles to bake", 1);
  const DualDepthMaps maps = bake_dual_depth(positions, normals, indices, size, grow, threads);

  Plane front(size, size), back(size, size);
  Image front_n(size, size), back_n(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const size_t i = static_cast<size_t>(y) * size + x;
      front.at(x, y) = maps.front[i];
      back.at(x, y) = maps.back[i];
      const glm::vec3 flip_green(1.0f, -1.0f, 1.0f);  // toward the image top, -v = -y
      front_n.at(x, y) = glm::vec4(maps.front_normal[i] * flip_green * 0.5f + 0.5f, 1.0f);
      back_n.at(x, y) = glm::vec4(maps.back_normal[i] * flip_green * 0.5f + 0.5f, 1.0f);
    }
  // All four are written in full before any is renamed into place; on failure none is, and
  // files already at those names are left as they were.
  StagedFiles out;
  Status st = stage_encoded(out, names[0], encode_plane(names[0], front));
  if (st.ok()) st = stage_encoded(out, names[1], encode_plane(names[1], back));
  if (st.ok()) st = stage_encoded(out, names[2], encode_image(names[2], front_n));
  if (st.ok()) st = stage_encoded(out, names[3], encode_image(names[3], back_n));
  if (st.ok()) st = out.commit();
  if (!st.ok()) return fail(st.message(), st.exit_code());
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "baked dual depth %dx%d in %.2f s -> %s_{front,back}{,_normal}.exr; box (%g %g %g) "
      "to (%g %g %g), depth_scale %.6g\n",
      size, size, secs, prefix.c_str(), maps.box_min.x, maps.box_min.y, maps.box_min.z,
      maps.box_max.x, maps.box_max.y, maps.box_max.z, maps.depth_scale());
  return 0;
}

}  // namespace relief::cli
