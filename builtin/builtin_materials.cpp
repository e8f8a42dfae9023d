// The built-in `materials` scene: the metallic-roughness BRDF on relief surfaces.
#include "builtin/builtin_materials.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "builtin/builtin_parts.h"
#include "builtin/builtin_room.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

float smooth01(float x) {
  x = std::clamp(x, 0.0f, 1.0f);
  return x * x * (3.0f - 2.0f * x);
}

// Round dimples on an 8 x 8 grid (tileable): 0 on the rim, 0.8 at a dimple's centre.
ReliefTexel dimples(float u, float v) {
  const float x = u * 8.0f - std::floor(u * 8.0f) - 0.5f;
  const float y = v * 8.0f - std::floor(v * 8.0f) - 0.5f;
  const float r = std::sqrt(x * x + y * y) / 0.42f;
  return {0.8f * (1.0f - smooth01(r)), glm::vec3(0.9f)};
}

// Square tiles (4 x 4 over the texture) with grooves between them.
ReliefTexel tiles(float u, float v) {
  const float x = u * 4.0f - std::floor(u * 4.0f), y = v * 4.0f - std::floor(v * 4.0f);
  const float edge = std::min(std::min(x, 1.0f - x), std::min(y, 1.0f - y));
  const int checker = (static_cast<int>(u * 4.0f) + static_cast<int>(v * 4.0f)) % 2;
  return {1.0f - smooth01(edge / 0.06f), checker ? glm::vec3(0.75f) : glm::vec3(0.35f)};
}

// The floor's metallicRoughness texture: roughness (green) 0.25 on one colour of tile, 0.85 on
// the other, metallic (blue) 0; linear, 64 x 64 with mips.
TexturePtr tile_roughness() {
  const int n = 64;
  std::vector<float> texels(size_t(n) * n * 4);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int checker = (x * 4 / n + y * 4 / n) % 2;
      float* t = &texels[(size_t(y) * n + x) * 4];
      t[0] = 1.0f;
      t[1] = checker ? 0.25f : 0.85f;
      t[2] = 0.0f;
      t[3] = 1.0f;
    }
  auto tex =
      std::make_shared<Texture>(Texture::from_floats(TexFormat::kRGBA8, n, n, texels.data()));
  tex->generate_mips();
  return tex;
}

Material sphere_material(const char* name, glm::vec3 base, float metallic, float roughness) {
  Material m = procedural_relief_material(name, dimples, 256, 0.03f);
  m.shading = ShadingModel::kMetallicRoughness;
  m.base_color = glm::vec4(base, 1.0f);
  m.metallic = metallic;
  m.roughness = roughness;
  return m;
}

}  // namespace

Result<Scene> make_materials_scene() {
  Scene s;
  s.name = "materials";
  const glm::vec3 gold(1.0f, 0.71f, 0.29f), red(0.8f, 0.12f, 0.08f);
  s.materials.push_back(sphere_material("smooth_metal", gold, 1.0f, 0.25f));
  s.materials.push_back(sphere_material("rough_metal", gold, 1.0f, 0.7f));
  s.materials.push_back(sphere_material("smooth_dielectric", red, 0.0f, 0.25f));
  s.materials.push_back(sphere_material("rough_dielectric", red, 0.0f, 0.7f));
  Material floor_mat = procedural_relief_material("floor_tiles", tiles, 512, 0.02f);
  floor_mat.shading = ShadingModel::kMetallicRoughness;
  floor_mat.metallic = 1.0f;  // times the texture's 0
  floor_mat.roughness = 1.0f;
  floor_mat.metallic_roughness_texture = tile_roughness();
  s.materials.push_back(floor_mat);
  for (int i = 0; i < 4; ++i) {
    s.meshes.push_back(make_sphere({-2.1f + 1.4f * i, 0.6f, 0.0f}, 0.6f, 48, 24));
    s.instances.push_back({i, i, glm::mat4(1.0f)});
  }
  Mesh floor;
  floor.name = "floor";
  add_rect(floor, {-4.0f, 0.0f, 3.0f}, {8.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -6.0f}, {4.0f, 3.0f});
  prepare_mesh(floor);
  s.meshes.push_back(std::move(floor));
  s.instances.push_back({4, 4, glm::mat4(1.0f)});
  // 80 cd at about 5.2 m: about 3 lux on the spheres, a white diffuse surface's radiance ~1
  s.lights.push_back(shadow_spot({2.5f, 4.0f, 3.0f}, {0.0f, 0.4f, 0.0f}, {1.0f, 0.96f, 0.9f}, 80.0f,
                                 30.0f, 40.0f));
  s.lights.push_back(directional_light("fill", {0.6f, -0.5f, -0.6f}, {0.6f, 0.7f, 0.85f}, 0.6f));
  s.cameras.push_back(look_at("front", {0.0f, 1.7f, 5.0f}, {0.0f, 0.45f, 0.0f}, 40.0f, 30.0f));
  s.ambient = glm::vec3(0.04f);
  s.background = glm::vec4(0.02f, 0.02f, 0.03f, 1.0f);
  return s;
}

}  // namespace relief
