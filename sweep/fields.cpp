// Height fields and views of the sweep (sweep/sweep.h): the built-in maps, depth images, the
// orthographic view of a field at one angle, and the technique settings taken from the registry.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "bake/normal_map.h"
#include "builtin/builtin.h"
#include "plugins/registry.h"
#include "plugins/relief_shell.h"
#include "render/derived_maps.h"
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

// A deterministic hash of (i, j, salt) to [0, 1) (lowbias32), the same on every platform.
double hash01(uint32_t i, uint32_t j, uint32_t salt) {
  uint32_t x = i * 0x9E3779B1u ^ (j + 0x7F4A7C15u) * 0x85EBCA77u ^ salt * 0xC2B2AE3Du;
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return static_cast<double>(x) / 4294967296.0;
}

// Periodic distance between texel coordinates a and b on a ring of n texels.
double ring_dist(double a, double b, int n) {
  double d = std::fabs(a - b);
  return std::min(d, n - d);
}

}  // namespace

Result<Texture> make_generated_depth(const std::string& name, int size) {
  if (size < 16 || (size & (size - 1)) != 0)
    return Status::usage(name + ": generated field size must be a power of two >= 16");
  const int n = size;
  std::vector<float> d(static_cast<size_t>(n) * n, 1.0f);
  auto at = [&](int i, int j) -> float& { return d[static_cast<size_t>(j) * n + i]; };
  if (name == "thin") {
    // tests/bake/field_fixture.h thin_walls on a depth-1 floor: walls every 8 texels,
    // 3 % of the floor texels one-texel pillars reaching 0 to 0.1
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        float v = 1.0f;
        if (i % 8 == 0 || j % 8 == 0)
          v = 0.0f;
        else if (hash01(i, j, 1) < 0.03)
          v = static_cast<float>(0.1 * hash01(i, j, 2));
        at(i, j) = v;
      }
  } else if (name == "spikes") {
    // one spike per 32 x 32 cell, centre jittered by up to 6 texels; cones (round) and square
    // pyramids alternate at random; base radius 6 to 12 texels, flat tip 1 to 3 texels wide
    const int cell = 32, cells = n / cell > 0 ? n / cell : 1;
    struct Spike {
      double x, y, r, tip;
      bool cone;
    };
    std::vector<Spike> spikes;
    for (int cj = 0; cj < cells; ++cj)
      for (int ci = 0; ci < cells; ++ci) {
        Spike s;
        s.x = ci * cell + cell * 0.5 + (hash01(ci, cj, 3) - 0.5) * 12.0;
        s.y = cj * cell + cell * 0.5 + (hash01(ci, cj, 4) - 0.5) * 12.0;
        s.r = 6.0 + 6.0 * hash01(ci, cj, 5);
        s.tip = 0.5 * (1 + static_cast<int>(hash01(ci, cj, 6) * 3.0));  // half width 0.5..1.5
        s.cone = hash01(ci, cj, 7) < 0.5;
        spikes.push_back(s);
      }
    for (const Spike& s : spikes) {  // each over its own footprint (periodic)
      const int r = static_cast<int>(std::ceil(s.r)) + 1;
      for (int y = static_cast<int>(s.y) - r; y <= static_cast<int>(s.y) + r; ++y)
        for (int x = static_cast<int>(s.x) - r; x <= static_cast<int>(s.x) + r; ++x) {
          const int i = ((x % n) + n) % n, j = ((y % n) + n) % n;
          const double dx = ring_dist(i + 0.5, s.x, n), dy = ring_dist(j + 0.5, s.y, n);
          const double dist = s.cone ? std::hypot(dx, dy) : std::max(dx, dy);
          const float v = static_cast<float>(std::clamp((dist - s.tip) / (s.r - s.tip), 0.0, 1.0));
          at(i, j) = std::min(at(i, j), v);
        }
    }
  } else if (name == "ramp") {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        at(i, j) = static_cast<float>(0.1 + 0.6 * (i + 0.5) / n + (j >= n / 2 ? 0.3 : 0.0));
  } else {
    return Status::usage("'" + name + "' is not a generated field (thin, spikes, ramp)");
  }
  return Texture::from_floats(TexFormat::kR32F, n, n, d.data());
}

const std::vector<std::string>& builtin_field_names() {
  static const std::vector<std::string> names = {"bricks", "pattern", "thin", "spikes",
                                                 "ramp",   "fur",     "grass"};
  return names;
}

