// Scene limits (docs/errors.md, "Limits"): a frame that would draw more than kMaxSceneTriangles
// triangles is refused by make_plan with one line naming the scene, the count and the limit;
// one at the limit is planned.
#include <gtest/gtest.h>

#include <string>

#include "builtin/builtin.h"
#include "render/render.h"

namespace relief {
namespace {

// The plane scene plus `copies` instances of a mesh of `triangles` triangles (all degenerate at
// the origin: the limit counts what is drawn, whatever it covers).
Scene with_extra_triangles(uint64_t triangles, int copies) {
  Result<Scene> s = make_builtin_scene("plane");
  CHECK(s.ok());
  Scene scene = std::move(*s);
  Mesh m;
  m.positions.assign(3, glm::vec3(0.0f));
  m.indices.assign(triangles * 3, 0u);
  scene.meshes.push_back(std::move(m));
  for (int i = 0; i < copies; ++i)
    scene.instances.push_back({static_cast<int>(scene.meshes.size()) - 1, 0, glm::mat4(1.0f)});
  return scene;
}

uint64_t scene_triangles(const Scene& s) {
  uint64_t n = 0;
  for (const Instance& i : s.instances) n += s.meshes[i.mesh].indices.size() / 3;
  return n;
}

TEST(Limits, MoreTrianglesThanTheLimitAreRefusedByThePlan) {
  const uint64_t chunk = kMaxSceneTriangles / 4;
  Scene over = with_extra_triangles(chunk, 5);  // instances count: 5 x a quarter of the limit
  ASSERT_GT(scene_triangles(over), kMaxSceneTriangles);
  RenderOptions opt;
  Result<Plan> p = make_plan(over, opt);
  ASSERT_FALSE(p.ok());
  const std::string& m = p.status().message();
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_NE(m.find("'plane'"), std::string::npos) << m;
  EXPECT_NE(m.find(std::to_string(scene_triangles(over))), std::string::npos) << m;
  EXPECT_NE(m.find(std::to_string(kMaxSceneTriangles)), std::string::npos) << m;
  EXPECT_EQ(p.status().exit_code(), 1);
}

TEST(Limits, TrianglesUpToTheLimitArePlanned) {
  Result<Scene> base = make_builtin_scene("plane");
  ASSERT_TRUE(base.ok());
  const uint64_t room = kMaxSceneTriangles - scene_triangles(*base);
  Scene at = with_extra_triangles(room, 1);
  ASSERT_EQ(scene_triangles(at), kMaxSceneTriangles);
  RenderOptions opt;
  EXPECT_TRUE(make_plan(at, opt).ok());
}

}  // namespace
}  // namespace relief
