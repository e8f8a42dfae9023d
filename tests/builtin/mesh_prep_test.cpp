// Tests for scene/mesh_prep: tangent frames (MikkTSpace-style, mirrored seams, degenerate uv) and
// the per-vertex quadric fit of Oliveira and Policarpo 2005, equation 2, on surfaces of known
// curvature (builtin/builtin_curved.h).
#include "scene/mesh_prep.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "builtin/builtin_curved.h"

namespace relief {
namespace {

constexpr float kPi = 3.14159265358979f;

// The vertex's orthonormal frame as the kernels rebuild it.
void frame_of(const Mesh& m, size_t k, glm::vec3& t, glm::vec3& b, glm::vec3& n) {
  n = glm::normalize(m.normals[k]);
  const glm::vec3 t4(m.tangents[k]);
  t = glm::normalize(t4 - n * glm::dot(n, t4));
  b = glm::cross(n, t) * m.tangents[k].w;
}

float angle_deg(glm::vec3 a, glm::vec3 b) {
  const float c = glm::dot(glm::normalize(a), glm::normalize(b));
  return std::acos(std::clamp(c, -1.0f, 1.0f)) * 180.0f / kPi;
}

// Expects every vertex's (a, b) within 1% of `e` (relative to the larger of |a|, |b|), except
// the `skip_rows` rows of the grid next to its first and last (the rings next to a sphere's
// poles span 1/40 of their height across u, so the float rounding of the positions, 6e-8, is
// about 2% of the x^2 term there: no fit of the mesh as stored can do better).
void expect_fit(const Mesh& m, glm::vec2 e, int row = 1, int skip_rows = 0) {
  const float scale = std::max(std::fabs(e.x), std::fabs(e.y));
  const size_t rows = m.positions.size() / row;
  for (size_t k = 0; k < m.positions.size(); ++k) {
    const size_t j = k / row;
    if (skip_rows > 0 && j >= 1 && (j <= size_t(skip_rows) || j + 1 + skip_rows >= rows)) continue;
    ASSERT_NEAR(m.quadric[k].x, e.x, 0.01f * scale) << "vertex " << k;
    ASSERT_NEAR(m.quadric[k].y, e.y, 0.01f * scale) << "vertex " << k;
  }
}

TEST(MeshPrep, QuadricOfSphereIsHalfTheCurvature) {
  for (float r : {0.5f, 2.0f}) {
    const Mesh m = parametric_mesh("s", sphere_surface(r), 256, 128, {4, 2});
    expect_fit(m, glm::vec2(0.5f / r), 257, 1);
  }
}

TEST(MeshPrep, QuadricOfCylinderCurvesAroundOnly) {
  const Mesh m = parametric_mesh("c", cylinder_surface(0.7f, 2.0f), 256, 64, {3, 2});
  expect_fit(m, glm::vec2(0.5f / 0.7f, 0.0f));
}

TEST(MeshPrep, QuadricOfTorusHasTheSaddleOnItsInnerHalf) {
  const float R = 1.0f, r = 0.4f;
  const int ns = 384, nt = 192;
  const Mesh m = parametric_mesh("t", torus_surface(R, r), ns, nt, {1, 1});
  int saddle = 0;
  for (size_t k = 0; k < m.positions.size(); ++k) {
    const float t = static_cast<float>(k / (ns + 1)) / nt, beta = 2.0f * kPi * t;
    const glm::vec2 e(std::cos(beta) / (2.0f * (R + r * std::cos(beta))), 0.5f / r);
    ASSERT_NEAR(m.quadric[k].x, e.x, 0.01f * e.y) << "vertex " << k;
    ASSERT_NEAR(m.quadric[k].y, e.y, 0.01f * e.y) << "vertex " << k;
    if (m.quadric[k].x < 0.0f) ++saddle;
  }
  EXPECT_GT(saddle, static_cast<int>(m.positions.size()) / 3);  // negative Gaussian curvature
}

// z = -(c1 x^2 + c2 y^2) over a fine grid: at the apex (a, b) = (c1, c2) (depth along -N). No
// dP/ds (ds = 0): the tangents come from prepare_mesh, whose frame the quadric is fitted in.
Surface height_field(float c1, float c2) {
  return [c1, c2](float s, float t) {
    const float x = (s - 0.5f) * 0.2f, y = (t - 0.5f) * 0.2f;
    const glm::vec3 n = glm::normalize(glm::vec3(2.0f * c1 * x, 2.0f * c2 * y, 1.0f));
    return SurfacePoint{{x, y, -(c1 * x * x + c2 * y * y)}, n, glm::vec3(0.0f)};
  };
}

TEST(MeshPrep, QuadricOfParaboloidsAndSaddlesAtTheApex) {
  for (glm::vec2 c : {glm::vec2(1.0f, 1.0f), glm::vec2(2.0f, 0.5f), glm::vec2(1.5f, -1.5f),
                      glm::vec2(-0.8f, 0.3f)}) {
    const Mesh m = parametric_mesh("p", height_field(c.x, c.y), 64, 64, {1, 1});
    const size_t apex = 32 * 65 + 32;
    ASSERT_NEAR(m.positions[apex].x, 0.0f, 1e-6f);
    const float scale = std::max(std::fabs(c.x), std::fabs(c.y));
    EXPECT_NEAR(m.quadric[apex].x, c.x, 0.01f * scale) << c.x << " " << c.y;
    EXPECT_NEAR(m.quadric[apex].y, c.y, 0.01f * scale) << c.x << " " << c.y;
  }
}

TEST(MeshPrep, DegenerateRingsGiveFiniteDocumentedValues) {
  const glm::vec3 t(1, 0, 0), b(0, 1, 0), n(0, 0, 1);
  // no neighbour, coincident neighbours, NaN: (0, 0)
  EXPECT_EQ(fit_quadric(nullptr, 0, t, b, n), glm::vec2(0.0f));
  const glm::vec3 same[3] = {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)};
  EXPECT_EQ(fit_quadric(same, 3, t, b, n), glm::vec2(0.0f));
  const glm::vec3 nan[2] = {glm::vec3(NAN, 0, 0), glm::vec3(0, 1, 0)};
  EXPECT_EQ(fit_quadric(nan, 2, t, b, n), glm::vec2(0.0f));
  // flat ring: (0, 0)
  const glm::vec3 flat[4] = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  const glm::vec2 f = fit_quadric(flat, 4, t, b, n);
  EXPECT_EQ(f, glm::vec2(0.0f));
  // neighbours along one line (under-determined): the isotropic fit, exact along the line
  const glm::vec3 line[2] = {{1, 0, -0.3f}, {-2, 0, -1.2f}};
  const glm::vec2 l = fit_quadric(line, 2, t, b, n);
  EXPECT_NEAR(l.x, 0.3f, 1e-5f);
  EXPECT_EQ(l.x, l.y);
  // planar-symmetric ring on the diagonals (x^2 = y^2 everywhere): isotropic, a = b
  const float z = -0.25f * 2.0f;  // z = 0.25 (x^2 + y^2) below the plane
  const glm::vec3 diag[4] = {{1, 1, z}, {-1, 1, z}, {-1, -1, z}, {1, -1, z}};
  const glm::vec2 d = fit_quadric(diag, 4, t, b, n);
  EXPECT_NEAR(d.x, 0.25f, 1e-6f);
  EXPECT_EQ(d.x, d.y);
  // a huge and a tiny ring stay finite and scale as 1 / length
  for (float s : {1e-15f, 1e15f}) {
    const glm::vec3 ring[4] = {{s, 0, -s}, {-s, 0, -s}, {0, s, -s}, {0, -s, -s}};
    const glm::vec2 q = fit_quadric(ring, 4, t, b, n);
    ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y)) << s;
    EXPECT_NEAR(q.x * s, 1.0f, 1e-4f) << s;
  }
}

