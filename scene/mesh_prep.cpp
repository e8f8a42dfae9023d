#include "scene/mesh_prep.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// ---- MikkTSpace (Mikkelsen 2008), triangles only -------------------------------------------
// Our own code following the published algorithm; the comments name its steps.

// Float bits with -0 folded onto +0, so that equal floats give equal keys (a total order).
uint32_t float_key(float f) {
  if (f == 0.0f) f = 0.0f;
  uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

bool tiny(float x) {
  return !(std::fabs(x) > FLT_MIN);
}
bool tiny(glm::vec3 v) {
  return tiny(v.x) && tiny(v.y) && tiny(v.z);
}
glm::vec3 unit_or_as_is(glm::vec3 v) {
  return tiny(v) ? v : glm::normalize(v);
}
glm::vec3 project(glm::vec3 v, glm::vec3 n) {
  return unit_or_as_is(v - n * glm::dot(n, v));
}

// Step 1: vertices with identical position, normal and uv are one vertex (weld[v], the lowest
// index of its class).
std::vector<uint32_t> weld_vertices(const Mesh& m, bool has_uv) {
  const size_t nv = m.positions.size();
  auto key = [&](uint32_t k) {
    std::array<uint32_t, 8> a{};
    const glm::vec3 p = m.positions[k], n = m.normals[k];
    const glm::vec2 t = has_uv ? m.uvs[k] : glm::vec2(0.0f);
    const float f[8] = {p.x, p.y, p.z, n.x, n.y, n.z, t.x, t.y};
    for (int i = 0; i < 8; ++i) a[i] = float_key(f[i]);
    return a;
  };
  std::vector<std::pair<std::array<uint32_t, 8>, uint32_t>> keys(nv);
  for (size_t k = 0; k < nv; ++k) keys[k] = {key(static_cast<uint32_t>(k)), uint32_t(k)};
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> weld(nv);
  for (size_t r = 0; r < nv; ++r)
    weld[keys[r].second] =
        r > 0 && keys[r].first == keys[r - 1].first ? weld[keys[r - 1].second] : keys[r].second;
  return weld;
}

struct MikkTri {
  uint32_t v[3];                   // welded vertex of each corner
  glm::vec3 os{0.0f}, ot{0.0f};    // unit directions of dP/du, dP/dv (zero when degenerate)
  bool preserving = false;         // the uv mapping keeps orientation (signed uv area > 0)
  bool any = true;                 // no usable uv derivatives: joins whatever group reaches it
  int32_t next[3] = {-1, -1, -1};  // triangle across edge (v[k], v[k+1])
  int32_t group[3] = {-1, -1, -1};
};

struct MikkGroup {
  uint32_t vertex;
  bool preserving;
  std::vector<uint32_t> tris;
};

struct CornerSpace {
  glm::vec3 t{1.0f, 0.0f, 0.0f};
  bool preserving = false;
  bool valid = false;  // false: MikkTSpace gives this corner no tangent space
};

// Step 3: adjacency across edges shared, with opposite directions, by two triangles; where more
// than two share an edge, the lowest-numbered free ones pair first.
void link_neighbours(std::vector<MikkTri>& tris) {
  struct Edge {
    uint32_t lo, hi, tri, k;
  };
  std::vector<Edge> edges;
  edges.reserve(tris.size() * 3);
  for (size_t t = 0; t < tris.size(); ++t)
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t a = tris[t].v[k], b = tris[t].v[(k + 1) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), uint32_t(t), k});
    }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return std::tie(x.lo, x.hi, x.tri, x.k) < std::tie(y.lo, y.hi, y.tri, y.k);
  });
  for (size_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    MikkTri& a = tris[e.tri];
    if (a.next[e.k] >= 0) continue;
    const uint32_t from = a.v[e.k], to = a.v[(e.k + 1) % 3];
    for (size_t j = i + 1; j < edges.size() && edges[j].lo == e.lo && edges[j].hi == e.hi; ++j) {
      MikkTri& b = tris[edges[j].tri];
      const uint32_t k = edges[j].k;
      if (b.v[k] == to && b.v[(k + 1) % 3] == from && b.next[k] < 0) {
        a.next[e.k] = int32_t(edges[j].tri);
        b.next[k] = int32_t(e.tri);
        break;
      }
    }
  }
}

int corner_of(const MikkTri& t, uint32_t v) {
  return t.v[0] == v ? 0 : t.v[1] == v ? 1 : t.v[2] == v ? 2 : -1;
}

