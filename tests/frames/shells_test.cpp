// The `shells` technique (plugins/shells.cpp): the prepare stage's layer geometry
// (render/prepare.cpp), the planner's alpha test, and rendered frames that converge to steep
// parallax mapping with many planes as the layer count grows and stay finite in corner cases.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "builtin/builtin.h"
#include "render/compare.h"
#include "render/render.h"
#include "tests/frames/cpu_frame.h"

namespace relief {
namespace {

Scene plane_scene() {
  Result<Scene> s = make_builtin_scene("plane");
  EXPECT_TRUE(s.ok());
  return std::move(s).value();
}

RenderOptions shells_options(int layers, int width = 160, int height = 90) {
  RenderOptions opt = test::cpu_options(width, height, "shells");
  opt.params["layers"] = std::to_string(layers);
  return opt;
}

// Every shell's vertices, indices and order: copy k is shell i = N-1-k, (1 - i/N) relief heights
// below the polygon along -N, tagged (i, N).
TEST(Shells, PrepareMakesOffsetCopiesOutermostFirst) {
  const Scene scene = plane_scene();
  const int n = 4;
  Result<Plan> plan = make_plan(scene, shells_options(n));
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  const BoundMaterial& b = plan->materials.at(0);
  EXPECT_EQ(b.uniforms.alpha_mode, AlphaMode::kMask);
  EXPECT_EQ(b.uniforms.alpha_cutoff, 0.5f);
  const MaterialLayers layers = material_layers(b);
  ASSERT_EQ(layers.layers, n);
  const PreparedFrame frame = prepare_frame(scene, *plan);
  const PreparedFrame plain_frame = prepare_frame(scene, *make_plan(scene, shells_options(1)));
  const std::vector<PreparedInstance> plain = prepare_instances(scene);  // no layers
  const PreparedInstance& d = frame.instances.at(0);
  const Mesh& mesh = scene.meshes.at(scene.instances[0].mesh);
  const size_t nv = mesh.positions.size(), ni = mesh.indices.size();
  ASSERT_EQ(d.layers, n);
  ASSERT_EQ(d.world.size(), nv * n);
  ASSERT_EQ(d.varyings.size(), nv * n * d.num_varyings);
  ASSERT_EQ(d.indices, d.layer_indices.get());
  ASSERT_EQ(d.indices->size(), ni * n);
  EXPECT_EQ(plain.at(0).layers, 0);
  EXPECT_EQ(plain.at(0).indices, &mesh.indices);
  EXPECT_EQ(plain_frame.instances.at(0).layers, 1);
  for (int k = 0; k < n; ++k) {
    const int i = n - 1 - k;
    for (size_t j = 0; j < ni; ++j)
      ASSERT_EQ((*d.indices)[k * ni + j], mesh.indices[j] + k * nv) << k;
    for (size_t v = 0; v < nv; ++v) {
      const float* src = &plain[0].varyings[v * plain[0].num_varyings];
      const float* o = &d.varyings[(k * nv + v) * d.num_varyings];
      const float h = static_cast<float>(i) / n;
      const float height =
          layers.depth_scale * (src[varying::kTileScale] + src[varying::kTileScale + 1]) * 0.5f;
      ASSERT_GT(height, 0.0f);
      // the plane faces +y
      const glm::vec4 expect = plain[0].world[v] - glm::vec4(0, (1.0f - h) * height, 0, 0);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(d.world[k * nv + v][c], expect[c], 1e-6f) << k << " " << v;
        EXPECT_EQ(o[varying::kPosition + c], d.world[k * nv + v][c]);
      }
      EXPECT_EQ(o[varying::kQuadric], static_cast<float>(i));
      EXPECT_EQ(o[varying::kQuadric + 1], static_cast<float>(n));
      EXPECT_EQ(o[varying::kUv], src[varying::kUv]);
    }
  }
  // the first copy is the outermost: the polygon minus 1/N of the height
  EXPECT_GT(d.world[0].y, d.world[(n - 1) * nv].y);
  bool explained = false;
  for (const std::string& r : b.reasons) explained |= r.rfind("layers: 4 shells", 0) == 0;
  EXPECT_TRUE(explained) << plan->explain();
}

bool finite_frame(const Framebuffer& f) {
  for (const glm::vec4& p : f.color.pixels)
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(p[c])) return false;
  for (float d : f.depth.values)
    if (!std::isfinite(d)) return false;
  return true;
}

int covered(const Framebuffer& f) {
  int n = 0;
  for (float d : f.depth.values) n += d > 0.0f;
  return n;
}

// Shells converge to the relief the steep parallax search with 256 planes finds on the same
// field and view (no self-shadow, no shadow maps: their models differ on purpose).
TEST(Shells, ConvergesToSteepParallaxAsLayersGrow) {
  const Scene scene = plane_scene();
  RenderOptions ref_opt = test::cpu_options(320, 180, "steep_parallax");
  ref_opt.params["steps"] = "256";
  ref_opt.self_shadow = ref_opt.shadows = false;
  const std::optional<Framebuffer> ref = test::render_frame(scene, ref_opt);
  ASSERT_TRUE(ref);
  double psnr[3];
  const int layers[3] = {8, 64, 256};
  for (int j = 0; j < 3; ++j) {
    RenderOptions opt = shells_options(layers[j], 320, 180);
    opt.self_shadow = opt.shadows = false;
    const std::optional<Framebuffer> f = test::render_frame(scene, opt);
    ASSERT_TRUE(f);
    ASSERT_TRUE(finite_frame(*f));
    psnr[j] = compare_images(f->color, ref->color).psnr_db;
    RecordProperty("psnr_layers_" + std::to_string(layers[j]), std::to_string(psnr[j]));
    std::printf("shells layers=%d vs steep_parallax 256: %.2f dB\n", layers[j], psnr[j]);
  }
  // measured: 24.6, 37.6 and 39.1 dB
  EXPECT_GT(psnr[1], psnr[0] + 6.0);
  EXPECT_GT(psnr[1], 33.0);
  EXPECT_GE(psnr[2], psnr[1]);
}

