// Dual-depth relief textures as impostors (Policarpo, Oliveira and Comba, "Real-Time Relief
// Mapping on Arbitrary Polygonal Surfaces", I3D 2005, section 3.1): the built-in `impostor` scene
// (a sphere baked into front and back depth layers, drawn with relief_dual on one quad) covers
// the pixels the sphere mesh itself covers, within 2% of the sphere's pixels, from views up to 45
// degrees off the quad's axis. Without the back layer the same maps draw "skins": walls from the
// object's outline down to depth 1, which cover far more.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bake/dual_depth_maps.h"
#include "builtin/builtin.h"
#include "builtin/builtin_curved.h"
#include "tests/frames/coverage.h"

namespace relief {
namespace {

constexpr int kSize = 128;

test::Mask render_coverage(const Scene& scene, const std::string& technique) {
  return test::render_coverage(scene, technique, kSize, kSize);
}

Scene impostor() {
  Result<Scene> s = make_builtin_scene("impostor");
  EXPECT_TRUE(s.ok());
  return std::move(s).value();
}

// Camera 5 units from the origin, `theta` degrees off +z at azimuth `phi`.
void aim(Scene& s, float theta, float phi) {
  const float t = theta * 3.14159265f / 180.0f, p = phi * 3.14159265f / 180.0f;
  Camera& c = s.cameras.at(0);
  c.position = 5.0f * glm::vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  c.target = glm::vec3(0.0f);
  c.up = std::abs(std::sin(t) * std::sin(p)) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
}

TEST(Impostor, DualDepthSphereCoversTheSpheresPixelsUpTo45DegreesOffAxis) {
  const Scene imp = impostor();
  ASSERT_EQ(imp.materials.at(0).technique, "relief_dual");
  Scene mesh = imp;
  mesh.meshes.at(0) = parametric_mesh("sphere", sphere_surface(1.0f), 64, 32, {1.0f, 1.0f});
  double worst = 0.0;
  for (float theta : {0.0f, 20.0f, 45.0f})
    for (float phi : {0.0f, 60.0f, 135.0f, 270.0f}) {
      if (theta == 0.0f && phi != 0.0f) continue;
      Scene a = imp, b = mesh;
      aim(a, theta, phi);
      aim(b, theta, phi);
      const test::Mask ma = render_coverage(a, ""), mb = render_coverage(b, "flat");
      ASSERT_EQ(ma.on.size(), static_cast<size_t>(kSize) * kSize);
      ASSERT_EQ(mb.on.size(), ma.on.size());
      const int sphere = mb.count();
      ASSERT_GT(sphere, kSize * kSize / 10);
      const int differ = test::compare_masks(ma, mb).differing;
      const double ratio = static_cast<double>(differ) / sphere;
      worst = std::max(worst, ratio);
      std::printf("theta %2.0f phi %3.0f: %d of %d sphere pixels differ (%.4f)\n", theta, phi,
                  differ, sphere, ratio);
      EXPECT_LT(ratio, 0.02) << "theta " << theta << " phi " << phi;
    }
  RecordProperty("worst_coverage_difference", std::to_string(worst));
}

TEST(Impostor, WithoutTheBackLayerTheOutlineGrowsSkins) {
  Scene imp = impostor();
  aim(imp, 45.0f, 0.0f);
  Scene mesh = imp;
  mesh.meshes.at(0) = parametric_mesh("sphere", sphere_surface(1.0f), 64, 32, {1.0f, 1.0f});
  const int sphere = render_coverage(mesh, "flat").count();
  const int dual = render_coverage(imp, "").count();
  imp.materials.at(0).textures.erase("depth_back");
  const int front_only = render_coverage(imp, "").count();
  std::printf("45 deg: sphere %d, dual %d, front layer only %d pixels\n", sphere, dual, front_only);
  EXPECT_LT(std::abs(dual - sphere), sphere / 50);
  EXPECT_GT(front_only, sphere + sphere / 5);  // the skins: a wall below the far side's outline
}

TEST(Impostor, BakedLayersOfASphere) {
  const Mesh s = parametric_mesh("sphere", sphere_surface(1.0f), 64, 32, {1.0f, 1.0f});
  const DualDepthMaps m = bake_dual_depth(s.positions, s.normals, s.indices, 64, 1.0f, 2);
  const DualDepthMaps m1 = bake_dual_depth(s.positions, s.normals, s.indices, 64, 1.0f, 1);
  EXPECT_EQ(m.front, m1.front);  // any thread count
  EXPECT_EQ(m.back, m1.back);
  EXPECT_NEAR(m.depth_scale(), 1.0f, 1e-3f);
  // the centre texel: the top (depth 0) and the bottom (depth 1) of the sphere
  const size_t c = 32 * 64 + 32;
  EXPECT_NEAR(m.front[c], 0.0f, 0.01f);
  EXPECT_NEAR(m.back[c], 1.0f, 0.01f);
  EXPECT_GT(m.front_normal[c].z, 0.99f);
  EXPECT_LT(m.back_normal[c].z, -0.99f);
  // a corner is outside the sphere: absent (front 1, back 0)
  EXPECT_EQ(m.front[0], 1.0f);
  EXPECT_EQ(m.back[0], 0.0f);
  // everywhere: front <= back where present, and the layers are symmetric about the mid-plane
  int present = 0;
  for (size_t i = 0; i < m.front.size(); ++i) {
    ASSERT_TRUE(std::isfinite(m.front[i]) && std::isfinite(m.back[i]));
    if (m.front[i] > m.back[i]) continue;
    ++present;
    EXPECT_NEAR(m.front[i] + m.back[i], 1.0f, 0.01f) << i;
  }
  EXPECT_GT(present, 64 * 64 * 3 / 4 - 64 * 4);  // pi / 4 of the square, less the rim
}

// Without a back map relief_dual's back layer is the constant 1, which costs no texture read:
// on `plane` (no depth_back) it runs relief's search with the same parameters, so it must count
// the same texture fetches, search steps and shadow steps as `relief` (counting the constant as
// a read, it reported 2,424,890 fetches here against relief's 1,261,597).
TEST(DualDepth, ConstantBackLayerCountsNoFetches) {
  Result<Scene> scene = make_builtin_scene("plane");
  ASSERT_TRUE(scene.ok());
  ASSERT_EQ(scene->materials.at(0).textures.count("depth_back"), 0u);
  WorkCounters counted[2];
  const char* techniques[2] = {"relief", "relief_dual"};
  for (int i = 0; i < 2; ++i) {
    const RenderOptions opt = test::cpu_options(256, 192, techniques[i]);
    Result<Plan> plan = make_plan(*scene, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(*scene, *plan);
    ASSERT_TRUE(r.ok());
    for (const PassStats& p : r->passes)
      if (p.kind == PassPlan::Kind::kMain) counted[i] += p.raster.work;
  }
  EXPECT_GT(counted[0].texture_fetches, counted[0].fragments);
  EXPECT_EQ(counted[1].fragments, counted[0].fragments);
  EXPECT_EQ(counted[1].texture_fetches, counted[0].texture_fetches);
  EXPECT_EQ(counted[1].search_steps, counted[0].search_steps);
  EXPECT_EQ(counted[1].shadow_steps, counted[0].shadow_steps);
}

}  // namespace
}  // namespace relief
