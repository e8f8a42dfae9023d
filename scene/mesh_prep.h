// Mesh preparation (DESIGN.md, "One frame, as data", step 2): what a relief material needs per
// vertex beside positions, normals and uv.
//
// Tangents: per-triangle dP/du and dP/dv, area-weighted at each vertex, Gram-Schmidt against the
// normal, bitangent sign from the handedness of (T, B, N). Where uv is degenerate (zero uv area)
// a triangle contributes nothing; a vertex left with no tangent gets any unit vector
// perpendicular to its normal (a finite frame, documented fallback).
// Tile scale (quadric paper, section 3.4): per vertex (sx, sy) = the lengths of dP/du and dP/dv
// in object units, area-weighted over the adjacent triangles; 1 where uv is degenerate.
#pragma once

#include "scene/scene.h"

namespace relief {

void compute_normals(Mesh& mesh);      // area-weighted face normals where a mesh has none
void compute_tangents(Mesh& mesh);
void compute_tile_scale(Mesh& mesh);
// Fills whatever of normals, tangents and tile scale the mesh lacks.
void prepare_mesh(Mesh& mesh);

}  // namespace relief
