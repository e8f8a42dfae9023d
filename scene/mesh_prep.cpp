#include "scene/mesh_prep.h"

#include <cmath>

#include <glm/geometric.hpp>

namespace relief {
namespace {

glm::vec3 perpendicular(glm::vec3 n) {
  const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

// A triangle's edges in object space and in uv, and the uv determinant.
struct UvTriangle {
  glm::vec3 e1, e2;
  glm::vec2 d1, d2;
  float det;
};

// Calls fn(indices, triangle) for every triangle whose uv mapping is not degenerate (|det| >=
// 1e-20); nothing when the mesh has no uv per vertex.
template <class Fn> void for_each_uv_triangle(const Mesh& m, Fn&& fn) {
  if (m.uvs.size() != m.positions.size()) return;
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const uint32_t* i = &m.indices[t];
    UvTriangle u;
    u.e1 = m.positions[i[1]] - m.positions[i[0]];
    u.e2 = m.positions[i[2]] - m.positions[i[0]];
    u.d1 = m.uvs[i[1]] - m.uvs[i[0]];
    u.d2 = m.uvs[i[2]] - m.uvs[i[0]];
    u.det = u.d1.x * u.d2.y - u.d2.x * u.d1.y;
    if (std::fabs(u.det) < 1e-20f) continue;  // degenerate uv: contributes nothing
    fn(i, u);
  }
}

}  // namespace

void compute_normals(Mesh& m) {
  m.normals.assign(m.positions.size(), glm::vec3(0.0f));
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
    const uint32_t i0 = m.indices[t], i1 = m.indices[t + 1], i2 = m.indices[t + 2];
    const glm::vec3 n =
        glm::cross(m.positions[i1] - m.positions[i0], m.positions[i2] - m.positions[i0]);
    m.normals[i0] += n;
    m.normals[i1] += n;
    m.normals[i2] += n;
  }
  for (auto& n : m.normals) {
    const float l = glm::length(n);
    n = l > 0.0f ? n / l : glm::vec3(0, 0, 1);
  }
}

void compute_tangents(Mesh& m) {
  const size_t nv = m.positions.size();
  std::vector<glm::vec3> tan(nv, glm::vec3(0.0f)), bit(nv, glm::vec3(0.0f));
  for_each_uv_triangle(m, [&](const uint32_t* i, const UvTriangle& u) {
    // dP/du and dP/dv scaled by the uv area (|det|), i.e. area-weighted.
    const float s = u.det > 0.0f ? 1.0f : -1.0f;
    const glm::vec3 dpdu = (u.e1 * u.d2.y - u.e2 * u.d1.y) * s;
    const glm::vec3 dpdv = (u.e2 * u.d1.x - u.e1 * u.d2.x) * s;
    for (int k = 0; k < 3; ++k) {
      tan[i[k]] += dpdu;
      bit[i[k]] += dpdv;
    }
  });
  m.tangents.resize(nv);
  for (size_t k = 0; k < nv; ++k) {
    const glm::vec3 n = glm::normalize(m.normals[k]);
    glm::vec3 t = tan[k] - n * glm::dot(n, tan[k]);
    const float len = glm::length(t);
    if (!(len > 1e-12f)) {
      m.tangents[k] = glm::vec4(perpendicular(n), 1.0f);
      continue;
    }
    t /= len;
    const float w = glm::dot(glm::cross(n, t), bit[k]) < 0.0f ? -1.0f : 1.0f;
    m.tangents[k] = glm::vec4(t, w);
  }
}

void compute_tile_scale(Mesh& m) {
  const size_t nv = m.positions.size();
  std::vector<glm::vec3> acc(nv, glm::vec3(0.0f));  // (sum |dP/du| * a, sum |dP/dv| * a, sum a)
  for_each_uv_triangle(m, [&](const uint32_t* i, const UvTriangle& u) {
    const glm::vec3 dpdu = (u.e1 * u.d2.y - u.e2 * u.d1.y) / u.det;
    const glm::vec3 dpdv = (u.e2 * u.d1.x - u.e1 * u.d2.x) / u.det;
    const float area = 0.5f * glm::length(glm::cross(u.e1, u.e2));
    for (int k = 0; k < 3; ++k)
      acc[i[k]] += glm::vec3(glm::length(dpdu), glm::length(dpdv), 1.0f) * area;
  });
  m.tile_scale.resize(nv);
  for (size_t k = 0; k < nv; ++k)
    m.tile_scale[k] = acc[k].z > 0.0f ? glm::vec2(acc[k].x, acc[k].y) / acc[k].z : glm::vec2(1.0f);
}

void prepare_mesh(Mesh& m) {
  if (m.normals.size() != m.positions.size()) compute_normals(m);
  if (m.uvs.size() != m.positions.size()) m.uvs.assign(m.positions.size(), glm::vec2(0.0f));
  if (m.tangents.size() != m.positions.size()) compute_tangents(m);
  if (m.tile_scale.size() != m.positions.size()) compute_tile_scale(m);
  if (m.quadric.size() != m.positions.size()) m.quadric.assign(m.positions.size(), glm::vec2(0.0f));
}

}  // namespace relief
