// The built-in `room` scene (scene/builtin_room.cpp).
#pragma once

#include "rasterizer/status.h"
#include "scene/scene.h"

namespace relief {

// The quadric paper's "relief room" (Oliveira and Policarpo 2005, figure 1): relief walls and
// floor, four relief columns, a relief sphere in the middle, one shadow-casting spot light and a
// fill light that casts none.
Result<Scene> make_room_scene();

}  // namespace relief
