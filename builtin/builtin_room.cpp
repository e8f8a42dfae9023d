// The built-in `room`: the "relief room" of Oliveira and Policarpo, "An Efficient Representation
// for Surface Details", UFRGS RP-351, 2005 (the quadric-silhouettes paper; figure 1: relief walls,
// floor and columns and a relief object in the middle; figure 13: relief casts shadows onto other
// objects and receives theirs). Every surface is relief-mapped with a procedural depth map (and
// its normal map, bake/normal_map.h), self-shadowed, depth-correcting, casting and receiving
// shadows; one spot light casts shadows (shadow maps, render/shadow_map.h), a dim directional
// fill light does not.
#include "builtin/builtin_room.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>

#include <glm/geometric.hpp>

#include "bake/normal_map.h"
#include "builtin/builtin_parts.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

constexpr float kPi = 3.14159265358979f;

// Deterministic value noise in [0, 1] of an integer lattice point.
float lattice01(int a, int b, uint32_t salt) {
  uint32_t h = static_cast<uint32_t>(a) * 0x8da6b343u ^ static_cast<uint32_t>(b) * 0xd8163841u ^
               salt * 0xcb1ab31fu;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return static_cast<float>(h & 0xffffffu) / 16777215.0f;
}

float smooth01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

using Texel = ReliefTexel;

// Square stone tiles, 4 x 4 per texture tile: grout at depth 1, bevelled faces with a small tilt.
Texel floor_tiles(float u, float v) {
  const int n = 4;
  const float cu = u * n, cv = v * n;
  const int i = static_cast<int>(std::floor(cu)), j = static_cast<int>(std::floor(cv));
  const float fu = cu - i, fv = cv - j;
  const float edge = std::min(std::min(fu, 1.0f - fu), std::min(fv, 1.0f - fv));
  const float shade = lattice01(i & 3, j & 3, 1);
  if (edge < 0.03f) return {1.0f, glm::vec3(0.30f, 0.29f, 0.27f)};
  const float bevel = 1.0f - smooth01((edge - 0.03f) / 0.07f);
  const float tilt = 0.12f * lattice01(i & 3, j & 3, 2) * fu + 0.05f * lattice01(i & 3, j & 3, 3);
  return {std::clamp(0.85f * bevel + tilt, 0.0f, 1.0f),
          glm::vec3(0.45f, 0.42f, 0.36f) * (0.75f + 0.4f * shade)};
}

// Ashlar: three courses of two large blocks per tile, offset by half a block on odd courses,
// with a rough face (two octaves of lattice noise) and deep joints.
Texel ashlar(float u, float v) {
  const int courses = 3;
  const float cv = v * courses;
  const int row = static_cast<int>(std::floor(cv));
  const float cu = u * 2.0f + ((row & 1) ? 0.5f : 0.0f);
  const int col = static_cast<int>(std::floor(cu));
  const float fu = cu - col, fv = cv - row;
  const float edge = std::min(std::min(fu, 1.0f - fu) * 0.5f, std::min(fv, 1.0f - fv) / courses);
  const int rc = row % courses, cc = col & 1;
  const float tone = lattice01(rc, cc, 7);
  if (edge < 0.012f) return {1.0f, glm::vec3(0.55f, 0.52f, 0.47f)};
  const float x = fu * 6.0f, y = fv * 3.0f;
  const int xi = static_cast<int>(x), yi = static_cast<int>(y);
  const float rough = 0.5f * lattice01(xi + 13 * cc, yi + 7 * rc, 8) +
                      0.5f * lattice01(static_cast<int>(x * 3.0f), static_cast<int>(y * 3.0f), 9);
  const float bevel = 1.0f - smooth01((edge - 0.012f) / 0.03f);
  return {std::clamp(0.9f * bevel + 0.12f * rough, 0.0f, 1.0f),
          glm::vec3(0.62f, 0.50f, 0.38f) * (0.8f + 0.3f * tone)};
}

