// Dual-depth relief textures baked with the CPU rasterizer: Policarpo, Oliveira and Comba,
// "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005, section 3.1. A closed
// mesh is rendered orthographically along -z twice, keeping the nearest surface (front layer)
// and the farthest (back layer), into square maps over a box around it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace relief {

// The baked maps: size x size texels, row j at v = (j + 0.5) / size (v grows with +y), column i
// at u = (i + 0.5) / size (u grows with +x). Depth 0 at box_max.z, 1 at box_min.z; where the mesh
// is absent front = 1 and back = 0 (never inside). Normals are the mesh's unit normals in the box
// frame (x along u, y along v, z up out of the reference plane), (0, 0, 1) where absent.
struct DualDepthMaps {
  int size = 0;
  std::vector<float> front, back;
  std::vector<glm::vec3> front_normal, back_normal;
  glm::vec3 box_min{0.0f}, box_max{0.0f};  // square in x and y, centred on the mesh
  // The relief height over the box side, the relief plugins' depth_scale for a quad covering the
  // box's top face with uv [0, 1]^2.
  float depth_scale() const { return (box_max.z - box_min.z) / (box_max.x - box_min.x); }
};

// Bakes `positions` (with per-vertex `normals`, triangles in `indices`) into size x size maps
// over the mesh's bounds in x and y grown by the factor `grow` (>= 1; e.g. so that views away
// from the axis still enter through the box's top face), on `threads` threads (0: all cores).
// Images are the same for any thread count. Empty input gives empty (absent) maps over a unit box.
DualDepthMaps bake_dual_depth(std::span<const glm::vec3> positions,
                              std::span<const glm::vec3> normals, std::span<const uint32_t> indices,
                              int size, float grow = 1.0f, int threads = 0);

}  // namespace relief