// Step 4: around each vertex, the triangles reachable from one another across shared edges with
// the same uv orientation form a group (one tangent space); a triangle with no usable uv takes
// the orientation of the first group to reach it.
std::vector<MikkGroup> build_groups(std::vector<MikkTri>& tris) {
  std::vector<MikkGroup> groups;
  std::vector<uint32_t> stack;
  for (size_t f = 0; f < tris.size(); ++f)
    for (int i = 0; i < 3; ++i) {
      if (tris[f].any || tris[f].group[i] >= 0) continue;
      const int32_t g = int32_t(groups.size());
      groups.push_back({tris[f].v[i], tris[f].preserving, {uint32_t(f)}});
      MikkGroup& grp = groups.back();
      tris[f].group[i] = g;
      stack.clear();
      auto push_around = [&](const MikkTri& t, int k) {
        for (int32_t nb : {t.next[k], t.next[(k + 2) % 3]})
          if (nb >= 0) stack.push_back(uint32_t(nb));
      };
      push_around(tris[f], i);
      while (!stack.empty()) {
        MikkTri& t = tris[stack.back()];
        const uint32_t ti = stack.back();
        stack.pop_back();
        const int k = corner_of(t, grp.vertex);
        if (k < 0 || t.group[k] >= 0) continue;
        if (t.any && t.group[0] < 0 && t.group[1] < 0 && t.group[2] < 0)
          t.preserving = grp.preserving;
        if (t.preserving != grp.preserving) continue;
        t.group[k] = g;
        grp.tris.push_back(ti);
        push_around(t, k);
      }
    }
  return groups;
}

// Step 5: a group's tangent: the triangles' dP/du projected on the vertex normal, normalised,
// weighted by the corner angle (measured in the tangent plane) and summed; only triangles with
// usable uv contribute. With MikkTSpace's default angular threshold (180 degrees) a group splits
// only where two of its projected directions are exactly opposite.
glm::vec3 eval_tangent(const Mesh& m, const std::vector<MikkTri>& tris,
                       const std::vector<uint32_t>& members, uint32_t vertex, glm::vec3 n) {
  glm::vec3 sum(0.0f);
  for (uint32_t f : members) {
    const MikkTri& t = tris[f];
    if (t.any) continue;
    const int k = corner_of(t, vertex);
    const glm::vec3 p = m.positions[t.v[k]];
    const glm::vec3 e1 = project(m.positions[t.v[(k + 2) % 3]] - p, n);
    const glm::vec3 e2 = project(m.positions[t.v[(k + 1) % 3]] - p, n);
    const float angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0f, 1.0f));
    sum += angle * project(t.os, n);
  }
  return unit_or_as_is(sum);
}

void group_spaces(const Mesh& m, const std::vector<MikkTri>& tris,
                  const std::vector<MikkGroup>& groups, std::vector<CornerSpace>& space) {
  std::vector<uint32_t> members;
  std::vector<std::pair<std::vector<uint32_t>, glm::vec3>> done;
  std::vector<glm::vec3> os, ot;
  for (size_t g = 0; g < groups.size(); ++g) {
    const MikkGroup& grp = groups[g];
    const glm::vec3 n = glm::normalize(m.normals[grp.vertex]);
    os.clear();
    ot.clear();
    for (uint32_t f : grp.tris) {
      os.push_back(project(tris[f].os, n));
      ot.push_back(project(tris[f].ot, n));
    }
    done.clear();
    for (size_t i = 0; i < grp.tris.size(); ++i) {
      const uint32_t f = grp.tris[i];
      members.clear();
      for (size_t j = 0; j < grp.tris.size(); ++j) {
        const uint32_t t = grp.tris[j];
        if (tris[f].any || tris[t].any || f == t ||
            (glm::dot(os[i], os[j]) > -1.0f && glm::dot(ot[i], ot[j]) > -1.0f))
          members.push_back(t);
      }
      std::sort(members.begin(), members.end());
      glm::vec3 tangent;
      auto hit =
          std::find_if(done.begin(), done.end(), [&](const auto& d) { return d.first == members; });
      if (hit != done.end()) {
        tangent = hit->second;
      } else {
        tangent = eval_tangent(m, tris, members, grp.vertex, n);
        done.emplace_back(members, tangent);
      }
      const int k = corner_of(tris[f], grp.vertex);
      space[f * 3 + k] = {tangent, grp.preserving, true};
    }
  }
}

}  // namespace

