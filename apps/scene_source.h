// Where a scene comes from: a built-in name or a file; and which backend renders it.
#pragma once

#include <memory>
#include <string>

#include "rasterizer/status.h"
#include "render/render.h"
#include "scene/scene.h"

namespace relief::cli {

std::string default_scene_source();
Result<Scene> load_scene_source(const std::string& name_or_path);
// "cpu" or "gl"; gpu is the EGL device index for gl (-1: first usable).
Result<std::unique_ptr<Backend>> make_backend(const std::string& name, int threads, int gpu);

}  // namespace relief::cli
