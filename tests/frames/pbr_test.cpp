// glTF metallic-roughness materials render as the BRDF says (docs/scene-format.md, "Shading"):
// four spheres (smooth and rough metal, smooth and rough dielectric, one base colour) saved as a
// glTF file and loaded back differ where they must: the metals' highlights carry the base colour
// and the dielectrics' are white, smooth highlights are smaller and brighter than rough ones, and
// a metal has no diffuse term. The metallicRoughness texture's blue and green channels scale the
// factors. The same frame is bit-identical for every SIMD level and the scalar lanes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <vector>

#include <glm/geometric.hpp>

#include "base/simd.h"
#include "builtin/builtin_room.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

constexpr int kW = 320, kH = 96;
const glm::vec4 kBase{0.9f, 0.5f, 0.2f, 1.0f};  // linear base colour: orange

struct Ball {
  float metallic, roughness;
  float x;  // centre
};
const Ball kBalls[] = {
    {1.0f, 0.2f, -3.0f}, {1.0f, 0.8f, -1.0f}, {0.0f, 0.2f, 1.0f}, {0.0f, 0.8f, 3.0f}};

Scene four_spheres() {
  Scene s;
  s.name = "four_spheres";
  s.background = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
  s.ambient = glm::vec3(0.0f);
  for (const Ball& b : kBalls) {
    Material m;
    m.name = "ball" + std::to_string(s.materials.size());
    m.technique = "flat";
    m.shading = ShadingModel::kMetallicRoughness;
    m.base_color = kBase;
    m.metallic = b.metallic;
    m.roughness = b.roughness;
    s.materials.push_back(m);
    s.meshes.push_back(make_sphere({b.x, 0.0f, 0.0f}, 0.9f, 64, 32));
    const int i = static_cast<int>(s.meshes.size()) - 1;
    s.instances.push_back({i, i, glm::mat4(1.0f)});
  }
  Light sun;
  sun.name = "sun";
  sun.direction = glm::normalize(glm::vec3(-0.3f, -0.4f, -1.0f));  // from behind the camera
  sun.intensity = 3.0f;
  s.lights.push_back(sun);
  Camera c;
  c.name = "front";
  c.position = {0.0f, 0.0f, 9.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.yfov_deg = 14.0f;
  s.cameras.push_back(c);
  return s;
}

Image render(const Scene& scene, bool scalar_lanes = false) {
  RenderOptions opt;
  opt.width = kW;
  opt.height = kH;
  opt.scalar_lanes = scalar_lanes;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return std::move(r).value().framebuffer.color;
}

// The pixels of ball i (its screen column band, foreground only).
struct BallStats {
  glm::vec3 brightest{0.0f};  // the pixel of largest luminance
  float peak = 0.0f;          // its luminance
  int bright = 0;             // pixels above half the peak
  glm::vec3 mean{0.0f};
  int covered = 0;
};

float luminance(glm::vec3 c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

BallStats ball_stats(const Image& img, int i) {
  BallStats st;
  const int x0 = kW * i / 4, x1 = kW * (i + 1) / 4;
  for (int pass = 0; pass < 2; ++pass)
    for (int y = 0; y < kH; ++y)
      for (int x = x0; x < x1; ++x) {
        const glm::vec3 c(img.at(x, y)[0], img.at(x, y)[1], img.at(x, y)[2]);
        const float l = luminance(c);
        if (pass == 0) {
          EXPECT_TRUE(std::isfinite(l)) << x << " " << y;
          if (l > st.peak) st.peak = l, st.brightest = c;
          if (l > 0.0f) st.mean += c, ++st.covered;
        } else if (l > 0.5f * st.peak) {
          ++st.bright;
        }
      }
  if (st.covered) st.mean /= float(st.covered);
  return st;
}

class Pbr : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::fresh_test_dir("pbr");
    const std::string path = (dir_ / "four_spheres.gltf").string();
    Status saved = save_gltf(four_spheres(), path);
    ASSERT_TRUE(saved.ok()) << saved.message();
    Result<Scene> loaded = load_scene(path);
    ASSERT_TRUE(loaded.ok()) << loaded.status().message();
    scene_ = std::move(loaded).value();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  Scene scene_;
};

TEST_F(Pbr, FileRoundTripKeepsTheMetallicRoughnessTerms) {
  ASSERT_EQ(scene_.materials.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(scene_.materials[i].shading, ShadingModel::kMetallicRoughness);
    EXPECT_EQ(scene_.materials[i].metallic, kBalls[i].metallic);
    EXPECT_EQ(scene_.materials[i].roughness, kBalls[i].roughness);
  }
}

TEST_F(Pbr, MetalsAndDielectricsRoughAndSmoothDifferWhereTheyMust) {
  const Image img = render(scene_);
  BallStats st[4];
  for (int i = 0; i < 4; ++i) {
    st[i] = ball_stats(img, i);
    ASSERT_GT(st[i].covered, 1000) << i;
  }
  // smooth highlights are brighter and smaller than rough ones (metal 0 vs 1, dielectric 2 vs 3)
  for (int smooth : {0, 2}) {
    EXPECT_GT(st[smooth].peak, 2.0f * st[smooth + 1].peak) << smooth;
    EXPECT_LT(st[smooth].bright, st[smooth + 1].bright) << smooth;
  }
  // a metal's highlight carries its base colour (f0 = base), a dielectric's is white (f0 = 0.04)
  const glm::vec3 metal = st[0].brightest, dielectric = st[2].brightest;
  EXPECT_NEAR(metal.b / metal.r, kBase.b / kBase.r, 0.05f);
  EXPECT_GT(dielectric.b / dielectric.r, 0.9f);  // diffuse orange under a white highlight
  // a metal has no diffuse term: away from the highlight it is darker than the dielectric
  EXPECT_LT(st[1].mean.r, st[3].mean.r);
}

// A metallicRoughness texture scales the factors: blue = metallic, green = roughness. A texture
// of (_, 0.25, 1) under factors (1, 0.8) is the material (1, 0.2): ball 0's pixels.
TEST_F(Pbr, MetallicRoughnessTextureScalesTheFactors) {
  Scene textured = four_spheres();
  Material& m = textured.materials[0];
  m.roughness = 0.8f;
  const float texel[4] = {0.0f, 0.25f, 1.0f, 1.0f};
  auto t = std::make_shared<Texture>(Texture::from_floats(TexFormat::kRGBA16F, 1, 1, texel));
  t->generate_mips();
  m.metallic_roughness_texture = t;
  const Image want = render(four_spheres());
  const Image got = render(textured);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW / 4; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got.at(x, y)[c], want.at(x, y)[c], 1e-5f * std::max(1.0f, want.at(x, y)[c]))
            << x << " " << y;
}

