// Built-in scenes, generated in code so `relief render` works with no files.
#include "builtin/builtin.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "bake/normal_map.h"
#include "base/check.h"
#include "builtin/builtin_bending.h"
#include "builtin/builtin_curved.h"
#include "builtin/builtin_fur.h"
#include "builtin/builtin_impostor.h"
#include "builtin/builtin_materials.h"
#include "builtin/builtin_parts.h"
#include "builtin/builtin_room.h"
#include "builtin/builtin_showcase.h"
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
float hash01(uint32_t x) {
  return static_cast<float>(hash32(x) & 0xffffff) / 16777215.0f;
}

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
  const uint32_t id =
      static_cast<uint32_t>((row & 7) * 16 + ((col % per_course + per_course) % per_course));
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

// Depth of the `pattern` tile at texel (x, y) of an n x n map (n a multiple of 16): quadrants of
// smooth features (a dome on sine swells), sharp features (a pyramid and a cone on a flat top),
// thin walls (a grid of one-texel walls and pillars over a deep floor) and terraces cut by
// one-texel walls, separated by one-texel walls at x = 0, n / 2 and y = 0, n / 2.
float pattern_depth_at(int x, int y, int n) {
  const int h = n / 2;
  if (x == 0 || y == 0 || x == h || y == h) return 0.0f;  // quadrant walls, one texel wide
  const float px = (x % h) + 0.5f, py = (y % h) + 0.5f;   // position inside the quadrant
  const float cx = px - 0.5f * h, cy = py - 0.5f * h;     // from the quadrant's centre
  const float r = std::sqrt(cx * cx + cy * cy);
  const float k = 2.0f * static_cast<float>(M_PI) / h;
  if (x < h && y < h) {
    // smooth: a spherical dome on sine swells
    const float dome_r = 0.3f * h;
    if (r < dome_r) return 1.0f - 0.85f * std::sqrt(1.0f - (r / dome_r) * (r / dome_r));
    return 0.6f + 0.25f * std::sin(2.0f * k * px) * std::cos(3.0f * k * py);
  }
  if (y < h) {
    // sharp: a pyramid (apex at depth 0) and a cone, on a flat top at depth 0.85
    const float pyr = std::max(std::fabs(cx + 0.2f * h), std::fabs(cy + 0.2f * h)) / (0.22f * h);
    const float cone = std::hypot(cx - 0.22f * h, cy - 0.22f * h) / (0.2f * h);
    return std::min({0.85f, pyr, 0.1f + cone});
  }
  if (x < h) {
    // thin: one-texel walls every 8 texels over a floor at depth 1, one-texel pillars between
    const int lx = x % h, ly = y % h;
    if (lx % 8 == 0 || ly % 8 == 0) return 0.0f;
    if (lx % 8 == 4 && ly % 8 == 4 && ((lx / 8 + ly / 8) & 1)) return 0.05f;
    return 1.0f;
  }
  // terraces: eight steps with sharp edges, crossed by one-texel diagonal walls
  const int lx = x % h, ly = y % h;
  if ((lx + ly) % 12 == 0) return 0.1f;
  return 0.2f + 0.1f * static_cast<float>(std::min(7, lx * 8 / h));
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

// One relief-mapped quad (half size 4, `uv_tiles` repeats of the maps along each side) under a
// sun, seen at 45 degrees: the frame shared by the built-in relief scenes.
Scene relief_quad_scene(const std::string& name, float uv_tiles, const std::string& material,
                        TexturePtr depth, TexturePtr color, float depth_scale) {
  Scene s;
  s.name = name;
  s.meshes.push_back(make_quad(4.0f, uv_tiles));  // fills a 16:9 view
  auto normal = std::make_shared<Texture>(normal_map_from_depth(*depth, depth_scale, true));
  Material mat;
  mat.name = material;
  mat.technique = "relief";
  mat.params = {{"depth_scale", depth_scale}};
  mat.textures = {{"base_color", color}, {"depth", depth}, {"normal", normal}};
  mat.self_shadow = true;
  mat.depth_write = true;
  s.materials.push_back(mat);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(directional_light("sun", {-0.6f, -0.7f, -0.4f}, glm::vec3(1.5f)));
  // 45 degrees between the view direction and the plane's normal.
  s.cameras.push_back(look_at("45deg", {0.0f, 1.25f, 1.25f}, glm::vec3(0.0f), 50.0f, 20.0f));
  s.ambient = glm::vec3(0.08f);
  s.background = glm::vec4(0.05f, 0.06f, 0.08f, 1.0f);
  return s;
}

Result<Scene> make_plane() {
  TexturePtr depth, color;
  make_bricks(512, depth, color);
  return relief_quad_scene("plane", 8.0f, "bricks", depth, color, 0.06f);
}

// The pattern's colour follows its depth (pale at the top, dark blue at the bottom) with a faint
// 16-texel checker, so a missed wall shows as floor colour where the wall should be.
TexturePtr make_pattern_color(const Texture& depth) {
  const int n = depth.width(0);
  std::vector<uint8_t> c(size_t(n) * n * 4);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const float d = depth.fetch_r(0, x, y);
      const float check = ((x / 16 + y / 16) & 1) ? 1.0f : 0.88f;
      const glm::vec3 top(0.86f, 0.78f, 0.60f), deep(0.10f, 0.16f, 0.36f);
      const glm::vec3 rgb = (top + (deep - top) * d) * check;
      const size_t i = (size_t(y) * n + x) * 4;
      for (int k = 0; k < 3; ++k) c[i + k] = static_cast<uint8_t>(std::lround(rgb[k] * 255.0f));
      c[i + 3] = 255;
    }
  auto ct = std::make_shared<Texture>(TexFormat::kRGBA8, n, n, c.data(), ColorSpace::kSRGB);
  ct->generate_mips(MipReduce::kAverage);
  return ct;
}

