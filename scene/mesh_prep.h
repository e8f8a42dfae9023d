// Mesh preparation (DESIGN.md, "One frame, as data", step 2): what a relief material needs per
// vertex beside positions, normals and uv.
//
// Tangents: MikkTSpace (Mikkelsen 2008, "Simulation of wrinkled surfaces revisited"), the frame
// glTF 2.0 asks clients to compute, written here from the published algorithm and checked corner
// by corner against the reference implementation (tests/scene/mikktspace_test.cpp, within 1e-4):
// vertices equal in position, normal and uv are welded; triangles with two equal positions are
// degenerate; around each vertex, triangles reachable across shared edges with the same uv
// orientation form one group, whose tangent is the sum of the triangles' dP/du projected on the
// vertex normal, normalised and weighted by the corner angle; a triangle with no usable uv
// derivatives joins the first group that reaches it; a degenerate triangle's corner copies the
// first good corner at its vertex. Run on the mesh's own uv (no flip): w = +1 where the uv
// mapping keeps orientation, so B = w cross(N, T) runs along +v (shaders_cpp/frame.h). glTF's
// TANGENT has the opposite w (scene/gltf_read_meshes.cpp and gltf_write.cpp negate it). Corners of
// one vertex that get different spaces (a mirrored uv seam, a fan broken by a non-manifold edge)
// are split: the vertex keeps the first space met in index order, copies (every per-vertex array,
// appended) take the others; triangle order and count are kept. Where MikkTSpace gives a corner no
// space (no group reaches it: no usable uv anywhere around it) the tangent is any unit vector
// perpendicular to the normal, w = +1 (the reference leaves (1, 0, 0), -1 there).
// Tile scale (quadric paper, section 3.4): per vertex (sx, sy) = the lengths of dP/du and dP/dv
// in object units, area-weighted over the adjacent triangles; 1 where uv is degenerate.
#pragma once

#include "scene/scene.h"

namespace relief {

void compute_normals(Mesh& mesh);  // area-weighted face normals where a mesh has none
void compute_tangents(Mesh& mesh);
void compute_tile_scale(Mesh& mesh);

// Quadric paper (Oliveira and Policarpo 2005), section 3, equation 2: per vertex, z = a x^2 + b y^2
// fitted by least squares to the vertex's one-ring in its tangent frame (x along T, y along
// B = w cross(N, T), z = depth along -N, so a convex surface has a, b > 0: a sphere of radius r
// gives a = b = 1 / (2 r)). Vertices at the same position (uv and normal seams) share one ring.
// Conditioning: the 2 x 2 normal equations are solved in units of the ring's rms edge length, in
// double. When they are singular relative to their scale (det < 1e-6 trace^2: neighbours along
// one line, or x^2 = y^2 for every neighbour, e.g. a ring on the diagonals) the isotropic fit
// a = b = sum r^2 z / sum r^4 is used; a vertex with no neighbour at a distance gets (0, 0).
// Never NaN or Inf.
void compute_quadrics(Mesh& mesh);
// The fit of one vertex: d = neighbour - vertex offsets, (t, b, n) its orthonormal frame.
glm::vec2 fit_quadric(const glm::vec3* d, size_t count, glm::vec3 t, glm::vec3 b, glm::vec3 n);
// Fills whatever of normals, uv, tangents, tile scale and quadrics the mesh lacks.
void prepare_mesh(Mesh& mesh);

}  // namespace relief
