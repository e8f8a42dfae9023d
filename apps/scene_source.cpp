#include "apps/scene_source.h"

#include "gl/gl_backend.h"
#include "scene/builtin.h"
#include "scene/gltf.h"

namespace relief::cli {

std::string default_scene_source() {
  return default_scene_name();
}

Result<Scene> load_scene_source(const std::string& name, bool allow_outside_scene_dir) {
  const auto ends_with = [&](const char* ext) {
    const std::string e(ext);
    return name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  GltfLoadOptions options;
  options.allow_outside_scene_dir = allow_outside_scene_dir;
  if (ends_with(".gltf") || ends_with(".glb")) return load_gltf(name, options);
  return make_builtin_scene(name);
}

Result<int> resolve_camera(const Scene& scene, const std::string& name_or_index) {
  if (name_or_index.empty()) return 0;
  const int n = static_cast<int>(scene.cameras.size());
  const bool digits = name_or_index.find_first_not_of("0123456789") == std::string::npos;
  if (digits && name_or_index.size() <= 9) {
    const int i = std::stoi(name_or_index);
    if (i < n) return i;
  }
  for (int i = 0; i < n; ++i)
    if (scene.cameras[i].name == name_or_index) return i;
  std::string known;
  for (int i = 0; i < n; ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  return Status::usage("--camera: scene '" + scene.name + "' has no camera '" + name_or_index +
                       "' (cameras: " + (known.empty() ? "none" : known) + ")");
}

Result<std::unique_ptr<Backend>> make_backend(const std::string& name, int threads, int gpu) {
  // threads applies to the CPU backend; llvmpipe takes LP_NUM_THREADS from the environment.
  if (name == "cpu") return make_cpu_backend(threads);
  return make_gl_backend(gpu);
}

}  // namespace relief::cli
