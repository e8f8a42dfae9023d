// The built-in scenes that show relief meeting other geometry:
//   interpenetration: spheres pushed through a relief floor (Policarpo, Oliveira and Comba 2005,
//     figure 18: with depth correction the relief cuts the spheres where its surface is, not
//     where its polygon is) and two coincident relief cylinders of different materials
//     (Oliveira and Policarpo 2005, figure 12: per fragment, the nearer relief surface wins);
//   teatime: a relief teapot on a relief floor under a shadow-casting spot light (the teapot's
//     relief casts into the shadow map and the floor receives it).
#include "builtin/builtin_showcase.h"

#include <algorithm>
#include <cmath>

#include "builtin/builtin_curved.h"
#include "builtin/builtin_parts.h"
#include "builtin/builtin_room.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

float fract(float x) {
  return x - std::floor(x);
}

// Square slabs with deep mortar joints, 3 x 3 per tile; slabs slightly domed.
ReliefTexel slabs(float u, float v) {
  const float fu = fract(u * 3.0f), fv = fract(v * 3.0f);
  const float edge = std::min({fu, 1.0f - fu, fv, 1.0f - fv});  // 0 on a joint, 0.5 inside
  const float depth = edge < 0.06f ? 1.0f : 0.15f * (1.0f - std::min(1.0f, edge / 0.5f));
  const int cell = static_cast<int>(std::floor(u * 3.0f)) + static_cast<int>(std::floor(v * 3.0f));
  const glm::vec3 stone =
      (cell & 1) ? glm::vec3(0.62f, 0.58f, 0.52f) : glm::vec3(0.55f, 0.52f, 0.5f);
  return {depth, edge < 0.06f ? glm::vec3(0.2f, 0.19f, 0.18f) : stone};
}

// Horizontal rings, 6 per tile: grooves of depth 1 between rounded ridges.
ReliefTexel rings(float, float v) {
  const float f = fract(v * 6.0f) - 0.5f;  // -0.5 .. 0.5 across one ring
  const float d = std::clamp(4.0f * f * f, 0.0f, 1.0f);
  return {d, glm::vec3(0.35f, 0.55f, 0.75f) * (1.0f - 0.5f * d)};
}

// Vertical flutes, 8 per tile: a different relief on the same cylinder as `rings`.
ReliefTexel flutes(float u, float) {
  const float f = fract(u * 8.0f) - 0.5f;
  const float d = std::clamp(1.0f - 4.0f * f * f, 0.0f, 1.0f);
  return {d, glm::vec3(0.8f, 0.6f, 0.3f) * (1.0f - 0.4f * d)};
}

// An untextured-relief sphere material: flat shading over a checker base colour.
Material checker_material(const std::string& name, glm::vec3 a, glm::vec3 b) {
  const int n = 64;
  std::vector<uint8_t> rgba(size_t(n) * n * 4, 255);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const glm::vec3 c = ((x / 8 + y / 8) & 1) ? a : b;
      for (int k = 0; k < 3; ++k)
        rgba[(size_t(y) * n + x) * 4 + k] = static_cast<uint8_t>(std::lround(c[k] * 255.0f));
    }
  auto tex = std::make_shared<Texture>(TexFormat::kRGBA8, n, n, rgba.data(), ColorSpace::kSRGB);
  tex->generate_mips(MipReduce::kAverage);
  Material m;
  m.name = name;
  m.technique = "flat";
  m.textures = {{"base_color", tex}};
  return m;
}

glm::mat4 translation(glm::vec3 t) {
  glm::mat4 m(1.0f);
  m[3] = glm::vec4(t, 1.0f);
  return m;
}

int add_mesh(Scene& s, Mesh mesh) {
  s.meshes.push_back(std::move(mesh));
  return static_cast<int>(s.meshes.size()) - 1;
}

Mesh floor_quad(float half, float tiles) {
  Mesh m;
  m.name = "floor";
  add_rect(m, {-half, 0, half}, {2 * half, 0, 0}, {0, 0, -2 * half}, {tiles, tiles});
  prepare_mesh(m);
  return m;
}

}  // namespace