// Six rounded flutes across u (a column's shaft), with a band once per tile along v.
Texel flutes(float u, float v) {
  const float groove = 0.5f - 0.5f * std::cos(2.0f * kPi * u * 6.0f);
  const float fv = v - std::floor(v);
  const float band = fv < 0.04f ? 1.0f : 0.0f;
  return {std::clamp(groove * (1.0f - band), 0.0f, 1.0f),
          glm::vec3(0.78f, 0.76f, 0.70f) * (band > 0.0f ? 0.85f : 1.0f)};
}

// Cobbles: the distance to the nearest of one jittered point per cell of a 6 x 6 grid (cellular
// noise, wrapping), rounded into stones.
Texel cobbles(float u, float v) {
  const int n = 6;
  const float x = u * n, y = v * n;
  const int cx = static_cast<int>(std::floor(x)), cy = static_cast<int>(std::floor(y));
  float d1 = 9.0f, d2 = 9.0f;
  int owner = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int gx = cx + dx, gy = cy + dy;
      const int wx = ((gx % n) + n) % n, wy = ((gy % n) + n) % n;
      const float px = gx + 0.2f + 0.6f * lattice01(wx, wy, 11);
      const float py = gy + 0.2f + 0.6f * lattice01(wx, wy, 12);
      const float d = std::hypot(x - px, y - py);
      if (d < d1) {
        d2 = d1;
        d1 = d;
        owner = wy * n + wx;
      } else if (d < d2) {
        d2 = d;
      }
    }
  const float gap = d2 - d1;  // 0 on the border between two stones
  const float tone = lattice01(owner, 0, 13);
  return {std::clamp(1.0f - smooth01(gap / 0.35f) + 0.25f * d1 * d1, 0.0f, 1.0f),
          glm::vec3(0.40f, 0.45f, 0.52f) * (0.7f + 0.5f * tone)};
}

uint8_t to_srgb8(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  const float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

}  // namespace

Material procedural_relief_material(const std::string& name, const ReliefPattern& pattern, int size,
                                    float depth_scale) {
  std::vector<float> depth(size_t(size) * size);
  std::vector<uint8_t> rgba(size_t(size) * size * 4, 255);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const Texel t = pattern((x + 0.5f) / size, (y + 0.5f) / size);
      const size_t i = size_t(y) * size + x;
      depth[i] = t.depth;
      for (int k = 0; k < 3; ++k) rgba[i * 4 + k] = to_srgb8(t.color[k]);
    }
  auto d =
      std::make_shared<Texture>(Texture::from_floats(TexFormat::kR8, size, size, depth.data()));
  d->generate_mips(MipReduce::kAverage);
  auto c = std::make_shared<Texture>(TexFormat::kRGBA8, size, size, rgba.data(), ColorSpace::kSRGB);
  c->generate_mips(MipReduce::kAverage);
  auto n = std::make_shared<Texture>(normal_map_from_depth(*d, depth_scale, true));
  Material m;
  m.name = name;
  m.technique = "relief";
  m.params = {{"depth_scale", depth_scale}};
  m.textures = {{"base_color", c}, {"depth", d}, {"normal", n}};
  m.self_shadow = true;
  m.depth_write = true;
  return m;
}

void add_rect(Mesh& m, glm::vec3 corner, glm::vec3 eu, glm::vec3 ev, glm::vec2 uv_max) {
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  const glm::vec3 n = glm::normalize(glm::cross(eu, ev));
  m.positions.insert(m.positions.end(), {corner, corner + eu, corner + eu + ev, corner + ev});
  m.normals.insert(m.normals.end(), 4, n);
  m.uvs.insert(m.uvs.end(), {{0, 0}, {uv_max.x, 0}, uv_max, {0, uv_max.y}});
  m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

Mesh make_sphere(glm::vec3 c, float r, int slices, int stacks) {
  Mesh m;
  m.name = "sphere";
  for (int j = 0; j <= stacks; ++j)
    for (int i = 0; i <= slices; ++i) {
      const float theta = kPi * j / stacks, phi = 2.0f * kPi * i / slices;
      const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                        -std::sin(theta) * std::sin(phi));
      m.positions.push_back(c + r * n);
      m.normals.push_back(n);
      m.uvs.push_back({4.0f * i / slices, 2.0f * (1.0f - static_cast<float>(j) / stacks)});
    }
  const uint32_t row = static_cast<uint32_t>(slices + 1);
  for (uint32_t j = 0; j < static_cast<uint32_t>(stacks); ++j)
    for (uint32_t i = 0; i < static_cast<uint32_t>(slices); ++i) {
      const uint32_t a = j * row + i, b = a + 1, d = a + row, e = d + 1;
      m.indices.insert(m.indices.end(), {a, d, e, a, e, b});
    }
  prepare_mesh(m);
  return m;
}

