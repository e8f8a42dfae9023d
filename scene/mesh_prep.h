// Mesh preparation (DESIGN.md, "One frame, as data", step 2): what a relief material needs per
// vertex beside positions, normals and uv.
//
// Tangents, MikkTSpace-compatible in the sense glTF 2.0 asks of clients (Mikkelsen 2008): per
// triangle dP/du and dP/dv, weighted by the triangle's uv area, summed per vertex (MikkTSpace
// weights by corner angle; the two agree on smooth meshes, tests/scene/mesh_prep_test.cpp),
// Gram-Schmidt against the normal; the bitangent sign w = +1
// or -1 is the handedness of (T, B, N). A vertex whose triangles disagree on the handedness (a
// mirrored uv seam) is split first, as MikkTSpace does: the copy (every per-vertex array) takes
// the left-handed triangles, so each side keeps its own sign. Where uv is degenerate (zero uv
// area, |det| < 1e-20) a triangle contributes nothing, and a sliver (area < 1e-4 of its longest
// edge squared, e.g. at a pole) does not vote on the handedness; a vertex left with no tangent takes any unit
// vector perpendicular to its normal, w = +1 (a finite frame).
// Tile scale (quadric paper, section 3.4): per vertex (sx, sy) = the lengths of dP/du and dP/dv
// in object units, area-weighted over the adjacent triangles; 1 where uv is degenerate.
#pragma once

#include "scene/scene.h"

namespace relief {

void compute_normals(Mesh& mesh);      // area-weighted face normals where a mesh has none
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
