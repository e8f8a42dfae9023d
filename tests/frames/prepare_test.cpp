// render/prepare.cpp hands the plugins world-space varyings. The per-vertex quadric is fitted in
// object units, so a scaled instance must see the curvature of the scaled surface: an instance
// of the `sphere` mesh scaled by s (and rotated) gets the coefficients the fit gives for a mesh
// whose vertices were scaled by s, i.e. 1/s of the unscaled ones (a = b = 1 / (2r)).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "builtin/builtin.h"
#include "render/render.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

std::vector<glm::vec2> prepared_quadrics(const Scene& scene) {
  const std::vector<PreparedDraw> draws = prepare_draws(scene, glm::mat4(1.0f));
  std::vector<glm::vec2> q;
  for (size_t v = 0; v * varying::kCount < draws.at(0).varyings.size(); ++v) {
    const float* o = &draws[0].varyings[v * varying::kCount];
    q.emplace_back(o[varying::kQuadric], o[varying::kQuadric + 1]);
  }
  return q;
}

TEST(Prepare, ScaledInstanceSeesTheQuadricOfTheScaledMesh) {
  Result<Scene> base = make_builtin_scene("sphere");
  ASSERT_TRUE(base.ok());
  ASSERT_EQ(base->instances.size(), 1u);
  const Mesh& mesh = base->meshes.at(base->instances[0].mesh);
  ASSERT_EQ(mesh.quadric.size(), mesh.positions.size());
  const std::vector<glm::vec2> unscaled = prepared_quadrics(*base);
  // identity: the fitted coefficients as they are
  for (size_t v = 0; v < unscaled.size(); ++v) ASSERT_EQ(unscaled[v], mesh.quadric[v]) << v;

  for (float s : {0.25f, 3.0f}) {
    Scene instanced = *base;  // the same mesh, scaled and rotated by the instance
    instanced.instances[0].transform =
        glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(s)), 0.7f, glm::vec3(0.3f, 1.0f, 0.2f));
    Scene refit = *base;  // the mesh itself scaled, fitted again
    Mesh& m = refit.meshes[refit.instances[0].mesh];
    for (glm::vec3& p : m.positions) p *= s;
    m.quadric.clear();
    m.tile_scale.clear();
    prepare_mesh(m);
    const std::vector<glm::vec2> a = prepared_quadrics(instanced), b = prepared_quadrics(refit);
    ASSERT_EQ(a.size(), b.size());
    int curved = 0;
    for (size_t v = 0; v < a.size(); ++v) {
      const float tol = 1e-4f * (std::abs(b[v].x) + std::abs(b[v].y)) + 1e-6f;
      EXPECT_NEAR(a[v].x, b[v].x, tol) << "scale " << s << " vertex " << v;
      EXPECT_NEAR(a[v].y, b[v].y, tol) << "scale " << s << " vertex " << v;
      EXPECT_NEAR(a[v].x * s, unscaled[v].x, tol * s) << "scale " << s << " vertex " << v;
      curved += std::abs(unscaled[v].x) > 0.1f;
    }
    EXPECT_GT(curved, static_cast<int>(a.size()) / 2);  // the sphere is curved almost everywhere
  }
}

}  // namespace
}  // namespace relief
