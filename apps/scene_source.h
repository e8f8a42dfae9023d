// Where a scene comes from: a built-in name or a file; and which backend renders it.
#pragma once

#include <memory>
#include <string>

#include "rasterizer/status.h"
#include "render/render.h"
#include "scene/scene.h"

namespace relief::cli {

std::string default_scene_source();
// A name ending in .gltf or .glb loads that file (scene/gltf.h); any other is a built-in scene.
// allow_outside_scene_dir: `--allow-outside-scene-dir` (the file's URIs may leave its folder).
Result<Scene> load_scene_source(const std::string& name_or_path,
                                bool allow_outside_scene_dir = false);
// The help text of `--allow-outside-scene-dir` (render, export, bench, bake --dual).
inline constexpr const char* kAllowOutsideSceneDirHelp =
    "Let a glTF file's buffer and image URIs lead outside its folder (.., symlinks)";
// `--camera NAME|INDEX`: an index into Scene::cameras, or the first camera with that name; empty
// picks camera 0. Anything else is a usage error listing the scene's cameras.
Result<int> resolve_camera(const Scene& scene, const std::string& name_or_index);
// "cpu" or "gl"; gpu is the EGL device index for gl (-1: first usable).
Result<std::unique_ptr<Backend>> make_backend(const std::string& name, int threads, int gpu);

}  // namespace relief::cli