namespace {

// A square column standing on y = 0: four sides and the top, one texture tile across each side.
Mesh make_column(glm::vec2 c, float half, float height) {
  Mesh m;
  m.name = "column";
  const float w = 2.0f * half;
  const glm::vec2 side(1.0f, height / w);
  add_rect(m, {c.x - half, 0, c.y + half}, {w, 0, 0}, {0, height, 0}, side);
  add_rect(m, {c.x + half, 0, c.y + half}, {0, 0, -w}, {0, height, 0}, side);
  add_rect(m, {c.x + half, 0, c.y - half}, {-w, 0, 0}, {0, height, 0}, side);
  add_rect(m, {c.x - half, 0, c.y - half}, {0, 0, w}, {0, height, 0}, side);
  add_rect(m, {c.x - half, height, c.y + half}, {w, 0, 0}, {0, 0, -w}, {1.0f, 1.0f});
  prepare_mesh(m);
  return m;
}

}  // namespace

Result<Scene> make_room_scene() {
  Scene s;
  s.name = "room";
  const float half = 4.0f, height = 4.0f;
  s.materials.push_back(procedural_relief_material("floor_tiles", floor_tiles, 512, 0.04f));
  s.materials.push_back(procedural_relief_material("ashlar_walls", ashlar, 512, 0.05f));
  s.materials.push_back(procedural_relief_material("fluted_columns", flutes, 256, 0.06f));
  s.materials.push_back(procedural_relief_material("cobble_sphere", cobbles, 512, 0.05f));
  enum { kFloorMat, kWallMat, kColumnMat, kSphereMat };
  auto add = [&](Mesh mesh, int material) {
    s.meshes.push_back(std::move(mesh));
    s.instances.push_back({static_cast<int>(s.meshes.size()) - 1, material, glm::mat4(1.0f)});
  };
  Mesh floor;
  floor.name = "floor";
  add_rect(floor, {-half, 0, half}, {2 * half, 0, 0}, {0, 0, -2 * half}, {4, 4});
  prepare_mesh(floor);
  add(std::move(floor), kFloorMat);
  Mesh walls;
  walls.name = "walls";  // back (facing +z), left (+x), right (-x); the front stays open
  add_rect(walls, {-half, 0, -half}, {2 * half, 0, 0}, {0, height, 0}, {4, 2});
  add_rect(walls, {-half, 0, half}, {0, 0, -2 * half}, {0, height, 0}, {4, 2});
  add_rect(walls, {half, 0, -half}, {0, 0, 2 * half}, {0, height, 0}, {4, 2});
  prepare_mesh(walls);
  add(std::move(walls), kWallMat);
  for (const glm::vec2 c : {glm::vec2(-2.6f, -2.6f), glm::vec2(2.6f, -2.6f), glm::vec2(-2.6f, 0.9f),
                            glm::vec2(2.6f, 0.9f)})
    add(make_column(c, 0.3f, 3.2f), kColumnMat);
  add(make_sphere({0.0f, 0.85f, -0.6f}, 0.85f, 48, 24), kSphereMat);

  s.lights.push_back(shadow_spot({2.2f, 3.7f, 2.6f}, {-0.4f, 0.3f, -0.9f}, {1.0f, 0.93f, 0.82f},
                                 34.0f, 38.0f, 52.0f));
  s.lights.push_back(directional_light("fill", {0.5f, -0.6f, -0.6f}, {0.55f, 0.62f, 0.75f}, 0.35f));

  s.cameras.push_back(look_at("entrance", {0.0f, 2.1f, 7.4f}, {0.0f, 1.1f, -0.6f}, 55.0f, 30.0f));
  s.ambient = glm::vec3(0.05f);
  s.background = glm::vec4(0.02f, 0.02f, 0.03f, 1.0f);
  return s;
}

}  // namespace relief
