// The built-in `impostor` scene: dual-depth relief textures (Policarpo, Oliveira and Comba,
// "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005, section 3.1) of a sphere,
// baked in code with our rasterizer and drawn with relief_dual on one quad.
#include "builtin/builtin_impostor.h"

#include <cmath>
#include <memory>

#include "builtin/builtin_curved.h"
#include "builtin/builtin_parts.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

TexturePtr depth_map(const DualDepthMaps& maps, const std::vector<float>& d) {
  return std::make_shared<Texture>(
      Texture::from_floats(TexFormat::kR32F, maps.size, maps.size, d.data()));
}

TexturePtr normal_map(const DualDepthMaps& maps, const std::vector<glm::vec3>& n) {
  std::vector<float> rgba;
  rgba.reserve(n.size() * 4);
  // the quad's uv runs +u = +x, +v = +y: green (toward the image top, -v) is -y (bake/normal_map.h)
  for (const glm::vec3& v : n)
    rgba.insert(rgba.end(), {v.x * 0.5f + 0.5f, -v.y * 0.5f + 0.5f, v.z * 0.5f + 0.5f, 1.0f});
  return std::make_shared<Texture>(
      Texture::from_floats(TexFormat::kRGBA16F, maps.size, maps.size, rgba.data()));
}

}  // namespace

Material dual_depth_material(const std::string& name, const DualDepthMaps& maps,
                             glm::vec3 base_color) {
  Material m;
  m.name = name;
  m.technique = "relief_dual";
  m.params = {{"depth_scale", maps.depth_scale()}};
  m.textures = {{"depth", depth_map(maps, maps.front)},
                {"depth_back", depth_map(maps, maps.back)},
                {"normal", normal_map(maps, maps.front_normal)},
                {"normal_back", normal_map(maps, maps.back_normal)}};
  m.base_color = glm::vec4(base_color, 1.0f);
  m.sampler.filter = Filter::kBilinear;
  m.sampler.wrap_u = m.sampler.wrap_v = Wrap::kClamp;
  m.self_shadow = false;
  m.depth_write = true;
  m.silhouette = true;
  return m;
}

Mesh dual_depth_quad(const DualDepthMaps& maps) {
  Mesh m;
  m.name = "impostor_quad";
  const glm::vec3 lo = maps.box_min, hi = maps.box_max;
  m.positions = {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  m.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
  m.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
  m.indices = {0, 1, 2, 0, 2, 3};
  prepare_mesh(m);
  return m;
}

float impostor_grow(float max_angle_deg) {
  const float a = max_angle_deg * 3.14159265358979f / 180.0f;
  return (1.0f + std::sin(a)) / std::cos(a);
}

Scene make_impostor_scene() {
  const Mesh sphere = parametric_mesh("sphere", sphere_surface(1.0f), 64, 32, {1.0f, 1.0f});
  const DualDepthMaps maps =
      bake_dual_depth(sphere.positions, sphere.normals, sphere.indices, 256, impostor_grow(45.0f));
  Scene s;
  s.name = "impostor";
  s.materials.push_back(dual_depth_material("sphere_impostor", maps, {0.8f, 0.5f, 0.3f}));
  s.meshes.push_back(dual_depth_quad(maps));
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(directional_light("sun", {-0.4f, -0.5f, -0.8f}, glm::vec3(1.4f)));
  const float a = 30.0f * 3.14159265358979f / 180.0f;
  s.cameras.push_back(look_at("view", glm::vec3(0.0f, -std::sin(a), std::cos(a)) * 5.0f,
                              glm::vec3(0.0f), 40.0f, 30.0f));
  s.ambient = glm::vec3(0.1f);
  s.background = glm::vec4(0.05f, 0.06f, 0.08f, 1.0f);
  return s;
}

}  // namespace relief