TEST(MeshPrep, TangentFramesWithinOneDegreeOnSphereAndTorus) {
  struct Case {
    Surface surface;
    int ns, nt;
  };
  for (const Case& c :
       {Case{sphere_surface(1.0f), 256, 128}, Case{torus_surface(1.0f, 0.4f), 256, 128}}) {
    Mesh m = parametric_mesh("m", c.surface, c.ns, c.nt, {4, 2});
    m.normals.clear();  // made by compute_normals: the whole preparation is under test
    m.tangents.clear();
    prepare_mesh(m);
    ASSERT_EQ(m.positions.size(), size_t(c.ns + 1) * (c.nt + 1));  // nothing mirrored, no split
    float worst = 0.0f;
    for (int j = 1; j < c.nt; ++j)  // the sphere's poles have no analytic frame
      for (int i = 0; i <= c.ns; ++i) {
        const size_t k = size_t(j) * (c.ns + 1) + i;
        const float s = static_cast<float>(i) / c.ns, tt = static_cast<float>(j) / c.nt;
        const float h = 1e-3f;
        const glm::vec3 dpds = c.surface(s + h, tt).p - c.surface(s - h, tt).p;
        const glm::vec3 dpdt = c.surface(s, tt + h).p - c.surface(s, tt - h).p;
        glm::vec3 t, b, n;
        frame_of(m, k, t, b, n);
        EXPECT_EQ(m.tangents[k].w, 1.0f);
        worst = std::max(
            {worst, angle_deg(t, dpds), angle_deg(b, dpdt), angle_deg(n, c.surface(s, tt).n)});
      }
    EXPECT_LT(worst, 1.0f);
  }
}

