// Shadow maps with relief depth (render/shadow_map.h, shaders_cpp/shadow_lookup.h): relief casts
// shadows onto other objects and receives theirs (quadric paper, figure 13), no acne with the
// default bias, and the shadowed room is bit-identical for any thread count.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <functional>
#include <memory>
#include <random>
#include <set>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "builtin/builtin_room.h"
#include "render/render.h"
#include "render/shadow_map.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

constexpr int kW = 240, kH = 180;

float luminance(glm::vec4 c) {
  return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
}

int add_mesh(Scene& s, Mesh m, int material) {
  prepare_mesh(m);
  s.meshes.push_back(std::move(m));
  s.instances.push_back({static_cast<int>(s.meshes.size()) - 1, material, glm::mat4(1.0f)});
  return static_cast<int>(s.instances.size()) - 1;
}

Mesh rect(glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, glm::vec2 uv_max = glm::vec2(1.0f)) {
  Mesh m;
  add_rect(m, corner, eu, ev, uv_max);
  return m;
}

// A relief material whose depth map is 0 everywhere: a geometrically flat receiver.
Material flat_relief(const std::string& name, glm::vec3 color) {
  return procedural_relief_material(
      name,
      [color](float, float) {
        return ReliefTexel{0.0f, color};
      },
      16, 0.05f);
}

Light directional(glm::vec3 travel) {
  Light l;
  l.name = "sun";
  l.type = LightType::kDirectional;
  l.direction = glm::normalize(travel);
  l.color = glm::vec3(1.0f);
  l.intensity = 2.0f;
  l.casts_shadows = true;
  l.shadow_resolution = 1024;
  return l;
}

Camera camera(glm::vec3 from, glm::vec3 to) {
  Camera c;
  c.name = "test";
  c.position = from;
  c.target = to;
  c.yfov_deg = 50.0f;
  c.znear = 0.05f;
  c.zfar = 30.0f;
  return c;
}

