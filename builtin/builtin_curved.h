// Curved built-in scenes for relief mapping with correct silhouettes (Oliveira and Policarpo, "An
// Efficient Representation for Surface Details", UFRGS RP-351, 2005: figure 9 cylinder and
// teapot, figure 14 the saddle region of a torus) and the parametric meshes they are made of.
#pragma once

#include <functional>

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

// A point of a parametric surface at (s, t) in [0, 1]^2: position, unit normal and the unit
// direction of dP/ds (the limit direction where dP/ds vanishes, as at a sphere's poles).
struct SurfacePoint {
  glm::vec3 p;
  glm::vec3 n;
  glm::vec3 ds;
};
using Surface = std::function<SurfacePoint(float s, float t)>;

// A grid of (ns + 1) x (nt + 1) vertices at s = i / ns, t = j / nt with uv = (s, t) * uv_tiles,
// two counter-clockwise triangles per cell seen from the normal side when (dP/ds, dP/dt, N) is
// right-handed; analytic normals and tangents (T along dP/ds, made perpendicular to N; the
// bitangent sign from dP/dt, so B runs along +v), the rest from prepare_mesh (scene/mesh_prep.h):
// the surface's own frame, not an estimate from the triangulation.
Mesh parametric_mesh(const std::string& name, const Surface& surface, int ns, int nt,
                     glm::vec2 uv_tiles);

// Sphere of radius r: s around (phi = 2 pi s), t from the south pole (0) to the north pole (1).
// At a vertex T = dP/ds, B = dP/dt, quadric a = b = 1 / (2 r).
Surface sphere_surface(float r);
// Torus around y: major radius R (s, alpha = 2 pi s), tube radius r (t, beta = 2 pi t; beta = 0
// outermost). Quadric a = cos(beta) / (2 (R + r cos(beta))) (negative on the inner, saddle half),
// b = 1 / (2 r).
Surface torus_surface(float R, float r);
// Open cylinder along y of radius r and height h: s around, t along the axis. a = 1 / (2 r), b = 0.
Surface cylinder_surface(float r, float h);

// The Utah teapot (Newell 1975): its 32 bicubic Bezier patches tessellated n x n each (uv per
// patch in [0, 1]^2 times uv_tiles), scaled to a height of about `height`, standing on y = 0.
Mesh make_teapot(int n, float height, glm::vec2 uv_tiles);

// `sphere`, `cylinder`, `torus`, `teapot`: one relief-mapped object (technique relief_quadric,
// silhouette on; `--technique relief` keeps the polygonal outline), one sun, one camera.
Result<Scene> make_curved_scene(const std::string& name);

}  // namespace relief