TEST(MeshPrep, MirroredSeamSplitsTheVertexAndFlipsTheSign) {
  // two quads side by side in z = 0 facing +z; u runs 0 -> 1 -> 0 across them (mirrored at x = 1)
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
  m.normals.assign(6, glm::vec3(0, 0, 1));
  m.uvs = {{0, 0}, {1, 0}, {0, 0}, {0, 1}, {1, 1}, {0, 1}};
  m.indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  prepare_mesh(m);
  ASSERT_EQ(m.positions.size(), 8u);  // the two seam vertices split
  for (size_t c = 0; c < m.indices.size(); ++c) {
    const glm::vec4 t = m.tangents[m.indices[c]];
    const bool right = c >= 6;  // the mirrored quad
    EXPECT_EQ(t.w, right ? -1.0f : 1.0f) << c;
    EXPECT_NEAR(t.x, right ? -1.0f : 1.0f, 1e-6f) << c;
    // B = w cross(N, T) is +y on both sides: v runs up on both
    glm::vec3 tt, b, n;
    frame_of(m, m.indices[c], tt, b, n);
    EXPECT_NEAR(b.y, 1.0f, 1e-6f) << c;
  }
  EXPECT_EQ(m.quadric.size(), m.positions.size());
  EXPECT_EQ(m.tile_scale.size(), m.positions.size());
}

TEST(MeshPrep, ZeroAreaUvGivesAFiniteFrame) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals.assign(3, glm::vec3(0, 0, 1));
  m.uvs.assign(3, glm::vec2(0.5f));
  m.indices = {0, 1, 2};
  prepare_mesh(m);
  for (const glm::vec4& t : m.tangents) {
    EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
    EXPECT_NEAR(t.z, 0.0f, 1e-6f);  // perpendicular to N
    EXPECT_EQ(std::fabs(t.w), 1.0f);
  }
  for (const glm::vec2& s : m.tile_scale) EXPECT_EQ(s, glm::vec2(1.0f));
  for (const glm::vec2& q : m.quadric) EXPECT_EQ(q, glm::vec2(0.0f));  // a flat ring
}

}  // namespace
}  // namespace relief