RenderResult render(const Scene& scene, int threads = 2, bool shadows = true, bool scalar = false,
                    int tile = 64, bool on_demand = true) {
  RenderOptions opt;
  opt.width = kW;
  opt.height = kH;
  opt.shadows = shadows;
  opt.scalar_lanes = scalar;
  opt.shadow_on_demand = on_demand;
  Result<Plan> plan = make_plan(scene, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  Result<RenderResult> r =
      make_cpu_backend({.threads = threads, .tile_size = tile})->render(scene, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return std::move(r).value();
}

void expect_finite(const Framebuffer& fb) {
  for (const glm::vec4& c : fb.color.pixels)
    for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(c[k]));
  for (float z : fb.depth.values) ASSERT_TRUE(std::isfinite(z) && z >= 0.0f && z <= 1.0f);
}

// Pixel of world point p, or (-1, -1) when it is off screen.
glm::ivec2 project(const Scene& s, glm::vec3 p) {
  const Camera& c = s.cameras[0];
  const glm::vec4 h = c.projection(float(kW) / kH) * c.view() * glm::vec4(p, 1.0f);
  const int x = static_cast<int>(std::floor((h.x / h.w * 0.5f + 0.5f) * kW));
  const int y = static_cast<int>(std::floor((0.5f - h.y / h.w * 0.5f) * kH));
  if (x < 0 || y < 0 || x >= kW || y >= kH) return {-1, -1};
  return {x, y};
}

// World position of pixel (x, y) from the depth buffer.
glm::vec3 unproject(const Scene& s, const Framebuffer& fb, int x, int y) {
  const Camera& c = s.cameras[0];
  const glm::mat4 inv = glm::inverse(c.projection(float(kW) / kH) * c.view());
  const glm::vec4 h = inv * glm::vec4((x + 0.5f) / kW * 2.0f - 1.0f, 1.0f - (y + 0.5f) / kH * 2.0f,
                                      fb.depth.at(x, y), 1.0f);
  return glm::vec3(h) / h.w;
}

// ---- a relief wall casts a shadow onto a flat floor --------------------------------------------

// Floor y = 0 (a flat receiver) and a wall in the plane x = 0 facing +x, z in [-1, 1], y in [0, 2],
// whose depth map has 8 vertical stripes across z: grooves (depth 1, 0.2 world units deep) and
// faces (depth 0). The sun shines from +x at 45 degrees; the camera looks from behind the wall
// (-x), which culls the wall, so the floor under and behind it is in view.
constexpr float kWallDepthScale = 0.1f;  // uv units; the wall is 2 world units per uv
bool groove_at(float u) {
  return static_cast<int>(std::floor(u * 8.0f)) % 2 == 0;
}

Scene wall_scene(const std::string& wall_technique) {
  Scene s;
  s.name = "wall";
  s.materials.push_back(flat_relief("floor", glm::vec3(0.8f)));
  Material wall = procedural_relief_material(
      "wall",
      [](float u, float) {
        return ReliefTexel{groove_at(u) ? 1.0f : 0.0f, glm::vec3(0.7f)};
      },
      64, kWallDepthScale);
  wall.technique = wall_technique;
  wall.self_shadow = false;
  wall.sampler.filter = Filter::kNearest;
  s.materials.push_back(wall);
  add_mesh(s, rect({-2, 0, 2}, {4, 0, 0}, {0, 0, -4}), 0);
  // u runs from z = 1 to z = -1
  add_mesh(s, rect({0, 0, 1}, {0, 0, -2}, {0, 2, 0}), 1);
  s.lights.push_back(directional({-1, -1, 0}));
  s.cameras.push_back(camera({-3.0f, 2.6f, 0.0f}, {-0.2f, 0.0f, 0.0f}));
  s.ambient = glm::vec3(0.05f);
  return s;
}

// Shadowed (true) or lit at floor points (x, 0, z) for z at the stripe centres.
std::vector<int> floor_row(const Scene& s, const RenderResult& lit, const RenderResult& r,
                           float x) {
  std::vector<int> shadowed;
  for (int k = 0; k < 8; ++k) {
    const float z = 1.0f - 2.0f * (k + 0.5f) / 8.0f;
    const glm::ivec2 p = project(s, {x, 0.0f, z});
    EXPECT_GE(p.x, 0) << "floor point off screen";
    if (p.x < 0) return shadowed;
    const float ref = luminance(lit.framebuffer.color.at(p.x, p.y));
    const float v = luminance(r.framebuffer.color.at(p.x, p.y));
    EXPECT_GT(ref, 0.3f);
    shadowed.push_back(v < 0.3f * ref ? 1 : (v > 0.9f * ref ? 0 : -1));  // -1: penumbra
  }
  return shadowed;
}

TEST(Shadow, ReliefWallShadowOutlineFollowsTheRelief) {
  const Scene relief = wall_scene("relief");
  const Scene flat = wall_scene("flat");
  const RenderResult unshadowed = render(relief, 2, false);
  const RenderResult r = render(relief);
  const RenderResult f = render(flat);
  expect_finite(r.framebuffer);
  ASSERT_EQ(r.passes.size(), 2u);
  EXPECT_EQ(r.passes[0].kind, PassPlan::Kind::kShadow);
  EXPECT_GT(r.passes[0].raster.work.search_steps, 0u);  // the wall's search ran from the light
  // In front of the wall everything is lit; beyond the relief's depth everything is shadowed.
  for (int v : floor_row(relief, unshadowed, r, 0.3f)) EXPECT_EQ(v, 0);
  for (int v : floor_row(relief, unshadowed, r, -0.4f)) EXPECT_EQ(v, 1);
  // Inside the relief's depth (0 > x > -0.2) the light reaches the floor through the grooves
  // only: the outline follows the stripes. A flat wall shadows all of it.
  const std::vector<int> in_relief = floor_row(relief, unshadowed, r, -0.1f);
  const std::vector<int> in_flat = floor_row(flat, unshadowed, f, -0.1f);
  ASSERT_EQ(in_relief.size(), 8u);
  ASSERT_EQ(in_flat.size(), 8u);
  for (int k = 0; k < 8; ++k) {
    const float u = (k + 0.5f) / 8.0f;
    EXPECT_EQ(in_relief[k], groove_at(u) ? 0 : 1) << "stripe " << k;
    EXPECT_EQ(in_flat[k], 1) << "stripe " << k;
  }
}

// ---- a flat blocker shadows a relief floor, for each kind of light -----------------------------

// A relief floor (0.15 world units deep, tile faces 0.09 to 0.12 below the polygon) under a flat
// square blocker at height 1 over x, z in [0.5, 1.5]. Floor pixels are classified from their
// depth-buffer position (the displaced relief point) by tracing towards the light: inside the
// blocker's shadow by a margin, they must be darker than without the blocker; outside by the
// margin, unchanged.
Scene blocker_scene(const Light& light, bool with_blocker) {
  Scene s;
  s.name = "blocker";
  s.materials.push_back(procedural_relief_material(
      "floor",
      [](float u, float v) {
        const float fu = u * 4 - std::floor(u * 4), fv = v * 4 - std::floor(v * 4);
        const bool grout = fu < 0.08f || fv < 0.08f;
        return ReliefTexel{grout ? 1.0f : 0.6f + 0.2f * fu, glm::vec3(0.8f)};
      },
      128, 0.05f));
  s.materials[0].self_shadow = false;
  Material blocker;
  blocker.name = "blocker";
  blocker.technique = "flat";
  blocker.base_color = glm::vec4(0.9f, 0.2f, 0.2f, 1.0f);
  blocker.double_sided = true;
  // Not a receiver: the directional map stays fitted to the floor alone, so its texel grid (and
  // with it the floor's relief shadowing itself) is the same with and without the blocker.
  blocker.receives_shadow = false;
  s.materials.push_back(blocker);
  add_mesh(s, rect({-3, 0, 3}, {6, 0, 0}, {0, 0, -6}, {2, 2}), 0);
  if (with_blocker) add_mesh(s, rect({0.5f, 1.0f, 1.5f}, {1, 0, 0}, {0, 0, -1}), 1);
  s.lights.push_back(light);
  s.cameras.push_back(camera({-0.5f, 4.5f, 4.0f}, {0.0f, 0.0f, 0.0f}));
  s.ambient = glm::vec3(0.05f);
  return s;
}

// +1: shadowed by the blocker by more than `margin`; -1: clear of it by more than `margin`; 0:
// near its outline.
int blocker_side(const Light& light, glm::vec3 p, float margin) {
  const glm::vec3 to_light = light.type == LightType::kDirectional
                                 ? -glm::normalize(light.direction)
                                 : glm::normalize(light.position - p);
  if (!(to_light.y > 1e-3f)) return -1;
  const float t = (1.0f - p.y) / to_light.y;
  if (light.type != LightType::kDirectional && t > glm::length(light.position - p)) return -1;
  const glm::vec3 q = p + to_light * t;
  const float inside = std::min(std::min(q.x - 0.5f, 1.5f - q.x), std::min(q.z - 0.5f, 1.5f - q.z));
  return inside > margin ? 1 : (inside < -margin ? -1 : 0);
}

void check_blocker_shadow(const Light& light) {
  const Scene without = blocker_scene(light, false);
  const Scene with = blocker_scene(light, true);
  const RenderResult a = render(without);
  const RenderResult b = render(with);
  expect_finite(b.framebuffer);
  ASSERT_EQ(b.passes.size(), 2u);
  int core = 0, core_dark = 0, outside = 0, outside_changed = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (a.framebuffer.depth.at(x, y) <= 0.0f) continue;
      if (a.framebuffer.depth.at(x, y) != b.framebuffer.depth.at(x, y)) continue;  // the blocker
      const glm::vec3 p = unproject(with, b.framebuffer, x, y);
      const float la = luminance(a.framebuffer.color.at(x, y));
      const float lb = luminance(b.framebuffer.color.at(x, y));
      const int side = blocker_side(light, p, 0.06f);
      if (side > 0 && la > 0.2f) {
        ++core;
        core_dark += lb < 0.5f * la;
      } else if (side < 0) {
        ++outside;
        outside_changed += std::fabs(lb - la) > 2.0f / 255.0f;
      }
    }
  EXPECT_GT(core, 200);
  EXPECT_GE(core_dark, core * 98 / 100) << core_dark << " of " << core;
  EXPECT_GT(outside, 5000);
  EXPECT_LE(outside_changed, outside / 100) << outside_changed << " of " << outside;
}

