#include "scene/mesh_prep.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

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
template <class Fn>
void for_each_uv_triangle(const Mesh& m, Fn&& fn) {
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

namespace {

// dP/du and dP/dv of a triangle (object units per uv unit).
glm::vec3 dp_du(const UvTriangle& u) {
  return (u.e1 * u.d2.y - u.e2 * u.d1.y) / u.det;
}
glm::vec3 dp_dv(const UvTriangle& u) {
  return (u.e2 * u.d1.x - u.e1 * u.d2.x) / u.det;
}

// The handedness of a triangle's uv mapping seen from the normal n of one of its corners.
float uv_handedness(glm::vec3 n, const UvTriangle& u) {
  return glm::dot(glm::cross(n, dp_du(u)), dp_dv(u)) < 0.0f ? -1.0f : 1.0f;
}

// Appends a copy of vertex k (every per-vertex array the mesh has) and returns its index.
uint32_t duplicate_vertex(Mesh& m, uint32_t k) {
  const size_t n = m.positions.size();
  auto dup = [&](auto& v) {
    if (v.size() == n) v.push_back(v[k]);
  };
  dup(m.normals);
  dup(m.uvs);
  dup(m.tangents);
  dup(m.quadric);
  dup(m.tile_scale);
  m.positions.push_back(m.positions[k]);
  return static_cast<uint32_t>(n);
}

// MikkTSpace keeps the two sides of a mirrored uv seam apart: a vertex whose triangles disagree on
// the uv handedness is split, the copy taking the left-handed triangles.
void split_mirrored_vertices(Mesh& m) {
  const size_t nv = m.positions.size();
  std::vector<uint8_t> seen(nv, 0);  // bit 0: right-handed corner, bit 1: left-handed
  std::vector<int8_t> corner_sign(m.indices.size(), 0);
  for_each_uv_triangle(m, [&](const uint32_t* i, const UvTriangle& u) {
    const size_t t = static_cast<size_t>(i - m.indices.data());
    // a triangle without area (a pole of a uv sphere) has no handedness: no vote
    const float e2 = std::max(glm::dot(u.e1, u.e1), glm::dot(u.e2, u.e2));
    if (!(glm::length(glm::cross(u.e1, u.e2)) > 1e-4f * e2)) return;
    for (int k = 0; k < 3; ++k) {
      const bool left = uv_handedness(m.normals[i[k]], u) < 0.0f;
      corner_sign[t + k] = left ? -1 : 1;
      seen[i[k]] |= left ? 2 : 1;
    }
  });
  std::vector<uint32_t> copy(nv, UINT32_MAX);
  for (size_t c = 0; c < m.indices.size(); ++c) {
    const uint32_t v = m.indices[c];
    if (v >= nv || seen[v] != 3 || corner_sign[c] >= 0) continue;
    if (copy[v] == UINT32_MAX) copy[v] = duplicate_vertex(m, v);
    m.indices[c] = copy[v];
  }
}

}  // namespace

void compute_tangents(Mesh& m) {
  split_mirrored_vertices(m);
  const size_t nv = m.positions.size();
  std::vector<glm::vec3> tan(nv, glm::vec3(0.0f)), bit(nv, glm::vec3(0.0f));
  for_each_uv_triangle(m, [&](const uint32_t* i, const UvTriangle& u) {
    // dP/du and dP/dv scaled by the uv area (|det|), i.e. area-weighted
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
      m.tangents[k] = glm::vec4(perpendicular(n), 1.0f);  // no usable uv: a finite frame
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
    const glm::vec3 dpdu = dp_du(u), dpdv = dp_dv(u);
    const float area = 0.5f * glm::length(glm::cross(u.e1, u.e2));
    for (int k = 0; k < 3; ++k)
      acc[i[k]] += glm::vec3(glm::length(dpdu), glm::length(dpdv), 1.0f) * area;
  });
  m.tile_scale.resize(nv);
  for (size_t k = 0; k < nv; ++k)
    m.tile_scale[k] = acc[k].z > 0.0f ? glm::vec2(acc[k].x, acc[k].y) / acc[k].z : glm::vec2(1.0f);
}

namespace {

// Vertices welded by exact position: group[v] is the same for every vertex at one point (uv and
// normal seams), numbered 0..groups-1; first[g] is one vertex of group g.
struct Welded {
  std::vector<uint32_t> group, first;
};
Welded weld_by_position(const Mesh& m) {
  const size_t nv = m.positions.size();
  std::vector<uint32_t> order(nv);
  for (size_t k = 0; k < nv; ++k) order[k] = static_cast<uint32_t>(k);
  auto key = [&](uint32_t k) {
    const glm::vec3& p = m.positions[k];
    return std::make_tuple(p.x, p.y, p.z, k);
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  Welded w;
  w.group.assign(nv, 0);
  for (size_t r = 0; r < nv; ++r) {
    const uint32_t k = order[r];
    if (r == 0 || m.positions[k] != m.positions[order[r - 1]]) w.first.push_back(k);
    w.group[k] = static_cast<uint32_t>(w.first.size() - 1);
  }
  return w;
}

}  // namespace

glm::vec2 fit_quadric(const glm::vec3* d, size_t count, glm::vec3 t, glm::vec3 b, glm::vec3 n) {
  double h2 = 0.0;  // mean squared neighbour distance: the fit runs in units of h
  for (size_t i = 0; i < count; ++i) h2 += double(glm::dot(d[i], d[i]));
  if (!(count > 0 && h2 > 0.0 && std::isfinite(h2))) return glm::vec2(0.0f);
  const double h = std::sqrt(h2 / double(count));
  double s40 = 0, s22 = 0, s04 = 0, sxz = 0, syz = 0;
  for (size_t i = 0; i < count; ++i) {
    const double x = glm::dot(d[i], t) / h, y = glm::dot(d[i], b) / h, z = -glm::dot(d[i], n) / h;
    const double x2 = x * x, y2 = y * y;
    s40 += x2 * x2;
    s22 += x2 * y2;
    s04 += y2 * y2;
    sxz += x2 * z;
    syz += y2 * z;
  }
  double a, bb;
  const double det = s40 * s04 - s22 * s22, tr = s40 + s04;
  if (det > 1e-6 * tr * tr) {
    a = (s04 * sxz - s22 * syz) / det;
    bb = (s40 * syz - s22 * sxz) / det;
  } else {
    // under-determined (neighbours along one line, or x^2 = y^2 for all): the isotropic fit
    // z = c (x^2 + y^2), c = sum r^2 z / sum r^4
    const double r4 = s40 + 2.0 * s22 + s04;
    a = bb = r4 > 1e-12 ? (sxz + syz) / r4 : 0.0;
  }
  a /= h;
  bb /= h;
  if (!std::isfinite(a) || !std::isfinite(bb)) return glm::vec2(0.0f);
  return glm::vec2(static_cast<float>(a), static_cast<float>(bb));
}

void compute_quadrics(Mesh& m) {
  const size_t nv = m.positions.size();
  m.quadric.assign(nv, glm::vec2(0.0f));
  if (nv == 0) return;
  const Welded w = weld_by_position(m);
  // one-ring of every welded point: (group, neighbour group) pairs, sorted and unique
  std::vector<std::pair<uint32_t, uint32_t>> edges;
  edges.reserve(m.indices.size() * 2);
  for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t g = w.group[m.indices[t + k]];
      for (int j = 1; j < 3; ++j) {
        const uint32_t o = w.group[m.indices[t + (k + j) % 3]];
        if (o != g) edges.emplace_back(g, o);
      }
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<size_t> start(w.first.size() + 1, 0);
  for (const auto& e : edges) ++start[e.first + 1];
  for (size_t g = 0; g < w.first.size(); ++g) start[g + 1] += start[g];
  std::vector<glm::vec3> d;
  for (size_t k = 0; k < nv; ++k) {
    const uint32_t g = w.group[k];
    d.clear();
    for (size_t e = start[g]; e < start[g + 1]; ++e)
      d.push_back(m.positions[w.first[edges[e].second]] - m.positions[k]);
    // the vertex's tangent frame as the kernels rebuild it (shaders_cpp/frame.h)
    const glm::vec3 n = glm::normalize(m.normals[k]);
    const glm::vec4 t4 = k < m.tangents.size() ? m.tangents[k] : glm::vec4(perpendicular(n), 1);
    glm::vec3 t = glm::vec3(t4) - n * glm::dot(n, glm::vec3(t4));
    t = glm::length(t) > 1e-12f ? glm::normalize(t) : perpendicular(n);
    const glm::vec3 b = glm::cross(n, t) * (t4.w < 0.0f ? -1.0f : 1.0f);
    m.quadric[k] = fit_quadric(d.data(), d.size(), t, b, n);
  }
}

void prepare_mesh(Mesh& m) {
  if (m.normals.size() != m.positions.size()) compute_normals(m);
  if (m.uvs.size() != m.positions.size()) m.uvs.assign(m.positions.size(), glm::vec2(0.0f));
  if (m.tangents.size() != m.positions.size()) compute_tangents(m);
  if (m.tile_scale.size() != m.positions.size()) compute_tile_scale(m);
  if (m.quadric.size() != m.positions.size()) compute_quadrics(m);
}

}  // namespace relief