Result<Field> builtin_field(const std::string& name) {
  // the maps of built-in scenes: `plane`'s bricks, `pattern`, and the generated fur and grass
  // fields of `fur` and `grass` (bake/fur_field.h)
  if (name == "bricks" || name == "pattern" || name == "fur" || name == "grass") {
    Result<Scene> s = make_builtin_scene(name == "bricks" ? "plane" : name);
    if (!s.ok()) return s.status();
    Result<Field> f = field_of_material(*s, 0);
    if (!f.ok()) return f.status();
    f->name = name;
    return f;
  }
  return generated_field(name, 256);
}

Result<Field> generated_field(const std::string& name, int size) {
  Result<Texture> t = make_generated_depth(name, size);
  if (!t.ok()) return t.status();
  Scene holder;
  Material m;
  m.name = name;
  m.params["depth_scale"] = 0.05f;
  m.textures["depth"] = std::make_shared<Texture>(std::move(t).value());
  holder.materials.push_back(m);
  return field_of_material(holder, 0);
}

Result<std::vector<Field>> builtin_fields() {
  std::vector<Field> out;
  for (const std::string& name : builtin_field_names()) {
    Result<Field> f = builtin_field(name);
    if (!f.ok()) return f.status();
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
  if (depth->second->levels() > 1) {
    f.depth_mips = depth->second;
  } else {  // no chain: the average one a scene loader makes for a mipmapped sampler
    auto mips = std::make_shared<Texture>(*fm.textures["depth"]);
    mips->generate_mips(MipReduce::kAverage);
    f.depth_mips = mips;
  }
  auto dsc = m.params.find("depth_scale");
  fm.params["depth_scale"] = dsc != m.params.end() ? dsc->second : kDepthScaleSpec.default_value;
  auto color = m.textures.find("base_color");
  fm.textures["base_color"] =
      color != m.textures.end() && color->second ? color->second : depth_colour(f.depth());
  auto normal = m.textures.find("normal");
  if (normal != m.textures.end() && normal->second) {
    fm.textures["normal"] = normal->second;
  } else if (derives_normal_map(m, "normal")) {  // a file's: the one its renders read
    Result<TexturePtr> n = derived_normal_map(m);
    if (!n.ok()) return n.status();
    fm.textures["normal"] = *n;
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

std::vector<Setting> settings_for(const PluginDescriptor& plugin, const std::vector<int>& steps,
                                  int binary_steps, const std::vector<std::string>& search_lods) {
  std::vector<Setting> out;
  const int binary = param_index(plugin, "binary_steps");
  // The swept count: search steps, or the layers of a technique drawn as shells (`shells`).
  const char* count = param_index(plugin, "steps") >= 0    ? "steps"
                      : param_index(plugin, "layers") >= 0 ? "layers"
                                                           : nullptr;
  if (!count) {
    out.push_back({plugin.name, {}, plugin.name, 0});
  } else {
    for (int n : steps) {
      Setting s{plugin.name, {{count, std::to_string(n)}}, "", n};
      if (param_index(plugin, "min_steps") >= 0) s.params["min_steps"] = std::to_string(n);
      s.label = std::string(plugin.name) + " " + std::to_string(n);
      if (binary >= 0 && binary_steps >= 0) {
        s.params["binary_steps"] = std::to_string(binary_steps);
        s.label += "+" + std::to_string(binary_steps);
      } else if (binary >= 0) {
        s.label += "+" + std::to_string(static_cast<int>(plugin.params[binary].default_value));
      }
      out.push_back(std::move(s));
    }
  }
  if (search_lods.empty() || param_index(plugin, "lod") < 0) return out;
  std::vector<Setting> with_lods;
  for (const std::string& lod : search_lods)
    for (Setting s : out) {
      s.params["lod"] = lod;
      if (lod != kSearchLodDefault) s.label += " lod=" + lod;
      with_lods.push_back(std::move(s));
    }
  return with_lods;
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

glm::dvec2 view_light_step(const Field& field, double* lz) {
  // toward the sun, in tangent space (T, B, N) = (x, z, y) as view_ray_step
  const glm::dvec3 w = -glm::normalize(glm::dvec3(field.sun.direction));
  const glm::dvec3 l(w.x, w.z, w.y);
  if (lz) *lz = l.z;
  const double s = static_cast<double>(field.depth_scale()) / std::max(l.z, 1e-4);
  return {l.x * s, l.y * s};
}

double half_texel_depth(const Field& field) {
  return 0.5 / (static_cast<double>(field.depth().width(0)) * field.depth_scale());
}

Scene view_scene(const Field& field, double angle_deg, int width, int height, bool as_rendered) {
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
  if (as_rendered && field.depth_mips) s.materials.back().textures["depth"] = field.depth_mips;
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