Light blocker_sun() {
  return directional({-0.5f, -1.0f, 0.3f});
}

Light blocker_spot() {
  Light l = directional({0, -1, 0});
  l.type = LightType::kSpot;
  l.position = glm::vec3(2.5f, 3.5f, 0.3f);
  l.direction = glm::normalize(glm::vec3(0.0f, 0.0f, 0.5f) - l.position);
  l.inner_cone_deg = 50.0f;
  l.outer_cone_deg = 60.0f;
  l.intensity = 25.0f;
  return l;
}

// The light sits beside the blocker's height, so its shadow crosses cube faces.
Light blocker_point() {
  Light l = directional({0, -1, 0});
  l.type = LightType::kPoint;
  l.position = glm::vec3(2.2f, 1.6f, 1.0f);
  l.intensity = 8.0f;
  l.shadow_resolution = 512;
  return l;
}

TEST(Shadow, FlatBlockerShadowsReliefFloorDirectional) {
  check_blocker_shadow(blocker_sun());
}

TEST(Shadow, FlatBlockerShadowsReliefFloorSpot) {
  check_blocker_shadow(blocker_spot());
}

TEST(Shadow, FlatBlockerShadowsReliefFloorPointCube) {
  check_blocker_shadow(blocker_point());
}

// ---- no acne ---------------------------------------------------------------------------------

