// The built-in `interpenetration` and `teatime` scenes (builtin/builtin_showcase.cpp).
#pragma once

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// Spheres through a relief floor and two coincident relief cylinders of different materials.
Result<Scene> make_interpenetration_scene();
// A relief teapot on a relief floor with a shadow-casting spot light.
Result<Scene> make_teatime_scene();

}  // namespace relief
