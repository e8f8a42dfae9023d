// Height fields and views of the sweep (sweep/sweep.h): the built-in maps, depth images, the
// orthographic view of a field at one angle, and the technique settings taken from the registry.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "bake/normal_map.h"
#include "plugins/registry.h"
#include "plugins/relief_shell.h"
#include "scene/builtin.h"
#include "scene/image_io.h"
#include "scene/mesh_prep.h"
#include "sweep/sweep.h"

namespace relief::sweep {
namespace {

// Pale at the top, dark blue at the bottom (as the pattern scene): a wrong hit shows in colour.
TexturePtr depth_colour(const Texture& depth) {
  const int w = depth.width(0), h = depth.height(0);
  std::vector<uint8_t> c(static_cast<size_t>(w) * h * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float d = depth.fetch_r(0, x, y);
      const glm::vec3 top(0.86f, 0.78f, 0.60f), deep(0.10f, 0.16f, 0.36f);
      const glm::vec3 rgb = top + (deep - top) * d;
      const size_t i = (static_cast<size_t>(y) * w + x) * 4;
      for (int k = 0; k < 3; ++k) c[i + k] = static_cast<uint8_t>(std::lround(rgb[k] * 255.0f));
      c[i + 3] = 255;
    }
  auto t = std::make_shared<Texture>(TexFormat::kRGBA8, w, h, c.data(), ColorSpace::kSRGB);
  t->generate_mips(MipReduce::kAverage);
  return t;
}

}  // namespace

Result<std::vector<Field>> builtin_fields() {
  std::vector<Field> out;
  for (const auto& [scene, name] :
       {std::pair{"plane", "bricks"}, std::pair{"pattern", "pattern"}}) {
    Result<Scene> s = make_builtin_scene(scene);
    if (!s.ok()) return s.status();
    Result<Field> f = field_of_material(*s, 0);
    if (!f.ok()) return f.status();
    f->name = name;
    out.push_back(std::move(f).value());
  }
  return out;
}

Result<Field> field_of_material(const Scene& scene, int material) {
  const Material& m = scene.materials.at(material);
  auto depth = m.textures.find("depth");
  if (depth == m.textures.end() || !depth->second)
    return Status::error("material '" + m.name + "' has no depth texture");
  Field f;
  f.name = m.name;
  Material& fm = f.material;
  fm.name = m.name;
  fm.sampler = m.sampler;
  fm.self_shadow = true;
  fm.depth_write = true;
  fm.textures["depth"] = texture_level0(*depth->second);
  auto dsc = m.params.find("depth_scale");
  fm.params["depth_scale"] = dsc != m.params.end() ? dsc->second : kDepthScaleSpec.default_value;
  auto color = m.textures.find("base_color");
  fm.textures["base_color"] =
      color != m.textures.end() && color->second ? color->second : depth_colour(f.depth());
  auto normal = m.textures.find("normal");
  if (normal != m.textures.end() && normal->second) {
    fm.textures["normal"] = normal->second;
  } else {
    auto n = std::make_shared<Texture>(normal_map_from_depth(f.depth(), f.depth_scale(), true));
    n->generate_mips(MipReduce::kAverage);
    fm.textures["normal"] = n;
  }
  // the scene's first directional light, else the built-in scenes' sun
  const Light* sun = nullptr;
  for (const Light& l : scene.lights)
    if (!sun && l.type == LightType::kDirectional) sun = &l;
  if (sun) {
    f.sun = *sun;
    f.ambient = scene.ambient;
    f.background = scene.background;
  } else {
    Result<Scene> plane = make_builtin_scene("plane");
    if (!plane.ok()) return plane.status();
    f.sun = plane->lights.at(0);
  }
  f.sun.casts_shadows = false;
  return f;
}

Result<Field> field_from_file(const std::string& path, float depth_scale, bool height) {
  if (!(depth_scale > 0.0f && depth_scale <= 1.0f))
    return Status::usage("--depth-scale: expected a value in (0, 1]");
  TextureLoadOptions lo;
  lo.first_channel_only = true;
  lo.height_to_depth = height;
  lo.unit_range = true;
  Result<Texture> t = load_texture(path, lo);
  if (!t.ok()) return t.status();
  Scene holder;  // a material with only the depth map: colour and normal map are derived
  Material m;
  m.name = path.substr(path.find_last_of('/') + 1);
  m.params["depth_scale"] = depth_scale;
  m.textures["depth"] = std::make_shared<Texture>(std::move(t).value());
  holder.materials.push_back(m);
  return field_of_material(holder, 0);
}

std::vector<std::string> sweep_techniques() {
  std::vector<std::string> names;
  for (const PluginDescriptor* p : PluginRegistry::global().all())
    for (int s = 0; s < p->num_textures; ++s)
      if (std::strcmp(p->textures[s].name, "depth") == 0 && p->textures[s].required)
        names.push_back(p->name);
  return names;
}

std::vector<Setting> settings_for(const PluginDescriptor& plugin, const std::vector<int>& steps) {
  std::vector<Setting> out;
  const int binary = param_index(plugin, "binary_steps");
  const bool has_steps = param_index(plugin, "steps") >= 0;
  if (!has_steps) {
    out.push_back({plugin.name, {}, plugin.name, 0});
    return out;
  }
  for (int n : steps) {
    Setting s{plugin.name, {{"steps", std::to_string(n)}}, "", n};
    if (param_index(plugin, "min_steps") >= 0) s.params["min_steps"] = std::to_string(n);
    s.label = std::string(plugin.name) + " " + std::to_string(n);
    if (binary >= 0)
      s.label += "+" + std::to_string(static_cast<int>(plugin.params[binary].default_value));
    out.push_back(std::move(s));
  }
  return out;
}

namespace {

struct ViewGeometry {
  glm::dvec3 dir;                          // the view direction (eye to surface), world
  glm::dvec3 up;                           // camera up, perpendicular to dir
  glm::dvec3 across;                       // the surface's horizontal direction across the frame
  double half_height = 0.0, length = 0.0;  // ortho half height; footprint along the view, uv
};

// The plane is y = 0 with u = x and v = z (one uv unit per world unit), normal +y.
ViewGeometry geometry(double angle_deg, int width, int height) {
  const double th = glm::radians(std::clamp(angle_deg, 0.0, 89.9));
  const double az = glm::radians(kAzimuthDeg);
  const glm::dvec3 h(std::sin(az), 0.0, std::cos(az)), n(0.0, 1.0, 0.0);
  ViewGeometry g;
  g.dir = std::sin(th) * h - std::cos(th) * n;
  g.up = std::cos(th) * h + std::sin(th) * n;
  g.across = glm::normalize(glm::cross(g.dir, g.up));
  const double aspect = static_cast<double>(width) / height;
  g.half_height = 0.5 / aspect;  // one uv tile across the frame
  g.length = 2.0 * g.half_height / std::cos(th);
  return g;
}

}  // namespace

glm::dvec2 view_ray_step(const Field& field, double angle_deg) {
  const ViewGeometry g = geometry(angle_deg, 1, 1);
  // tangent space (T, B, N) = (x, z, y)
  const glm::dvec3 v(g.dir.x, g.dir.z, g.dir.y);
  const double s = static_cast<double>(field.depth_scale()) / std::max(-v.z, 1e-4);
  return {v.x * s, v.y * s};
}

Scene view_scene(const Field& field, double angle_deg, int width, int height) {
  const ViewGeometry g = geometry(angle_deg, width, height);
  Scene s;
  s.name = field.name;
  // a quad centred under the view, large enough for the footprint at any azimuth
  const float half = static_cast<float>(0.5 * std::hypot(g.length, 1.0) + 1.0);
  Mesh m;
  m.name = "quad";
  m.positions = {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
  m.normals.assign(4, glm::vec3(0, 1, 0));
  m.uvs = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
  m.indices = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +y
  prepare_mesh(m);
  s.meshes.push_back(std::move(m));
  s.materials.push_back(field.material);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(field.sun);
  Camera cam;
  cam.name = "sweep";
  const double dist = g.length + 2.0;
  cam.position = glm::vec3(-g.dir * dist);
  cam.target = glm::vec3(0.0f);
  cam.up = glm::vec3(g.up);
  cam.orthographic = true;
  cam.ortho_half_height = static_cast<float>(g.half_height);
  cam.znear = 0.05f;
  cam.zfar = static_cast<float>(2.0 * dist + 2.0);
  s.cameras.push_back(cam);
  s.ambient = field.ambient;
  s.background = field.background;
  return s;
}

}  // namespace relief::sweep
