// The built-in `fur` and `grass` scenes: a generated field (bake/fur_field.h) tiled over a sphere
// and over a ground plane, rendered by steep parallax mapping with 32 depth planes and the
// depth-darkening self-shadow (McGuire and McGuire 2005: dense tall strands stop the march early,
// one polygon and no shells). The polygon is the level of the strand tips; the relief carves the
// skin or ground below it.
#include "builtin/builtin_fur.h"

#include <memory>
#include <string>
#include <utility>

#include "bake/fur_field.h"
#include "base/check.h"
#include "builtin/builtin_curved.h"
#include "builtin/builtin_parts.h"
#include "builtin/builtin_room.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

// The fields the scenes tile: 256 texels a side keeps the exported PNGs small.
constexpr int kFieldSize = 256;

// A steep-parallax material over the field of `options`: depth (16-bit), colour and the wrapped
// normal map for `depth_scale` (uv units).
Material field_material(const std::string& name, const FurFieldOptions& options,
                        float depth_scale) {
  Result<FurField> field = make_fur_field(options);
  CHECK(field.ok());
  auto depth = std::make_shared<Texture>(fur_depth_texture(*field));
  auto color = std::make_shared<Texture>(fur_color_texture(*field));
  auto normal = std::make_shared<Texture>(fur_normal_texture(*depth, depth_scale));
  Material m;
  m.name = name;
  m.technique = "steep_parallax";
  // the poster's fur self-shadow: darkening with depth (shadow=depth, index 1), no shadow rays
  m.params = {{"steps", 32.0f}, {"depth_scale", depth_scale}, {"shadow", 1.0f}};
  m.textures = {{"base_color", color}, {"depth", depth}, {"normal", normal}};
  m.self_shadow = true;  // the darkening is the self-shadow effect (--no-self-shadow: off)
  m.specular = 0.1f;
  m.shininess = 16.0f;
  return m;
}

// The fur scene's material, all of its set-up in one place.
Material fur_material() {
  FurFieldOptions o = fur_field_defaults(FurKind::kFur);
  o.size = kFieldSize;
  return field_material("fur", o, 0.06f);
}

// The grass scene's material, all of its set-up in one place.
Material grass_material() {
  FurFieldOptions o = fur_field_defaults(FurKind::kGrass);
  o.size = kFieldSize;
  return field_material("grass", o, 0.1f);
}

// One field-covered mesh under one sun, seen by one camera.
Scene field_scene(const std::string& name, Mesh mesh, Material material, const Light& sun,
                  const Camera& camera, glm::vec3 ambient, glm::vec4 background) {
  Scene s;
  s.name = name;
  s.meshes.push_back(std::move(mesh));
  s.materials.push_back(std::move(material));
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(sun);
  s.cameras.push_back(camera);
  s.ambient = ambient;
  s.background = background;
  return s;
}

}  // namespace

Result<Scene> make_fur_scene() {
  // 8 x 4 tiles around the unit sphere: a tile about 0.8 units, a strand about 0.01.
  return field_scene("fur", parametric_mesh("fur_sphere", sphere_surface(1.0f), 96, 48, {8, 4}),
                     fur_material(),
                     directional_light("sun", {-0.6f, -0.5f, -0.6f}, glm::vec3(1.5f)),
                     look_at("view", {0.0f, 0.8f, 3.3f}, glm::vec3(0.0f), 40.0f, 30.0f),
                     glm::vec3(0.1f), glm::vec4(0.05f, 0.06f, 0.08f, 1.0f));
}

Result<Scene> make_grass_scene() {
  // A 16 x 16 ground facing +y, 24 tiles a side: a tile 0.67 units, grass 0.067 tall.
  const float half = 8.0f;
  Mesh ground;
  ground.name = "ground";
  add_rect(ground, {-half, 0.0f, half}, {2.0f * half, 0.0f, 0.0f}, {0.0f, 0.0f, -2.0f * half},
           {24.0f, 24.0f});
  prepare_mesh(ground);
  // About 15 degrees above the plane: eye 0.8 up, aimed at a point 3 units ahead; a sky behind.
  return field_scene("grass", std::move(ground), grass_material(),
                     directional_light("sun", {-0.4f, -0.6f, -0.7f}, glm::vec3(1.6f)),
                     look_at("low", {0.0f, 0.8f, 3.0f}, {0.0f, 0.0f, 0.0f}, 45.0f, 40.0f),
                     glm::vec3(0.12f), glm::vec4(0.45f, 0.6f, 0.8f, 1.0f));
}

}  // namespace relief
