// The built-in `impostor` scene: a whole object drawn on one quad from dual-depth relief textures
// (Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces",
// I3D 2005, section 3.1), baked in code with our rasterizer (bake/dual_depth_maps.h).
#pragma once

#include "bake/dual_depth_maps.h"
#include "scene/scene.h"

namespace relief {

// A relief_dual material from baked maps: front and back depth (R32F, no mips, so distant views
// do not blur the layers into each other), front and back normal maps, clamped bilinear sampling
// and depth_scale = maps.depth_scale().
Material dual_depth_material(const std::string& name, const DualDepthMaps& maps,
                             glm::vec3 base_color);

// The quad that carries `maps`: the top face of their box (z = box_max.z), facing +z, uv (0, 0)
// at (box_min.x, box_min.y), u along +x, v along +y.
Mesh dual_depth_quad(const DualDepthMaps& maps);

// Half-size of a dual-depth quad, over the object's own half-size, such that every view up to
// `max_angle_deg` off the quad's normal enters the object through the quad: (1 + sin a) / cos a
// for an object as deep as it is wide.
float impostor_grow(float max_angle_deg);

// `impostor`: a unit sphere (64 x 32 cells) baked at 256 x 256 for views up to 45 degrees off
// axis, on one quad, technique relief_dual; one sun, one camera 30 degrees off axis.
Scene make_impostor_scene();

}  // namespace relief