void compute_tangents(Mesh& m) {
  const size_t nv = m.positions.size();
  if (m.normals.size() != nv) compute_normals(m);
  const bool has_uv = m.uvs.size() == nv;
  const size_t nt = m.indices.size() / 3;
  for (size_t c = 0; c < nt * 3; ++c)
    if (m.indices[c] >= nv) {  // not a valid mesh (the loaders refuse it): finite frames only
      m.tangents.resize(nv);
      for (size_t v = 0; v < nv; ++v)
        m.tangents[v] = glm::vec4(perpendicular(glm::normalize(m.normals[v])), 1.0f);
      return;
    }
  const std::vector<uint32_t> weld = weld_vertices(m, has_uv);
  auto uv = [&](uint32_t v) { return has_uv ? m.uvs[v] : glm::vec2(0.0f); };

  // Step 2: triangles with two equal positions are degenerate; the others, in order, carry the
  // per-triangle derivatives.
  std::vector<MikkTri> tris;
  std::vector<uint32_t> good_face;  // the face of each good triangle
  std::vector<uint32_t> degenerate;
  for (size_t f = 0; f < nt; ++f) {
    MikkTri t;
    for (int k = 0; k < 3; ++k) t.v[k] = weld[m.indices[f * 3 + k]];
    const glm::vec3 p0 = m.positions[t.v[0]], p1 = m.positions[t.v[1]], p2 = m.positions[t.v[2]];
    if (p0 == p1 || p0 == p2 || p1 == p2) {
      degenerate.push_back(uint32_t(f));
      continue;
    }
    const glm::vec2 t1 = uv(t.v[0]), d1 = uv(t.v[1]) - t1, d2 = uv(t.v[2]) - t1;
    const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    const float area = d1.x * d2.y - d1.y * d2.x;  // twice the signed uv area
    const glm::vec3 os = d2.y * e1 - d1.y * e2;    // dP/du times the area
    const glm::vec3 ot = d1.x * e2 - d2.x * e1;    // dP/dv times the area
    t.preserving = area > 0.0f;
    if (!tiny(area)) {
      const float sign = t.preserving ? 1.0f : -1.0f, los = glm::length(os), lot = glm::length(ot);
      if (!tiny(los)) t.os = os * (sign / los);
      if (!tiny(lot)) t.ot = ot * (sign / lot);
      t.any = tiny(los / std::fabs(area)) || tiny(lot / std::fabs(area));
    }
    tris.push_back(t);
    good_face.push_back(uint32_t(f));
  }
  link_neighbours(tris);
  std::vector<MikkGroup> groups = build_groups(tris);
  std::vector<CornerSpace> good_space(tris.size() * 3);
  group_spaces(m, tris, groups, good_space);

  std::vector<CornerSpace> space(nt * 3);
  for (size_t g = 0; g < tris.size(); ++g)
    for (int k = 0; k < 3; ++k) space[good_face[g] * 3 + k] = good_space[g * 3 + k];
  // Step 6: a degenerate triangle's corner copies the space of the first good corner at the same
  // welded vertex.
  if (!degenerate.empty()) {
    std::vector<int64_t> first(nv, -1);
    for (size_t g = tris.size(); g-- > 0;)
      for (int k = 2; k >= 0; --k) first[tris[g].v[k]] = int64_t(g * 3 + k);
    for (uint32_t f : degenerate)
      for (int k = 0; k < 3; ++k) {
        const int64_t src = first[weld[m.indices[f * 3 + k]]];
        if (src >= 0) space[f * 3 + k] = good_space[size_t(src)];
      }
  }

  // Per vertex: corners of one vertex with different spaces get their own copies (the first
  // space met keeps the vertex); a corner without a space gets a finite frame, w = +1.
  std::vector<glm::vec4> corner_tangent(nt * 3);
  for (size_t c = 0; c < nt * 3; ++c) {
    const CornerSpace& s = space[c];
    const glm::vec3 n = glm::normalize(m.normals[m.indices[c]]);
    const float w = !s.valid || s.preserving ? 1.0f : -1.0f;
    const bool usable = s.valid && glm::length(s.t - n * glm::dot(n, s.t)) > 1e-6f;
    corner_tangent[c] = glm::vec4(usable ? s.t : perpendicular(n), w);
  }
  m.tangents.assign(nv, glm::vec4(0.0f));
  std::vector<uint8_t> set(nv, 0);
  std::vector<std::vector<std::pair<glm::vec4, uint32_t>>> extra(nv);  // copies made so far
  for (size_t c = 0; c < nt * 3; ++c) {
    const uint32_t v = m.indices[c];
    const glm::vec4 t = corner_tangent[c];
    if (!set[v]) {
      set[v] = 1;
      m.tangents[v] = t;
      continue;
    }
    if (m.tangents[v] == t) continue;
    uint32_t copy = UINT32_MAX;
    for (const auto& [tt, idx] : extra[v])
      if (tt == t) copy = idx;
    if (copy == UINT32_MAX) {
      copy = duplicate_vertex(m, v);
      m.tangents[copy] = t;
      extra[v].emplace_back(t, copy);
    }
    m.indices[c] = copy;
  }
  for (size_t v = 0; v < nv; ++v)  // vertices no triangle uses
    if (!set[v]) m.tangents[v] = glm::vec4(perpendicular(glm::normalize(m.normals[v])), 1.0f);
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