// Blinn-Phong stays a material choice: with "shading": "blinn_phong" the metallic-roughness terms
// do not apply (the frame is the same bits whatever they are), and the look is Blinn-Phong's.
TEST_F(Pbr, BlinnPhongMaterialsIgnoreTheMetallicRoughnessTerms) {
  for (Material& m : scene_.materials) m.shading = ShadingModel::kBlinnPhong;
  const Image img = render(scene_);
  Scene other = scene_;
  for (Material& m : other.materials) m.metallic = 0.5f, m.roughness = 0.05f;
  EXPECT_EQ(render(other).pixels, img.pixels);
  // Blinn-Phong's white highlight (specular 0.25 x 3 lux) over the orange diffuse on every ball
  for (int i = 0; i < 4; ++i) EXPECT_GT(ball_stats(img, i).brightest.b, 0.7f) << i;
}

TEST_F(Pbr, BitIdenticalOnEverySimdLevelAndTheScalarLanes) {
  const SimdLevel saved = simd_level();
  set_simd_level(SimdLevel::kBaseline);
  const Image base = render(scene_);
  EXPECT_EQ(render(scene_, true).pixels, base.pixels) << "scalar lanes";
  for (SimdLevel level : simd_levels_supported()) {
    set_simd_level(level);
    EXPECT_EQ(render(scene_).pixels, base.pixels) << simd_level_name(level);
  }
  set_simd_level(saved);
}

}  // namespace
}  // namespace relief
