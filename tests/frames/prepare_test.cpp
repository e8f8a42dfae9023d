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
  const std::vector<PreparedInstance> draws = prepare_instances(scene);
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

// A view's draw is the instance's world positions through the view, bit for bit what transforming
// the mesh's positions by model then view_proj gives, and it borrows the prepared varyings.
TEST(Prepare, ViewDrawTransformsTheSharedWorldPositions) {
  Result<Scene> scene = make_builtin_scene("sphere");
  ASSERT_TRUE(scene.ok());
  scene->instances[0].transform =
      glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, -1.0f, 2.0f)), 0.4f,
                  glm::vec3(0.0f, 1.0f, 0.0f));
  const std::vector<PreparedInstance> instances = prepare_instances(*scene);
  ASSERT_EQ(instances.size(), 1u);
  const Mesh& mesh = scene->meshes[scene->instances[0].mesh];
  const glm::mat4 view_proj = glm::perspective(0.8f, 1.5f, 0.1f, 50.0f) *
                              glm::lookAt(glm::vec3(1, 2, 5), glm::vec3(0), glm::vec3(0, 1, 0));
  const PreparedDraw draw = view_draw(instances[0], view_proj);
  ASSERT_EQ(draw.clip.size(), mesh.positions.size());
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec4 expected =
        view_proj * (scene->instances[0].transform * glm::vec4(mesh.positions[v], 1.0f));
    ASSERT_EQ(draw.clip[v], expected) << v;
  }
  EXPECT_EQ(draw.varyings.data(), instances[0].varyings.data());
  EXPECT_EQ(draw.varyings.size(), instances[0].varyings.size());
}

int g_created = 0, g_destroyed = 0;
void* count_create(const MaterialUniforms&) {
  ++g_created;
  return new int(7);
}
void count_destroy(void* s) {
  ++g_destroyed;
  delete static_cast<int*>(s);
}

// Plugin state is made once per frame per material that asks for it, by the prepare stage, and
// freed with the prepared frame.
TEST(Prepare, PluginStateIsMadeOncePerMaterialAndFreed) {
  Result<Scene> scene = make_builtin_scene("sphere");
  ASSERT_TRUE(scene.ok());
  PluginDescriptor with_state{};
  with_state.name = "with_state";
  with_state.create_state = &count_create;
  with_state.destroy_state = &count_destroy;
  PluginDescriptor without_state{};
  without_state.name = "without_state";
  Plan plan;
  plan.materials.resize(3);
  plan.materials[0].plugin = &with_state;
  plan.materials[1].plugin = &without_state;
  plan.materials[2].plugin = &with_state;
  g_created = g_destroyed = 0;
  {
    const PreparedFrame prep = prepare_frame(*scene, plan);
    EXPECT_EQ(g_created, 2);
    ASSERT_EQ(prep.states.size(), 3u);
    ASSERT_NE(prep.state(0), nullptr);
    EXPECT_EQ(*static_cast<const int*>(prep.state(0)), 7);
    EXPECT_EQ(prep.state(1), nullptr);
    EXPECT_NE(prep.state(2), prep.state(0));
    EXPECT_EQ(prep.instances.size(), scene->instances.size());
    EXPECT_EQ(g_destroyed, 0);
  }
  EXPECT_EQ(g_destroyed, 2);
}

RenderResult cpu_frame(Backend& backend, const Scene& scene) {
  RenderOptions opt;
  opt.width = 96;
  opt.height = 72;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = backend.render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? std::move(*r) : RenderResult{};
}

bool same_colour(const RenderResult& a, const RenderResult& b) {
  return a.framebuffer.color.pixels == b.framebuffer.color.pixels;
}

// The CPU backend keeps each frame's prepared instances for the next (PreparedCache): an unchanged
// instance is found by instance_key instead of prepared, and the frame's bits do not change.
TEST(Prepare, CpuBackendReusesUnchangedInstancesAndRendersTheSameBits) {
  Result<Scene> room = make_builtin_scene("room");
  ASSERT_TRUE(room.ok());
  const int n = static_cast<int>(room->instances.size());
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  const RenderResult first = cpu_frame(*cpu, *room);
  EXPECT_EQ(first.geometry_prepared, n);
  EXPECT_EQ(first.geometry_reused, 0);
  const RenderResult second = cpu_frame(*cpu, *room);
  EXPECT_EQ(second.geometry_prepared, 0);
  EXPECT_EQ(second.geometry_reused, n);
  EXPECT_TRUE(same_colour(first, second));
  // A moved instance is prepared again, alone, and shows.
  room->instances.back().transform[3][1] += 0.05f;
  const RenderResult moved = cpu_frame(*cpu, *room);
  EXPECT_EQ(moved.geometry_prepared, 1);
  EXPECT_EQ(moved.geometry_reused, n - 1);
  EXPECT_FALSE(same_colour(first, moved));
  std::unique_ptr<Backend> fresh = make_cpu_backend({.threads = 2});
  EXPECT_TRUE(same_colour(moved, cpu_frame(*fresh, *room)));
}

// A kept instance found for another Scene object with the same content reads that scene's
// indices, not the first one's (destroyed here: ASan would see a stale pointer).
TEST(Prepare, KeptInstancesReadTheCurrentScenesIndices) {
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 1});
  RenderResult a;
  {
    Result<Scene> first = make_builtin_scene("teatime");
    ASSERT_TRUE(first.ok());
    a = cpu_frame(*cpu, *first);
  }
  Result<Scene> second = make_builtin_scene("teatime");
  ASSERT_TRUE(second.ok());
  const RenderResult b = cpu_frame(*cpu, *second);
  EXPECT_EQ(b.geometry_prepared, 0);
  EXPECT_TRUE(same_colour(a, b));
}

}  // namespace
}  // namespace relief
