// Built-in scenes, generated in code (`relief scenes` lists them).
#pragma once

#include <string>
#include <vector>

#include "rasterizer/status.h"
#include "scene/scene.h"

namespace relief {

struct BuiltinSceneInfo {
  std::string name;
  std::string description;
};

const std::vector<BuiltinSceneInfo>& builtin_scenes();
// The scene `make demo` renders when none is named.
const char* default_scene_name();
Result<Scene> make_builtin_scene(const std::string& name);

}  // namespace relief