// One layer is the base shell: opaque everywhere (hit depth 1), finite.
TEST(Shells, OneLayerIsTheOpaqueBase) {
  const Scene scene = plane_scene();
  RenderOptions opt = shells_options(1);
  opt.aovs = aov_bit(Aov::kHitDepth);
  const std::optional<Framebuffer> f = test::render_frame(scene, opt);
  ASSERT_TRUE(f);
  EXPECT_TRUE(finite_frame(*f));
  const std::optional<Framebuffer> flat =
      test::render_frame(scene, test::cpu_options(160, 90, "flat"));
  ASSERT_TRUE(flat);
  // the base lies one relief height below the polygon: nearly the flat quad's pixels
  EXPECT_GT(covered(*f), covered(*flat) * 9 / 10);
  for (int y = 0; y < f->height; ++y)
    for (int x = 0; x < f->width; ++x)
      if (f->depth.values[y * f->width + x] > 0.0f) {
        ASSERT_EQ(f->aov_at(x, y)[kAovOffset[1]], 1.0f);
      }
}

// Corner cases stay finite: grazing views, a 1x1 depth map, an all-zero one (every shell opaque:
// the outermost hides the rest).
TEST(Shells, CornerCasesAreFinite) {
  for (float elevation : {0.02f, 0.2f}) {
    Scene scene = plane_scene();
    scene.cameras[0].position = glm::vec3(0.0f, 1.8f * elevation, 1.8f);
    const std::optional<Framebuffer> f = test::render_frame(scene, shells_options(16));
    ASSERT_TRUE(f);
    EXPECT_TRUE(finite_frame(*f)) << elevation;
  }
  for (int size : {1, 16}) {
    Scene scene = plane_scene();
    std::vector<float> zero(size * size, 0.0f);
    scene.materials[0].textures["depth"] =
        std::make_shared<Texture>(Texture::from_floats(TexFormat::kR32F, size, size, zero.data()));
    RenderOptions opt = shells_options(8);
    opt.aovs = aov_bit(Aov::kHitDepth);
    const std::optional<Framebuffer> f = test::render_frame(scene, opt);
    ASSERT_TRUE(f);
    EXPECT_TRUE(finite_frame(*f)) << size;
    EXPECT_GT(covered(*f), 160 * 90 / 2) << size;
    for (int y = 0; y < f->height; ++y)
      for (int x = 0; x < f->width; ++x)
        if (f->depth.values[y * f->width + x] > 0.0f) {  // the outermost shell, h = 7/8
          ASSERT_EQ(f->aov_at(x, y)[kAovOffset[1]], 1.0f / 8.0f) << size;
        }
  }
}

// MASK materials keep their cutoff; BLEND ones are alpha-tested instead.
TEST(Shells, PlannerAlphaTestsLayeredMaterials) {
  Scene scene = plane_scene();
  scene.materials[0].alpha_mode = AlphaMode::kBlend;
  Result<Plan> plan = make_plan(scene, shells_options(4));
  ASSERT_TRUE(plan.ok());
  EXPECT_EQ(plan->materials[0].uniforms.alpha_mode, AlphaMode::kMask);
  EXPECT_NE(plan->explain().find("instead of BLEND"), std::string::npos) << plan->explain();
  scene.materials[0].alpha_mode = AlphaMode::kMask;
  scene.materials[0].alpha_cutoff = 0.25f;
  plan = make_plan(scene, shells_options(4));
  ASSERT_TRUE(plan.ok());
  EXPECT_EQ(plan->materials[0].uniforms.alpha_cutoff, 0.25f);
}

TEST(Shells, TheTriangleLimitCountsEveryLayer) {
  // 33000 triangles are within the scene limit once, not 256 times (8.4 M > 2^23): the planner
  // refuses before the prepare stage allocates the copies
  Scene scene = plane_scene();
  Mesh& mesh = scene.meshes[scene.instances[0].mesh];
  const std::vector<uint32_t> quad = mesh.indices;
  while (mesh.indices.size() / 3 < 33000)
    mesh.indices.insert(mesh.indices.end(), quad.begin(), quad.end());
  const uint64_t triangles = mesh.indices.size() / 3;
  ASSERT_LE(triangles * 128, kMaxSceneTriangles);
  ASSERT_GT(triangles * 256, kMaxSceneTriangles);
  EXPECT_TRUE(make_plan(scene, shells_options(128)).ok());
  Result<Plan> plan = make_plan(scene, shells_options(256));
  ASSERT_FALSE(plan.ok());
  EXPECT_NE(plan.status().message().find("use fewer layers"), std::string::npos)
      << plan.status().message();
}

}  // namespace
}  // namespace relief