// A flat receiving and casting plane lit at 60 degrees from its normal: with the default bias
// every lookup returns 1, so the image is bit-identical to the frame without the shadow pass.
// Also with flat and normal (polygon receivers).
class ShadowAcne : public ::testing::TestWithParam<const char*> {};

TEST_P(ShadowAcne, NoAcneOnLitPlaneAt60Degrees) {
  Scene s;
  s.name = "lit plane";
  s.materials.push_back(flat_relief("plane", glm::vec3(0.8f)));
  s.materials[0].technique = GetParam();
  add_mesh(s, rect({-3, 0, 3}, {6, 0, 0}, {0, 0, -6}, {3, 3}), 0);
  const float a = glm::radians(60.0f);
  s.lights.push_back(directional({-std::sin(a), -std::cos(a), 0.0f}));
  s.cameras.push_back(camera({0.0f, 2.5f, 3.0f}, {0.0f, 0.0f, 0.0f}));
  const RenderResult shadowed = render(s);
  ASSERT_EQ(shadowed.passes.size(), 2u);
  const RenderResult plain = render(s, 2, false);
  ASSERT_EQ(plain.passes.size(), 1u);
  int differ = 0;
  for (size_t i = 0; i < plain.framebuffer.color.pixels.size(); ++i)
    differ += plain.framebuffer.color.pixels[i] != shadowed.framebuffer.color.pixels[i];
  EXPECT_EQ(differ, 0);
}

INSTANTIATE_TEST_SUITE_P(Shadow, ShadowAcne, ::testing::Values("relief", "flat", "normal"));

// ---- determinism ------------------------------------------------------------------------------

bool identical(const Framebuffer& a, const Framebuffer& b) {
  return a.color.pixels == b.color.pixels && a.depth.values == b.depth.values;
}

Scene small_room() {
  Result<Scene> s = make_room_scene();
  EXPECT_TRUE(s.ok());
  s->lights[0].shadow_resolution = 256;  // keeps the test fast; the paths are the same
  return std::move(s).value();
}

TEST(Shadow, RoomIsBitIdenticalForAnyThreadCountAndFinite) {
  const Scene room = small_room();
  const RenderResult ref = render(room, 1);
  ASSERT_EQ(ref.passes.size(), 2u);
  EXPECT_GT(ref.passes[0].raster.work.fragments, 0u);
  expect_finite(ref.framebuffer);
  for (auto [threads, tile] : {std::pair{2, 64}, std::pair{7, 64}, std::pair{7, 16}}) {
    const RenderResult r = render(room, threads, true, false, tile);
    EXPECT_TRUE(identical(ref.framebuffer, r.framebuffer)) << threads << " threads, tile " << tile;
  }
  // shadows change the image
  EXPECT_FALSE(identical(ref.framebuffer, render(room, 2, false).framebuffer));
}

