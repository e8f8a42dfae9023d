// compute_tangents (scene/mesh_prep.h) against the reference MikkTSpace implementation: per-corner
// tangents and signs within 1e-4 on a sphere band with a pole (degenerate triangles), a mirrored
// u, a welded wrap and a uv seam, and on a sheet with zero-uv-area, repeated-position, mirrored
// and isolated triangles. The expected numbers and where they came from:
// tests/scene/mikktspace_test_data.h.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "scene/mesh_prep.h"
#include "tests/scene/mikktspace_test_data.h"

namespace relief {
namespace {

namespace data = mikktspace_data;

template <size_t NV, size_t NI>
Mesh mesh_of(const float (&v)[NV], const uint32_t (&idx)[NI]) {
  Mesh m;
  for (size_t k = 0; k + 7 < NV; k += 8) {
    m.positions.push_back({v[k], v[k + 1], v[k + 2]});
    m.normals.push_back({v[k + 3], v[k + 4], v[k + 5]});
    m.uvs.push_back({v[k + 6], v[k + 7]});
  }
  m.indices.assign(idx, idx + NI);
  return m;
}

// Compares every corner (through the index buffer, whose triangle order compute_tangents keeps)
// with the reference. Where the reference has no tangent space at all (its untouched default,
// (1, 0, 0) with sign -1: a triangle no group reached) ours is documented as a finite frame:
// unit, perpendicular to the normal, w = +1. Returns the number of such corners.
template <size_t NV, size_t NI, size_t NE>
int expect_reference(const std::string& name, const float (&v)[NV], const uint32_t (&idx)[NI],
                     const float (&expected)[NE]) {
  static_assert(NE == NI * 4);
  Mesh m = mesh_of(v, idx);
  const size_t nv = m.positions.size();
  const Mesh before = m;
  compute_tangents(m);
  EXPECT_EQ(m.indices.size(), before.indices.size()) << name;
  EXPECT_EQ(m.tangents.size(), m.positions.size()) << name;
  EXPECT_EQ(m.uvs.size(), m.positions.size()) << name;
  int none = 0;
  float worst = 0.0f;
  for (size_t c = 0; c < NI; ++c) {
    const uint32_t k = m.indices[c], k0 = before.indices[c];
    // a split vertex is a copy of the original: same position, normal and uv
    EXPECT_EQ(m.positions[k], before.positions[k0]) << name << " corner " << c;
    EXPECT_EQ(m.uvs[k], before.uvs[k0]) << name << " corner " << c;
    if (k != k0) {
      EXPECT_GE(k, nv) << name << " corner " << c;
    }
    const glm::vec4 t = m.tangents[k];
    const float* e = &expected[c * 4];
    const glm::vec3 n = glm::normalize(m.normals[k]);
    if (e[0] == 1.0f && e[1] == 0.0f && e[2] == 0.0f && e[3] == -1.0f) {
      ++none;
      EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-5f) << name << " corner " << c;
      EXPECT_NEAR(glm::dot(glm::vec3(t), n), 0.0f, 1e-5f) << name << " corner " << c;
      EXPECT_EQ(t.w, 1.0f) << name << " corner " << c;
      continue;
    }
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(t[i], e[i], 1e-4f) << name << " face " << c / 3 << " corner " << c % 3;
      worst = std::max(worst, std::fabs(t[i] - e[i]));
    }
    EXPECT_EQ(t.w, e[3]) << name << " face " << c / 3 << " corner " << c % 3;
  }
  // corners the reference gives different spaces never share a vertex
  for (size_t a = 0; a < NI; ++a)
    for (size_t b = a + 1; b < NI; ++b)
      if (m.indices[a] == m.indices[b]) {
        bool same = true;
        for (int i = 0; i < 4; ++i) same = same && expected[a * 4 + i] == expected[b * 4 + i];
        EXPECT_TRUE(same) << name << " corners " << a << " and " << b << " share vertex "
                          << m.indices[a];
      }
  ::testing::Test::RecordProperty(name + "_worst", std::to_string(worst));
  return none;
}

TEST(MikkTSpace, MatchesTheReferenceOnASphereBandWithPoleMirrorAndSeam) {
  const int none = expect_reference("sphere_band", data::k_sphere_band_vertices,
                                    data::k_sphere_band_indices, data::k_sphere_band_expected);
  EXPECT_LE(none, 2);  // only where the reference itself has nothing
}

TEST(MikkTSpace, MatchesTheReferenceOnDegenerateAndMirroredTriangles) {
  const int none =
      expect_reference("sheet_degenerate", data::k_sheet_degenerate_vertices,
                       data::k_sheet_degenerate_indices, data::k_sheet_degenerate_expected);
  EXPECT_EQ(none, 6);  // the zero-uv triangle no group reaches and the isolated one
}

TEST(MikkTSpace, MirroredVertexIsSplitAndEachSideKeepsItsSign) {
  // one vertex shared by a right-handed and a left-handed triangle (the uv folds through it)
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.uvs = {{0.5f, 0.5f}, {0.9f, 0.5f}, {0.5f, 0.9f}, {0.9f, 0.6f}};
  m.indices = {0, 1, 2, 0, 2, 3};
  compute_tangents(m);
  ASSERT_EQ(m.positions.size(), 6u);  // vertices 0 and 2 split
  EXPECT_EQ(m.indices[0], 0u);
  EXPECT_EQ(m.indices[3], 4u);
  EXPECT_EQ(m.tangents[0].w, 1.0f);
  EXPECT_EQ(m.tangents[4].w, -1.0f);
  EXPECT_NEAR(m.tangents[0].x, 1.0f, 1e-6f);
}

TEST(MikkTSpace, MeshWithoutUvGetsFiniteFramesAndNoSplit) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.2f}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.indices = {0, 1, 2, 2, 1, 3, 0, 0, 1};  // the last triangle is degenerate
  compute_tangents(m);
  ASSERT_EQ(m.positions.size(), 4u);
  for (const glm::vec4& t : m.tangents) {
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);
    EXPECT_EQ(t.w, 1.0f);
  }
}

}  // namespace
}  // namespace relief
