// The built-in `fur` and `grass` scenes (builtin/builtin_fur.cpp): generated fur and grass fields
// (bake/fur_field.h) rendered as one relief surface by steep parallax mapping (McGuire and
// McGuire 2005, "Fur and Grass", figure 3).
#pragma once

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// A fur-covered sphere under one directional light, the camera framing the sphere.
Result<Scene> make_fur_scene();
// A grass-covered ground plane seen from about 15 degrees above it, one sun.
Result<Scene> make_grass_scene();

}  // namespace relief