TEST(Shadow, RoomScalarAndSimdLanesAgreeBitForBit) {
  const Scene room = small_room();
  EXPECT_TRUE(
      identical(render(room, 2, true, false).framebuffer, render(room, 2, true, true).framebuffer));
}

// ---- shadow maps drawn on demand ---------------------------------------------------------------

// Shadow fragments shaded in the frame's shadow pass (one shadow-casting light).
uint64_t shadow_fragments(const RenderResult& r) {
  EXPECT_EQ(r.passes.size(), 2u);
  return r.passes.front().raster.work.fragments;
}

// Drawing the maps' tiles when the main pass's lookups first reach them gives the image (colour
// and depth) of the maps drawn whole, for each kind of light, at any thread count and tile size;
// the view here needs less than the whole map, so fewer shadow fragments are shaded, and as many
// on every run (the tiles drawn are those the frame's lookups reach, whichever thread asks).
void expect_on_demand_matches_whole(const Scene& s) {
  const RenderResult whole = render(s, 2, true, false, 64, false);
  expect_finite(whole.framebuffer);
  ASSERT_EQ(whole.passes.size(), 2u);
  EXPECT_GT(whole.passes[0].raster.tiles, 0u);
  EXPECT_EQ(whole.passes[0].raster.tiles_drawn, whole.passes[0].raster.tiles);
  uint64_t drawn = 0;  // the shadow fragments drawn on demand: the same for every run
  for (auto [threads, tile] : {std::pair{1, 64}, std::pair{2, 64}, std::pair{7, 16}}) {
    const RenderResult r = render(s, threads, true, false, tile, true);
    EXPECT_TRUE(identical(whole.framebuffer, r.framebuffer))
        << threads << " threads, tile " << tile;
    if (drawn == 0) drawn = shadow_fragments(r);
    EXPECT_EQ(shadow_fragments(r), drawn) << threads << " threads, tile " << tile;
    EXPECT_LT(shadow_fragments(r), shadow_fragments(whole));
    EXPECT_GT(shadow_fragments(r), 0u);
    EXPECT_EQ(r.passes[0].raster.tiles, whole.passes[0].raster.tiles);
    EXPECT_LT(r.passes[0].raster.tiles_drawn, r.passes[0].raster.tiles);
  }
}

TEST(Shadow, MapsDrawnOnDemandGiveTheWholeMapsImageDirectional) {
  expect_on_demand_matches_whole(blocker_scene(blocker_sun(), true));
}

TEST(Shadow, MapsDrawnOnDemandGiveTheWholeMapsImageSpot) {
  expect_on_demand_matches_whole(blocker_scene(blocker_spot(), true));
}

TEST(Shadow, MapsDrawnOnDemandGiveTheWholeMapsImagePointCube) {
  expect_on_demand_matches_whole(blocker_scene(blocker_point(), true));
}

TEST(Shadow, MapsDrawnOnDemandGiveTheWholeMapsImageRoom) {
  expect_on_demand_matches_whole(small_room());
}

// One face of a shadow map whose tiles "draw" by filling in the caster's depth: a lookup that
// read a texel of a tile it had not asked for would read the far plane there.
struct FakeTiledMap {
  int size, tile;
  float caster_depth;  // reversed-Z depth of the caster over every texel
  std::vector<float> depth;
  std::unique_ptr<std::atomic<uint8_t>[]> drawn;
  std::set<std::pair<int, int>> asked;  // tiles drawn since reset(), (tx, ty)
  ShadowTiles tiles;

