#include "apps/scene_source.h"

#include "gl/gl_backend.h"
#include "scene/builtin.h"

namespace relief::cli {

std::string default_scene_source() { return default_scene_name(); }

Result<Scene> load_scene_source(const std::string& name) {
  const auto ends_with = [&](const char* ext) {
    const std::string e(ext);
    return name.size() > e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  if (ends_with(".gltf") || ends_with(".glb"))
    return Status::error(name + ": glTF scenes are not supported yet");
  return make_builtin_scene(name);
}

Result<std::unique_ptr<Backend>> make_backend(const std::string& name, int threads, int gpu) {
  // threads applies to the CPU backend; llvmpipe takes LP_NUM_THREADS from the environment.
  if (name == "cpu") return make_cpu_backend(threads);
  return make_gl_backend(gpu);
}

}  // namespace relief::cli
