// Image-based light on the CPU backend (docs/environment.md, shaders_cpp/lighting.h
// metallic_roughness_indirect): white spheres in a white furnace (a constant environment) return
// what the single-scattering split sum says and never more than 1; the environment turns with
// --env-rotation and scales with --env-intensity; the occlusion texture scales it; a scene without
// lights gets the studio environment unless told not to; and the frames are bit-identical on
// every SIMD level and the scalar lanes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/environment_bake.h"
#include "base/simd.h"
#include "builtin/builtin_room.h"
#include "render/derived_maps.h"
#include "render/render.h"

namespace relief {
namespace {

constexpr int kW = 384, kH = 64;

struct Ball {
  float metallic, roughness;
};
// White dielectrics and white metals at roughness 0, 0.5 and 1.
const Ball kBalls[] = {{0.0f, 0.0f}, {0.0f, 0.5f}, {0.0f, 1.0f},
                       {1.0f, 0.0f}, {1.0f, 0.5f}, {1.0f, 1.0f}};
constexpr int kBallCount = 6;

Scene furnace(const char* technique = "flat") {
  Scene s;
  s.name = "furnace";
  s.background = glm::vec4(0.0f);  // alpha 0: covered pixels are those of alpha 1
  s.ambient = glm::vec3(0.0f);
  for (int i = 0; i < kBallCount; ++i) {
    Material m;
    m.name = "ball" + std::to_string(i);
    m.technique = technique;
    m.shading = ShadingModel::kMetallicRoughness;
    m.base_color = glm::vec4(1.0f);
    m.metallic = kBalls[i].metallic;
    m.roughness = kBalls[i].roughness;
    s.materials.push_back(m);
    s.meshes.push_back(make_sphere({2.0f * i - 5.0f, 0.0f, 0.0f}, 0.9f, 64, 32));
    s.instances.push_back({i, i, glm::mat4(1.0f)});
  }
  Camera c;
  c.name = "front";
  c.position = {0.0f, 0.0f, 40.0f};
  c.target = {0.0f, 0.0f, 0.0f};
  c.yfov_deg = 2.8645f;  // 2 atan(1 / 40): the six balls centred in six equal columns
  s.cameras.push_back(c);
  return s;
}

// An equirectangular environment of one radiance, or brighter on the +X half (u in (0.5, 1)).
Image constant_environment(float radiance, float plus_x = -1.0f) {
  Image img(64, 32);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const float r = plus_x >= 0.0f && x >= img.width / 2 ? plus_x : radiance;
      img.at(x, y) = glm::vec4(r, r, r, 1.0f);
    }
  return img;
}

std::shared_ptr<const EnvironmentMaps> maps_of(const Image& img) {
  Result<DerivedEnvironment> d = derived_environment(img);
  EXPECT_TRUE(d.ok()) << d.status().message();
  return d.ok() ? d->maps : nullptr;
}

struct Frame {
  Image color;
  bool studio = false;  // the plan chose the studio environment
};

Frame render(const Scene& scene, RenderOptions opt) {
  opt.width = kW;
  opt.height = kH;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Frame f;
  f.studio = plan->environment_reason.find("studio") != std::string::npos;
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  if (r.ok()) f.color = std::move(r).value().framebuffer.color;
  return f;
}

RenderOptions with_environment(const Image& env, float degrees = 0.0f, float intensity = 1.0f) {
  RenderOptions opt;
  opt.environment = maps_of(env);
  opt.env_view = environment_view(degrees, intensity);
  return opt;
}

// The covered pixels of ball i: their range per channel and mean.
struct Range {
  float lo = 1e30f, hi = -1e30f, mean = 0.0f;
  int covered = 0;
};
Range ball_range(const Image& img, int i, int channel = 0) {
  Range r;
  const int x0 = kW * i / kBallCount, x1 = kW * (i + 1) / kBallCount;
  for (int y = 0; y < kH; ++y)
    for (int x = x0; x < x1; ++x) {
      if (img.at(x, y)[3] < 1.0f) continue;  // edge or background
      const float v = img.at(x, y)[channel];
      EXPECT_TRUE(std::isfinite(v));
      r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v), r.mean += v, ++r.covered;
    }
  if (r.covered) r.mean /= static_cast<float>(r.covered);
  return r;
}

// White furnace: a white dielectric returns (1 - s) E/pi + s L = 1 for any split-sum weight s; a
// white metal returns A + B <= 1, the single-scattering model's loss growing with roughness.
// The bound 1 + 2e-3 is the bake's own error on a constant: SH9 projection of the constant by
// quadrature and half-float storage of the prefiltered radiance and (A, B).
TEST(EnvironmentLight, WhiteFurnaceNeverExceedsOne) {
  for (const char* technique : {"flat", "relief"}) {
    Scene s = furnace(technique);
    if (std::string(technique) == "relief") {
      // a flat depth map: the relief kernel's hit is the surface, its normal the sphere's
      const float zero = 0.0f;
      auto depth = std::make_shared<Texture>(Texture::from_floats(TexFormat::kR32F, 1, 1, &zero));
      depth->generate_mips();
      for (Material& m : s.materials) m.textures["depth"] = depth;
    }
    const Frame f = render(s, with_environment(constant_environment(1.0f)));
    for (int i = 0; i < kBallCount; ++i) {
      const Range r = ball_range(f.color, i);
      ASSERT_GT(r.covered, 500) << technique << " " << i;
      EXPECT_LE(r.hi, 1.002f) << technique << " ball " << i;
      if (kBalls[i].metallic == 0.0f) {
        EXPECT_GE(r.lo, 0.995f) << technique << " ball " << i;
      } else {
        // A + B: near 1 when smooth; a rough metal loses energy, most at grazing angles, down
        // to the split sum's smallest A + B over the ball's n.v (the LUT's own error aside)
        float least = 1.0f;
        for (float nv = 0.02f; nv <= 1.0f; nv += 0.02f) {
          const glm::vec2 ab = integrate_split_sum(nv, kBalls[i].roughness, 4096);
          least = std::min(least, ab.x + ab.y);
        }
        EXPECT_GT(r.lo, least - 0.02f) << technique << " ball " << i;
      }
    }
    // rougher metals lose more
    EXPECT_GT(ball_range(f.color, 3).mean, ball_range(f.color, 5).mean) << technique;
  }
}