  FakeTiledMap(int size_, int tile_, float caster)
      : size(size_), tile(tile_), caster_depth(caster), depth(size_t(size_) * size_) {
    const int per_row = (size + tile - 1) / tile;
    drawn = std::make_unique<std::atomic<uint8_t>[]>(size_t(per_row) * per_row);
    tiles.shift = std::countr_zero(static_cast<unsigned>(tile));
    EXPECT_EQ(1 << tiles.shift, tile);
    tiles.per_row = per_row;
    tiles.drawn[0] = drawn.get();
    tiles.owner = this;
    tiles.draw = [](const void* owner, int face, int t) {
      auto* m = const_cast<FakeTiledMap*>(static_cast<const FakeTiledMap*>(owner));
      EXPECT_EQ(face, 0);
      const int tx = t % m->tiles.per_row, ty = t / m->tiles.per_row;
      EXPECT_TRUE(m->asked.insert({tx, ty}).second) << "tile drawn twice";
      for (int y = ty * m->tile; y < std::min((ty + 1) * m->tile, m->size); ++y)
        for (int x = tx * m->tile; x < std::min((tx + 1) * m->tile, m->size); ++x)
          m->depth[size_t(y) * m->size + x] = m->caster_depth;
      m->drawn[t].store(1, std::memory_order_release);
    };
    reset();
  }
  void reset() {
    std::fill(depth.begin(), depth.end(), 0.0f);  // the far plane: lights every receiver
    for (int t = 0; t < tiles.per_row * tiles.per_row; ++t) drawn[t].store(0);
    asked.clear();
  }
};

// A lookup asks, before it reads, for exactly the tiles its taps reach, and for each once: a
// sun straight down over a floor, a caster over all of it, receivers all over the map and on
// its borders (where the taps are clamped), each PCF radius.
TEST(Shadow, LookupAsksForExactlyTheTilesItsTapsReach) {
  Light sun = directional({0.0f, -1.0f, 0.0f});
  sun.shadow_resolution = 64;
  Bounds floor, casters;
  floor.add({-1.0f, 0.0f, -1.0f});
  floor.add({1.0f, 0.0f, 1.0f});
  casters.add({-1.0f, 0.5f, -1.0f});
  casters.add({1.0f, 0.5f, 1.0f});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coord(-1.1f, 1.1f);
  for (int r = 0; r <= kMaxPcfRadius; ++r) {
    ShadowSettings settings;
    settings.pcf_radius = r;
    const ShadowPassSetup setup = fit_shadow_pass(sun, floor, casters, settings);
    ASSERT_TRUE(setup.orthographic);
    // the caster at 0.5 above the floor, in the map's reversed-Z depth
    const glm::vec4 c = setup.proj[0] * setup.view[0] * glm::vec4(0.0f, 0.5f, 0.0f, 1.0f);
    FakeTiledMap map(setup.size, 8, c.z / c.w);
    const float* faces[1] = {map.depth.data()};
    ShadowMapView view = make_shadow_view(setup, faces, settings);
    view.tiles = &map.tiles;
    for (int i = 0; i < 400; ++i) {
      map.reset();
      const glm::vec3 p(coord(rng), 0.0f, coord(rng));
      const glm::vec4 q = setup.proj[0] * setup.view[0] * glm::vec4(p, 1.0f);
      const float px = (q.x / q.w * 0.5f + 0.5f) * setup.size;
      const float py = (0.5f - q.y / q.w * 0.5f) * setup.size;
      float fetches = 0.0f;
      const float lit = relief::detail::shadow_lookup(view, p, {0, 1, 0}, {0, 1, 0}, fetches);
      if (!(px >= 0.0f && px <= setup.size && py >= 0.0f && py <= setup.size)) {
        EXPECT_EQ(lit, 1.0f);  // outside the map: lit, and nothing asked for
        EXPECT_TRUE(map.asked.empty());
        continue;
      }
      EXPECT_EQ(lit, 0.0f) << "a tap read a tile it did not ask for, at " << px << ", " << py;
      std::set<std::pair<int, int>> expected;
      const int x0 = static_cast<int>(std::floor(px - 0.5f));
      const int y0 = static_cast<int>(std::floor(py - 0.5f));
      for (int j = -r; j <= r + 1; ++j)
        for (int k = -r; k <= r + 1; ++k)
          expected.insert({std::clamp(x0 + k, 0, setup.size - 1) / map.tile,
                           std::clamp(y0 + j, 0, setup.size - 1) / map.tile});
      EXPECT_EQ(map.asked, expected) << "radius " << r << " at " << px << ", " << py;
    }
  }
}

}  // namespace
}  // namespace relief
