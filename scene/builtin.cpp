// Built-in scenes, generated in code so `relief render` works with no files.
#include "scene/builtin.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "bake/normal_map.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

uint32_t hash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}
float hash01(uint32_t x) { return static_cast<float>(hash32(x) & 0xffffff) / 16777215.0f; }

// Running-bond bricks: 8 courses and 4 bricks per course per tile, half-brick offset on odd
// courses. Depth 0 on brick faces (with a per-brick tilt of up to 0.08), 1 in the mortar,
// bevelled edges.
struct BrickTile {
  float depth;
  glm::vec3 color;
};
BrickTile brick_at(float u, float v) {
  const int courses = 8, per_course = 4;
  const float mortar = 0.012f, bevel = 0.018f;
  const float cv = v * courses;
  const int row = static_cast<int>(std::floor(cv));
  const float fv = cv - row;
  const float shift = (row & 1) ? 0.5f : 0.0f;
  const float cu = u * per_course + shift;
  const int col = static_cast<int>(std::floor(cu));
  const float fu = cu - col;
  // distance to the brick's border in uv units
  const float du = std::min(fu, 1.0f - fu) / per_course;
  const float dv = std::min(fv, 1.0f - fv) / courses;
  const float edge = std::min(du, dv);
  const uint32_t id = static_cast<uint32_t>((row & 7) * 16 + ((col % per_course + per_course) % per_course));
  BrickTile b;
  if (edge < mortar) {
    b.depth = 1.0f;
    b.color = glm::vec3(0.62f, 0.60f, 0.56f);
    return b;
  }
  const float tilt = 0.08f * hash01(id * 3 + 1) * (fu - 0.5f) + 0.04f * hash01(id * 3 + 2);
  const float bev = edge < mortar + bevel ? (1.0f - (edge - mortar) / bevel) : 0.0f;
  b.depth = std::clamp(tilt + 0.9f * bev * bev, 0.0f, 1.0f);
  const float tint = hash01(id * 7 + 5);
  b.color = glm::vec3(0.55f + 0.15f * tint, 0.22f + 0.06f * tint, 0.14f + 0.04f * tint);
  return b;
}

void make_bricks(int size, TexturePtr& depth, TexturePtr& color) {
  std::vector<float> d(size_t(size) * size);
  std::vector<uint8_t> c(size_t(size) * size * 4);
  auto srgb8 = [](float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    const float s = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
    return static_cast<uint8_t>(std::lround(s * 255.0f));
  };
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const BrickTile b = brick_at((x + 0.5f) / size, (y + 0.5f) / size);
      const size_t i = size_t(y) * size + x;
      d[i] = b.depth;
      for (int k = 0; k < 3; ++k) c[i * 4 + k] = srgb8(b.color[k]);
      c[i * 4 + 3] = 255;
    }
  auto dt = std::make_shared<Texture>(Texture::from_floats(TexFormat::kR8, size, size, d.data()));
  dt->generate_mips(MipReduce::kAverage);
  auto ct = std::make_shared<Texture>(TexFormat::kRGBA8, size, size, c.data(), ColorSpace::kSRGB);
  ct->generate_mips(MipReduce::kAverage);
  depth = dt;
  color = ct;
}

Mesh make_quad(float half, float uv_tiles) {
  Mesh m;
  m.name = "quad";
  // XZ plane facing +y; u along +x, v along +z.
  m.positions = {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
  m.normals.assign(4, glm::vec3(0, 1, 0));
  m.uvs = {{0, 0}, {uv_tiles, 0}, {uv_tiles, uv_tiles}, {0, uv_tiles}};
  m.indices = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +y
  prepare_mesh(m);
  return m;
}

Result<Scene> make_plane() {
  Scene s;
  s.name = "plane";
  s.meshes.push_back(make_quad(4.0f, 8.0f));  // fills a 16:9 view
  TexturePtr depth, color;
  make_bricks(512, depth, color);
  const float depth_scale = 0.06f;
  auto normal = std::make_shared<Texture>(normal_map_from_depth(*depth, depth_scale, true));
  Material mat;
  mat.name = "bricks";
  mat.technique = "relief";
  mat.params = {{"depth_scale", depth_scale}};
  mat.textures = {{"base_color", color}, {"depth", depth}, {"normal", normal}};
  mat.self_shadow = true;
  mat.depth_write = true;
  s.materials.push_back(mat);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  Light sun;
  sun.name = "sun";
  sun.type = LightType::kDirectional;
  sun.direction = glm::normalize(glm::vec3(-0.6f, -0.7f, -0.4f));
  sun.color = glm::vec3(1.5f);
  s.lights.push_back(sun);
  Camera cam;
  cam.name = "45deg";
  // 45 degrees between the view direction and the plane's normal.
  cam.position = glm::vec3(0.0f, 1.25f, 1.25f);
  cam.target = glm::vec3(0.0f, 0.0f, 0.0f);
  cam.yfov_deg = 50.0f;
  cam.znear = 0.05f;
  cam.zfar = 20.0f;
  s.cameras.push_back(cam);
  s.ambient = glm::vec3(0.08f);
  s.background = glm::vec4(0.05f, 0.06f, 0.08f, 1.0f);
  return s;
}

}  // namespace

const std::vector<BuiltinSceneInfo>& builtin_scenes() {
  static const std::vector<BuiltinSceneInfo> scenes = {
      {"plane", "one quad with a procedural brick depth map and its normal map, camera at 45 deg"},
  };
  return scenes;
}

const char* default_scene_name() { return "plane"; }

Result<Scene> make_builtin_scene(const std::string& name) {
  if (name == "plane") return make_plane();
  std::string known;
  for (const auto& s : builtin_scenes()) known += (known.empty() ? "" : ", ") + s.name;
  return Status::error("unknown scene '" + name + "' (built-in scenes: " + known + ")");
}

}  // namespace relief