// Every covered pixel of `got` is exactly k times `base` (k a power of two: exact in float).
void expect_scaled(const Image& got, const Image& base, float k) {
  int covered = 0;
  for (size_t p = 0; p < base.pixels.size(); ++p) {
    if (base.pixels[p][3] < 1.0f) continue;
    ++covered;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(got.pixels[p][c], k * base.pixels[p][c]) << p;
  }
  EXPECT_GT(covered, 3000);
}

// --env-intensity scales the whole indirect term: 2x is exact in float.
TEST(EnvironmentLight, IntensityScalesExactly) {
  const Scene s = furnace();
  const Image env = constant_environment(0.3f, 1.5f);
  const Image one = render(s, with_environment(env, 30.0f, 1.0f)).color;
  const Image two = render(s, with_environment(env, 30.0f, 2.0f)).color;
  expect_scaled(two, one, 2.0f);
}

// The environment is bright on its +X half. Unturned, a rough dielectric sphere is brighter on
// its +X (screen right) side; turned by 180 degrees the bright half is behind -X.
TEST(EnvironmentLight, RotationTurnsTheEnvironmentAboutY) {
  const Scene s = furnace();
  const Image env = constant_environment(0.1f, 1.0f);
  auto sides = [&](float degrees) {
    const Image img = render(s, with_environment(env, degrees)).color;
    const int i = 2;  // rough dielectric
    const int x0 = kW * i / kBallCount, x1 = kW * (i + 1) / kBallCount, xm = (x0 + x1) / 2;
    float left = 0.0f, right = 0.0f;
    for (int y = 0; y < kH; ++y)
      for (int x = x0; x < x1; ++x) (x < xm ? left : right) += img.at(x, y)[0];
    return std::pair<float, float>(left, right);
  };
  const auto [l0, r0] = sides(0.0f);
  EXPECT_GT(r0, 2.0f * l0);
  const auto [l1, r1] = sides(180.0f);
  EXPECT_GT(l1, 2.0f * r1);
  EXPECT_NEAR(l1, r0, 0.02f * r0);  // mirror images of each other
}

// The glTF occlusion texture scales the environment's light: 0.5 at strength 1 halves it.
TEST(EnvironmentLight, OcclusionTextureScalesTheIndirectLight) {
  Scene s = furnace();
  const Image env = constant_environment(0.5f, 1.2f);
  const Image full = render(s, with_environment(env)).color;
  const float half[4] = {0.5f, 0.5f, 0.5f, 1.0f};
  auto t = std::make_shared<Texture>(Texture::from_floats(TexFormat::kRGBA16F, 1, 1, half));
  t->generate_mips();
  for (Material& m : s.materials) m.occlusion_texture = t, m.occlusion_strength = 1.0f;
  const Image occluded = render(s, with_environment(env)).color;
  expect_scaled(occluded, full, 0.5f);
}

// A scene without lights is lit by the studio environment (its plan says so); with
// studio_environment off it has only its ambient colour (0 here: black); a scene with a light
// does not get it.
TEST(EnvironmentLight, StudioEnvironmentLightsASceneWithoutLights) {
  Scene s = furnace();
  const Frame studio = render(s, RenderOptions{});
  EXPECT_TRUE(studio.studio);
  EXPECT_GT(ball_range(studio.color, 1).mean, 0.1f);
  RenderOptions off;
  off.studio_environment = false;
  const Frame dark = render(s, off);
  EXPECT_FALSE(dark.studio);
  EXPECT_EQ(ball_range(dark.color, 1).hi, 0.0f);
  Light sun;
  sun.direction = glm::vec3(0.0f, 0.0f, -1.0f);
  s.lights.push_back(sun);
  EXPECT_FALSE(render(s, RenderOptions{}).studio);
}

TEST(EnvironmentLight, BitIdenticalOnEverySimdLevelAndTheScalarLanes) {
  Scene s = furnace();
  s.materials[1].shading = ShadingModel::kBlinnPhong;  // its ambient is the irradiance
  const RenderOptions opt = with_environment(constant_environment(0.2f, 2.0f), 45.0f, 0.7f);
  const SimdLevel saved = simd_level();
  set_simd_level(SimdLevel::kBaseline);
  const Image base = render(s, opt).color;
  RenderOptions scalar = opt;
  scalar.scalar_lanes = true;
  EXPECT_EQ(render(s, scalar).color.pixels, base.pixels) << "scalar lanes";
  for (SimdLevel level : simd_levels_supported()) {
    set_simd_level(level);
    EXPECT_EQ(render(s, opt).color.pixels, base.pixels) << simd_level_name(level);
  }
  set_simd_level(saved);
}

}  // namespace
}  // namespace relief
