// The built-in `room` scene (builtin/builtin_room.cpp).
#pragma once

#include <functional>
#include <string>

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// One texel of a procedural relief pattern over uv in [0, 1)^2: depth (0 top, 1 deepest) and
// linear colour.
struct ReliefTexel {
  float depth;
  glm::vec3 color;
};
using ReliefPattern = std::function<ReliefTexel(float u, float v)>;

// A relief material from a pattern sampled at texel centres (size x size): R8 depth, sRGB colour
// and the normal map derived from the depth (wrapping), all with mip chains; technique `relief`
// with depth_scale (uv units), self_shadow and depth_write on.
Material procedural_relief_material(const std::string& name, const ReliefPattern& pattern, int size,
                                    float depth_scale);

// Appends a rectangle from `corner` along the edges eu and ev, facing cross(eu, ev)
// (counter-clockwise seen from that side), uv from (0, 0) at `corner` to uv_max. Call
// prepare_mesh (scene/mesh_prep.h) once the mesh is complete.
void add_rect(Mesh& mesh, glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, glm::vec2 uv_max);

// A latitude-longitude sphere of `slices` x `stacks` quads with normals, u around (4 tiles), v from
// the bottom to the top (2 tiles); prepared (prepare_mesh).
Mesh make_sphere(glm::vec3 centre, float radius, int slices, int stacks);

// The quadric paper's "relief room" (Oliveira and Policarpo 2005, figure 1): relief walls and
// floor, four relief columns, a relief sphere in the middle, one shadow-casting spot light and a
// fill light that casts none.
Result<Scene> make_room_scene();

}  // namespace relief