Result<Scene> make_pattern() {
  auto depth = std::make_shared<Texture>(make_pattern_depth(kPatternSize));
  return relief_quad_scene("pattern", 4.0f, "pattern", depth, make_pattern_color(*depth), 0.05f);
}

}  // namespace

Texture make_pattern_depth(int size) {
  CHECK(size >= 16 && size % 16 == 0);
  std::vector<float> d(size_t(size) * size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) d[size_t(y) * size + x] = pattern_depth_at(x, y, size);
  Texture t = Texture::from_floats(TexFormat::kR8, size, size, d.data());
  t.generate_mips(MipReduce::kAverage);
  return t;
}

const std::vector<BuiltinSceneInfo>& builtin_scenes() {
  static const std::vector<BuiltinSceneInfo> scenes = {
      {"plane", "one quad with a procedural brick depth map and its normal map, camera at 45 deg"},
      {"room",
       "relief room: relief walls, floor, columns and sphere, one shadow-casting spot light"},
      {"pattern",
       "the same quad with smooth and sharp features and one-texel walls (4 x 4 tiles "
       "of 256 x 256), where searches that step over thin structures show"},
      {"sphere", "relief bumps on a uv sphere, relief_quadric (curved silhouette)"},
      {"cylinder", "relief bumps on an open cylinder, relief_quadric (curved silhouette)"},
      {"torus", "relief bumps on a torus seen from above: its inner half is a saddle region"},
      {"teapot", "relief bumps on the Utah teapot (32 Bezier patches), relief_quadric"},
      {"bending", "a relief-mapped cylinder bent by two joints (skinned, animated: --frames 0-47)"},
      {"interpenetration",
       "spheres through a relief floor and two coincident relief cylinders (depth correction)"},
      {"teatime", "a relief teapot on a relief floor under a shadow-casting spot light"},
      {"impostor", "a sphere as dual-depth relief textures on one quad, relief_dual (impostor)"},
      {"materials",
       "four relief spheres lit by the glTF metallic-roughness BRDF (smooth and rough metal and "
       "dielectric) on a relief floor of rough and polished tiles, spot light in candela"},
      {"fur", "a fur-covered sphere (a generated fur field, steep_parallax, 32 steps), one sun"},
      {"grass",
       "a grass-covered ground (a generated grass field, steep_parallax) seen 15 deg above it"},
  };
  return scenes;
}

const char* default_scene_name() {
  return "room";
}

TexturePtr texture_level0(const Texture& t) {
  std::vector<float> v(static_cast<size_t>(t.width(0)) * t.height(0));
  for (int y = 0; y < t.height(0); ++y)
    for (int x = 0; x < t.width(0); ++x)
      v[static_cast<size_t>(y) * t.width(0) + x] = t.fetch_r(0, x, y);
  return std::make_shared<Texture>(
      Texture::from_floats(t.format(), t.width(0), t.height(0), v.data()));
}

Result<Scene> make_builtin_scene(const std::string& name) {
  if (name == "plane") return make_plane();
  if (name == "room") return make_room_scene();
  if (name == "pattern") return make_pattern();
  if (name == "bending") return make_bending_scene();
  if (name == "interpenetration") return make_interpenetration_scene();
  if (name == "teatime") return make_teatime_scene();
  if (name == "impostor") return make_impostor_scene();
  if (name == "materials") return make_materials_scene();
  if (name == "fur") return make_fur_scene();
  if (name == "grass") return make_grass_scene();
  if (name == "sphere" || name == "cylinder" || name == "torus" || name == "teapot")
    return make_curved_scene(name);
  std::string known;
  for (const auto& s : builtin_scenes()) known += (known.empty() ? "" : ", ") + s.name;
  return Status::error("unknown scene '" + name + "' (built-in scenes: " + known + ")");
}

}  // namespace relief
