// The built-in `materials` scene (builtin/builtin_materials.cpp).
#pragma once

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// Four relief spheres lit by the glTF metallic-roughness BRDF (smooth and rough metal, smooth and
// rough dielectric) on a relief floor whose metallicRoughness texture alternates rough and
// polished tiles, under a shadow-casting spot light in physical units (docs/scene-format.md,
// "Lights" and "Shading").
Result<Scene> make_materials_scene();

}  // namespace relief