Result<Scene> make_interpenetration_scene() {
  Scene s;
  s.name = "interpenetration";
  // The floor: 4 x 4 units, 2 tiles each way, relief 0.06 uv deep = 0.12 units.
  s.materials.push_back(procedural_relief_material("slabs", slabs, 256, 0.06f));
  s.materials.back().self_shadow = false;
  s.materials.push_back(checker_material("red_ball", {0.8f, 0.15f, 0.1f}, {0.95f, 0.85f, 0.8f}));
  s.materials.push_back(checker_material("green_ball", {0.1f, 0.6f, 0.2f}, {0.85f, 0.95f, 0.85f}));
  // The coincident cylinders: the same surface, two reliefs; relief_quadric for the outlines.
  Material ringed = procedural_relief_material("rings", rings, 128, 0.05f);
  Material fluted = procedural_relief_material("flutes", flutes, 128, 0.05f);
  for (Material* m : {&ringed, &fluted}) {
    m->technique = "relief_quadric";
    m->self_shadow = false;
    m->silhouette = true;
  }
  s.materials.push_back(ringed);
  s.materials.push_back(fluted);
  enum { kFloor, kRed, kGreen, kRings, kFlutes };

  const int floor = add_mesh(s, floor_quad(2.0f, 2.0f));
  s.instances.push_back({floor, kFloor, glm::mat4(1.0f)});
  // Spheres whose centres sit at the polygon (y = 0), half way into the relief (y = -0.06) and
  // just above it: the relief hides a different cap of each.
  // One mesh per instance: a glTF mesh carries its material, so shared meshes would not
  // round-trip through `relief export` as they are.
  const Mesh ball = parametric_mesh("ball", sphere_surface(0.35f), 32, 16, {2, 1});
  s.instances.push_back({add_mesh(s, ball), kRed, translation({-1.1f, 0.0f, 0.4f})});
  s.instances.push_back({add_mesh(s, ball), kGreen, translation({-0.3f, -0.06f, 0.9f})});
  s.instances.push_back({add_mesh(s, ball), kRed, translation({0.4f, 0.05f, 0.2f})});
  const Mesh tube = parametric_mesh("tube", cylinder_surface(0.4f, 1.2f), 48, 6, {2, 1});
  s.instances.push_back({add_mesh(s, tube), kRings, translation({1.1f, 0.0f, -0.6f})});
  s.instances.push_back({add_mesh(s, tube), kFlutes, translation({1.1f, 0.0f, -0.6f})});

  s.lights.push_back(directional_light("sun", {-0.4f, -0.8f, -0.5f}, glm::vec3(1.0f), 1.3f));
  s.cameras.push_back(look_at("front", {0.2f, 1.9f, 3.6f}, {0.2f, 0.1f, 0.0f}, 45.0f, 40.0f));
  s.ambient = glm::vec3(0.08f);
  s.background = glm::vec4(0.05f, 0.06f, 0.08f, 1.0f);
  return s;
}

Result<Scene> make_teatime_scene() {
  Scene s;
  s.name = "teatime";
  s.materials.push_back(procedural_relief_material("slabs", slabs, 256, 0.04f));
  Material pot = procedural_relief_material("ringed_pot", rings, 128, 0.03f);
  pot.technique = "relief_quadric";
  pot.self_shadow = false;
  pot.silhouette = true;
  s.materials.push_back(pot);
  const int floor = add_mesh(s, floor_quad(3.0f, 3.0f));
  s.instances.push_back({floor, 0, glm::mat4(1.0f)});
  const int teapot = add_mesh(s, make_teapot(10, 1.4f, {2, 2}));
  s.instances.push_back({teapot, 1, glm::mat4(1.0f)});

  s.lights.push_back(shadow_spot({-2.0f, 3.6f, 1.6f}, {0.2f, 0.3f, -0.2f}, {1.0f, 0.94f, 0.85f},
                                 24.0f, 30.0f, 45.0f));
  s.lights.push_back(directional_light("fill", {0.5f, -0.6f, -0.4f}, glm::vec3(1.0f), 0.25f));
  s.cameras.push_back(look_at("table", {0.6f, 2.2f, 4.2f}, {0.0f, 0.55f, 0.0f}, 40.0f, 40.0f));
  s.ambient = glm::vec3(0.05f);
  s.background = glm::vec4(0.03f, 0.03f, 0.04f, 1.0f);
  return s;
}

}  // namespace relief
