// Tests for scene/gltf: round trips of built-in scenes (.gltf and .glb, the shipped
// scenes/plane.gltf against the built-in), node and texture transforms at known pixels, lights
// and cameras, and bad input (one line naming the file and the JSON pointer).
#include "scene/gltf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "apps/scene_source.h"
#include "builtin/builtin.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/animation.h"
#include "scene/image_io.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

class Gltf : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::fresh_test_dir("relief_gltf"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  fs::path dir_;
};

// ---- comparing scenes ----
template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool same_texture(const Texture& a, const Texture& b) {
  if (a.format() != b.format() || a.color_space() != b.color_space() || a.levels() != b.levels())
    return false;
  for (int l = 0; l < a.levels(); ++l)
    if (a.width(l) != b.width(l) || a.height(l) != b.height(l) ||
        a.level(l).data != b.level(l).data)
      return false;
  return true;
}

void expect_same_scene(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (size_t i = 0; i < a.meshes.size(); ++i) {
    SCOPED_TRACE("mesh " + std::to_string(i));
    const Mesh &x = a.meshes[i], &y = b.meshes[i];
    EXPECT_TRUE(same_bytes(x.positions, y.positions));
    EXPECT_TRUE(same_bytes(x.normals, y.normals));
    EXPECT_TRUE(same_bytes(x.uvs, y.uvs));
    EXPECT_TRUE(same_bytes(x.tangents, y.tangents));
    EXPECT_TRUE(same_bytes(x.tile_scale, y.tile_scale));
    EXPECT_TRUE(same_bytes(x.quadric, y.quadric));
    EXPECT_EQ(x.indices, y.indices);
  }
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    SCOPED_TRACE("material " + std::to_string(i));
    const Material &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.technique, y.technique);
    EXPECT_EQ(x.params, y.params);
    ASSERT_EQ(x.textures.size(), y.textures.size());
    for (const auto& [slot, t] : x.textures) {
      SCOPED_TRACE("slot " + slot);
      ASSERT_TRUE(y.textures.count(slot));
      EXPECT_TRUE(same_texture(*t, *y.textures.at(slot)));
    }
    EXPECT_EQ(x.base_color, y.base_color);
    EXPECT_EQ(x.uv_scale, y.uv_scale);
    EXPECT_EQ(x.uv_offset, y.uv_offset);
    EXPECT_EQ(x.sampler.filter, y.sampler.filter);
    EXPECT_EQ(x.sampler.wrap_u, y.sampler.wrap_u);
    EXPECT_EQ(x.sampler.wrap_v, y.sampler.wrap_v);
    EXPECT_EQ(x.specular, y.specular);
    EXPECT_EQ(x.shininess, y.shininess);
    EXPECT_EQ(x.double_sided, y.double_sided);
    EXPECT_EQ(x.self_shadow, y.self_shadow);
    EXPECT_EQ(x.depth_write, y.depth_write);
    EXPECT_EQ(x.silhouette, y.silhouette);
    EXPECT_EQ(x.casts_shadow, y.casts_shadow);
    EXPECT_EQ(x.receives_shadow, y.receives_shadow);
  }
  ASSERT_EQ(a.instances.size(), b.instances.size());
  for (size_t i = 0; i < a.instances.size(); ++i) {
    EXPECT_EQ(a.instances[i].mesh, b.instances[i].mesh);
    EXPECT_EQ(a.instances[i].material, b.instances[i].material);
    EXPECT_EQ(a.instances[i].transform, b.instances[i].transform);
  }
  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    SCOPED_TRACE("light " + std::to_string(i));
    const Light &x = a.lights[i], &y = b.lights[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    if (x.type != LightType::kDirectional) {
      EXPECT_EQ(x.position, y.position);
    }
    for (int k = 0; k < 3 && x.type != LightType::kPoint; ++k) {
      // The loaded direction is the node's unit vector rounded to float (within one ulp of it),
      // or, from our export, the exact bits its RELIEF_relief_mapping `direction` kept.
      EXPECT_TRUE(x.direction[k] == y.direction[k] ||
                  std::abs(glm::normalize(x.direction)[k] - y.direction[k]) <=
                      std::nextafter(std::abs(y.direction[k]), 2.0f) - std::abs(y.direction[k]))
          << x.direction[k] << " vs " << y.direction[k];
    }
    EXPECT_EQ(x.color * x.intensity, y.color * y.intensity);
    EXPECT_EQ(x.range, y.range);
    if (x.type == LightType::kSpot) {
      EXPECT_EQ(x.inner_cone_deg, y.inner_cone_deg);
      EXPECT_EQ(x.outer_cone_deg, y.outer_cone_deg);
    }
    EXPECT_EQ(x.casts_shadows, y.casts_shadows);
    EXPECT_EQ(x.shadow_resolution, y.shadow_resolution);
  }
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    SCOPED_TRACE("camera " + std::to_string(i));
    const Camera &x = a.cameras[i], &y = b.cameras[i];
    EXPECT_EQ(x.name, y.name);
    // The orientation goes through a quaternion and the target is re-derived on the view ray, so
    // the view matrix agrees to float rounding, not to the bit (exactly for axis-aligned views).
    const glm::mat4 vx = x.view(), vy = y.view();
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) EXPECT_NEAR(vx[c][r], vy[c][r], 2e-6f) << c << "," << r;
    EXPECT_EQ(x.position, y.position);
    EXPECT_EQ(x.projection(16.0f / 9.0f), y.projection(16.0f / 9.0f));
  }
  EXPECT_EQ(a.ambient, b.ambient);
  EXPECT_EQ(a.background, b.background);
}

// Renders on the CPU and returns colour and depth.
Framebuffer render(const Scene& s, int w, int h, int camera = 0) {
  RenderOptions opt;
  opt.width = w;
  opt.height = h;
  opt.camera = camera;
  // the files without lights here are lit by their ambient colour (1: the texels as they are),
  // not by the studio environment a scene without lights gets by default
  opt.studio_environment = false;
  Result<Plan> plan = make_plan(s, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return {};
  Result<RenderResult> r = make_cpu_backend({.threads = 2})->render(s, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer : Framebuffer{};
}

struct PixelDiff {
  size_t pixels = 0;     // colour pixels that differ in any bit
  float max_abs = 0.0f;  // largest channel difference
};
PixelDiff diff(const Framebuffer& a, const Framebuffer& b) {
  PixelDiff d;
  for (size_t i = 0; i < a.color.pixels.size() && i < b.color.pixels.size(); ++i) {
    const glm::vec4 e = glm::abs(a.color.pixels[i] - b.color.pixels[i]);
    d.pixels += std::memcmp(&a.color.pixels[i], &b.color.pixels[i], sizeof(glm::vec4)) != 0;
    d.max_abs = std::max({d.max_abs, e.r, e.g, e.b, e.a});
  }
  return d;
}

void expect_same_pixels(const Framebuffer& a, const Framebuffer& b) {
  ASSERT_EQ(a.color.width, b.color.width);
  ASSERT_EQ(a.color.height, b.color.height);
  ASSERT_FALSE(a.color.pixels.empty());
  size_t differ = 0;
  for (size_t i = 0; i < a.color.pixels.size(); ++i)
    differ += std::memcmp(&a.color.pixels[i], &b.color.pixels[i], sizeof(a.color.pixels[i])) != 0;
  EXPECT_EQ(differ, 0u) << "colour pixels differ";
  EXPECT_TRUE(same_bytes(a.depth.values, b.depth.values)) << "depth differs";
}

// Compares a built-in scene with its glTF form, scene and pixels. Light directions and camera
// orientations are the quantities that go through a rounding (quaternions, back to float): they
// are checked to float rounding, the frame difference they make is printed, and with the
// built-in's bits put back the frames are bit-identical.
void expect_round_trip(const Scene& builtin, Scene loaded) {
  expect_same_scene(builtin, loaded);
  const PixelDiff d = diff(render(builtin, 320, 180), render(loaded, 320, 180));
  std::printf("%s through glTF at 320x180: %zu pixels differ, max channel difference %g\n",
              builtin.name.c_str(), d.pixels, d.max_abs);
  for (size_t i = 0; i < loaded.lights.size(); ++i)
    loaded.lights[i].direction = builtin.lights[i].direction;
  for (size_t i = 0; i < loaded.cameras.size(); ++i) {
    loaded.cameras[i].target = builtin.cameras[i].target;
    loaded.cameras[i].up = builtin.cameras[i].up;
  }
  expect_same_pixels(render(builtin, 320, 180), render(loaded, 320, 180));
}

// The normal maps a file asks for from its depth maps (render/derived_maps.h, made when a frame is
// planned) put in its materials, so that it compares with a built-in scene that holds them.
void add_derived_normal_maps(Scene& s) {
  for (Material& m : s.materials) {
    if (!derives_normal_map(m, "normal")) continue;
    Result<TexturePtr> normal = derived_normal_map(m);
    ASSERT_TRUE(normal.ok()) << normal.status().message();
    m.textures["normal"] = *normal;
  }
}

// Loads `file` (first written from the built-in scene when `save_first`) and compares it with
// the built-in scene `name`.
void expect_builtin_file(const std::string& name, const std::string& file, bool save_first) {
  SCOPED_TRACE(file);
  Result<Scene> builtin = make_builtin_scene(name);
  ASSERT_TRUE(builtin.ok());
  if (save_first) {
    ASSERT_TRUE(save_gltf(*builtin, file).ok());
  }
  Result<Scene> loaded = load_scene(file);
  ASSERT_TRUE(loaded.ok()) << loaded.status().message();
  add_derived_normal_maps(*loaded);
  expect_round_trip(*builtin, *loaded);
}

TEST_F(Gltf, BuiltinPlaneRoundTripsThroughGltf) {
  expect_builtin_file("plane", path("plane.gltf"), true);
}

TEST_F(Gltf, BuiltinPlaneRoundTripsThroughGlb) {
  expect_builtin_file("plane", path("plane.glb"), true);
  // One self-contained file: images and buffer embedded.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

// scenes/NAME.gltf is `relief export NAME -o scenes/NAME.gltf`; when a built-in scene changes,
// run that again. plane must be there; every other shipped built-in is checked too.
TEST_F(Gltf, ShippedScenesRenderLikeTheBuiltins) {
  const std::string dir = std::string(RELIEF_SOURCE_DIR) + "/scenes/";
  ASSERT_TRUE(fs::exists(dir + "plane.gltf"));
  for (const BuiltinSceneInfo& info : builtin_scenes())
    if (fs::exists(dir + info.name + ".gltf"))
      expect_builtin_file(info.name, dir + info.name + ".gltf", false);
}

// ---- hand-made files ----

// A glTF document under construction: a JSON object and one binary buffer written beside it.
struct Doc {
  json j = json::object();
  std::vector<uint8_t> bin;

  int view(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}});
    const uint8_t* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    return static_cast<int>(j["bufferViews"].size()) - 1;
  }
  template <class T>
  int accessor(const std::vector<T>& v, int components, int component_type, const char* type) {
    const int bv = view(v.data(), v.size() * sizeof(T));
    j["accessors"].push_back({{"bufferView", bv},
                              {"componentType", component_type},
                              {"count", v.size() / components},
                              {"type", type}});
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  std::string write(const fs::path& dir, const std::string& name) {
    json out = j;
    out["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(dir / (name + ".gltf")) << out.dump(1);
    return (dir / (name + ".gltf")).string();
  }
};

constexpr int kFloatType = 5126, kUShortType = 5123;
const glm::vec4 kQuadrant[4] = {{1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, 1, 1}, {1, 1, 1, 1}};

// One quad in its local xy plane, facing +z, uv (0, 0) at its top-left corner (-0.5, 0.5), with a
// 2x2 texture (red, green / blue, white; nearest, clamped) under node 1 (rotated 90 degrees about
// z, scaled 2x) under node 0 (moved by +1 along x); an orthographic camera 10 units up +z, 4
// units tall; ambient 1 and no light, so a pixel shows its texel's colour.
Doc quad_doc(const fs::path& dir) {
  Image tex(2, 2);
  for (int i = 0; i < 4; ++i) tex.at(i % 2, i / 2) = kQuadrant[i];
  EXPECT_TRUE(write_image((dir / "quadrants.png").string(), tex).ok());
  Doc d;
  json& j = d.j;
  j["asset"] = {{"version", "2.0"}};
  const std::vector<float> pos = {-0.5f, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f, -0.5f, 0, -0.5f, -0.5f, 0};
  const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 1};
  const std::vector<uint16_t> idx = {0, 3, 2, 0, 2, 1};  // counter-clockwise seen from +z
  const int p = d.accessor(pos, 3, kFloatType, "VEC3");
  j["accessors"][p]["min"] = {-0.5, -0.5, 0};
  j["accessors"][p]["max"] = {0.5, 0.5, 0};
  const int n = d.accessor(nrm, 3, kFloatType, "VEC3");
  const int t = d.accessor(uv, 2, kFloatType, "VEC2");
  const int i = d.accessor(idx, 1, kUShortType, "SCALAR");
  j["meshes"] = json::array(
      {{{"primitives",
         json::array({{{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}},
                       {"indices", i},
                       {"material", 0}}})}}});
  j["images"] = json::array({{{"uri", "quadrants.png"}}});
  j["samplers"] =
      json::array({{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}});
  j["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  j["materials"] = json::array(
      {{{"name", "quadrants"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  const double s = std::sqrt(0.5);
  j["nodes"] = json::array({{{"translation", {1, 0, 0}}, {"children", {1}}},
                            {{"mesh", 0}, {"rotation", {0, 0, s, s}}, {"scale", {2, 2, 1}}},
                            {{"camera", 0}, {"translation", {0, 0, 10}}, {"name", "top"}}});
  j["cameras"] =
      json::array({{{"type", "orthographic"},
                    {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.1}, {"zfar", 100}}}}});
  j["scenes"] = json::array({{{"nodes", {0, 2}}}});
  j["scene"] = 0;
  j["extensions"]["RELIEF_relief_mapping"] = {{"ambient", {1, 1, 1}}, {"background", {0, 0, 0, 1}}};
  j["extensionsUsed"] = {"RELIEF_relief_mapping"};
  return d;
}

// The colour the quad shows at world (x, y), computed from the node transforms above and a
// KHR_texture_transform (offset, rotation, scale) written out as glTF defines it.
glm::vec4 expected_at(double x, double y, glm::dvec2 offset, double rotation, glm::dvec2 scale) {
  // world = T(1,0,0) R_z(90) S(2,2,1) local  =>  local = ( y / 2, -(x - 1) / 2 )
  const double lx = y / 2.0, ly = -(x - 1.0) / 2.0;
  if (std::abs(lx) >= 0.5 || std::abs(ly) >= 0.5) return {0, 0, 0, 1};  // background
  const double u = lx + 0.5, v = 0.5 - ly;
  const double c = std::cos(rotation), sn = std::sin(rotation);
  const double tu = c * scale.x * u + sn * scale.y * v + offset.x;
  const double tv = -sn * scale.x * u + c * scale.y * v + offset.y;
  const int tx = std::clamp(static_cast<int>(std::floor(tu * 2)), 0, 1);
  const int ty = std::clamp(static_cast<int>(std::floor(tv * 2)), 0, 1);
  return kQuadrant[ty * 2 + tx];
}

// Renders `file` at 64x64 (the view spans x, y in [-2, 2]) and compares the pixels whose centres
// are at least 0.1 from any quadrant or quad edge (where nearest sampling is unambiguous).
void expect_quadrant_pixels(const std::string& file, glm::dvec2 offset, double rotation,
                            glm::dvec2 scale) {
  Result<Scene> s = load_scene(file);
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Framebuffer fb = render(*s, 64, 64);
  ASSERT_EQ(fb.color.width, 64);
  int checked = 0, on_quad = 0;
  for (int py = 0; py < 64; ++py)
    for (int px = 0; px < 64; ++px) {
      const double x = -2.0 + (px + 0.5) * 4.0 / 64, y = 2.0 - (py + 0.5) * 4.0 / 64;
      bool clear = true;
      for (double dx : {-0.1, 0.0, 0.1})
        for (double dy : {-0.1, 0.0, 0.1})
          clear &= expected_at(x + dx, y + dy, offset, rotation, scale) ==
                   expected_at(x, y, offset, rotation, scale);
      if (!clear) continue;
      const glm::vec4 want = expected_at(x, y, offset, rotation, scale);
      const glm::vec4 got = fb.color.at(px, py);
      ++checked;
      on_quad += want != glm::vec4(0, 0, 0, 1);
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(got[c], want[c], 1e-6) << "pixel " << px << "," << py << " channel " << c;
    }
  EXPECT_GT(on_quad, 400);  // the quad covers 2x2 of the 4x4 view: a quarter of the pixels
  EXPECT_GT(checked, 3000);
}

TEST_F(Gltf, NodeTransformsPlaceTheQuad) {
  expect_quadrant_pixels(quad_doc(dir_).write(dir_, "quad"), {0, 0}, 0.0, {1, 1});
}

TEST_F(Gltf, TextureTransformOffsetAndScale) {
  Doc d = quad_doc(dir_);
  d.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
      {"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"scale", {0.5, 0.5}}}}};
  const std::string file = d.write(dir_, "offset_scale");
  Result<Scene> s = load_scene(file);
  ASSERT_TRUE(s.ok()) << s.status().message();
  EXPECT_EQ(s->materials[0].uv_scale, glm::vec2(0.5f));
  EXPECT_EQ(s->materials[0].uv_offset, glm::vec2(0.5f, 0.25f));
  expect_quadrant_pixels(file, {0.5, 0.25}, 0.0, {0.5, 0.5});
}

TEST_F(Gltf, TextureTransformRotationIsAppliedToUvs) {
  Doc d = quad_doc(dir_);
  const double r = 0.5;  // radians
  d.j["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
      {"KHR_texture_transform", {{"offset", {0.3, -0.1}}, {"rotation", r}, {"scale", {1.5, 1}}}}};
  expect_quadrant_pixels(d.write(dir_, "rotation"), {0.3, -0.1}, r, {1.5, 1});
}

TEST_F(Gltf, LightsAndCamerasFollowTheirNodes) {
  Doc d = quad_doc(dir_);
  json& j = d.j;
  const double s = std::sqrt(0.5);
  j["extensionsUsed"].push_back("KHR_lights_punctual");
  j["extensions"]["KHR_lights_punctual"]["lights"] = json::array(
      {{{"type", "directional"}, {"name", "sun"}, {"intensity", 2.0}},
       {{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"range", 7.5}},
       {{"type", "spot"},
        {"name", "spot"},
        {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}},
        {"extensions",
         {{"RELIEF_relief_mapping", {{"casts_shadows", true}, {"shadow_resolution", 512}}}}}}});
  // node 3: sun pointing down (-z rotated -90 degrees about x: -y); node 4: point light at
  // (0, 2, 0) under node 0 (+1 x); node 5: spot at (0, 0, 3) looking along -z.
  j["nodes"].push_back(
      {{"rotation", {-s, 0, 0, s}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  j["nodes"].push_back(
      {{"translation", {0, 2, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  j["nodes"].push_back(
      {{"translation", {0, 0, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  j["nodes"][0]["children"].push_back(4);
  // camera 1 (perspective, no zfar) on node 6 at (0, 0, 5) looking down -z; node 2 keeps camera 0.
  j["cameras"].push_back({{"type", "perspective"},
                          {"name", "persp"},
                          {"perspective", {{"yfov", 0.8}, {"znear", 0.5}}}});
  j["nodes"].push_back({{"camera", 1}, {"translation", {0, 0, 5}}});
  j["scenes"][0]["nodes"] = {6, 0, 2, 3, 5};
  Result<Scene> sc = load_scene(d.write(dir_, "lights"));
  ASSERT_TRUE(sc.ok()) << sc.status().message();
  ASSERT_EQ(sc->lights.size(), 3u);
  // Traversal order: node 0's child 4 (point), then 3 (sun), then 5 (spot).
  const Light& point = sc->lights[0];
  EXPECT_EQ(point.type, LightType::kPoint);
  EXPECT_EQ(point.position, glm::vec3(1, 2, 0));
  EXPECT_EQ(point.color, glm::vec3(1, 0.5f, 0.25f));
  EXPECT_EQ(point.range, 7.5f);
  EXPECT_EQ(point.name, "light1");
  const Light& sun = sc->lights[1];
  EXPECT_EQ(sun.type, LightType::kDirectional);
  EXPECT_EQ(sun.intensity, 2.0f);
  EXPECT_NEAR(glm::distance(sun.direction, glm::vec3(0, -1, 0)), 0.0f, 1e-6f);
  const Light& spot = sc->lights[2];
  EXPECT_EQ(spot.type, LightType::kSpot);
  EXPECT_EQ(spot.position, glm::vec3(0, 0, 3));
  EXPECT_EQ(spot.direction, glm::vec3(0, 0, -1));
  EXPECT_NEAR(spot.inner_cone_deg, 0.25 * 180 / M_PI, 1e-4);
  EXPECT_NEAR(spot.outer_cone_deg, 0.5 * 180 / M_PI, 1e-4);
  EXPECT_TRUE(spot.casts_shadows);
  EXPECT_EQ(spot.shadow_resolution, 512);
  EXPECT_FALSE(sun.casts_shadows);

  // Cameras in glTF camera order: 0 is the orthographic "top", 1 the perspective "persp".
  ASSERT_EQ(sc->cameras.size(), 2u);
  const Camera& top = sc->cameras[0];
  EXPECT_EQ(top.name, "top");  // the node's name, the camera having none
  EXPECT_TRUE(top.orthographic);
  EXPECT_EQ(top.ortho_half_height, 2.0f);
  EXPECT_EQ(top.position, glm::vec3(0, 0, 10));
  const Camera& persp = sc->cameras[1];
  EXPECT_EQ(persp.name, "persp");
  EXPECT_FALSE(persp.orthographic);
  EXPECT_NEAR(persp.yfov_deg, 0.8 * 180 / M_PI, 1e-4);
  EXPECT_EQ(persp.znear, 0.5f);
  EXPECT_GT(persp.zfar, 5.0f);  // infinite: reaches past the scene bounds
  const glm::vec3 fwd = glm::normalize(persp.target - persp.position);
  EXPECT_NEAR(glm::distance(fwd, glm::vec3(0, 0, -1)), 0.0f, 1e-6f);

  // --camera NAME|INDEX
  EXPECT_EQ(*cli::resolve_camera(*sc, ""), 0);
  EXPECT_EQ(*cli::resolve_camera(*sc, "1"), 1);
  EXPECT_EQ(*cli::resolve_camera(*sc, "persp"), 1);
  EXPECT_EQ(*cli::resolve_camera(*sc, "top"), 0);
  Result<int> bad = cli::resolve_camera(*sc, "side");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.status().exit_code(), 2);
  EXPECT_NE(bad.status().message().find("0 'top', 1 'persp'"), std::string::npos)
      << bad.status().message();
  EXPECT_FALSE(cli::resolve_camera(*sc, "2").ok());

  // The perspective camera sees the quad (white, red... pixels) around the centre of its view.
  const Framebuffer fb = render(*sc, 32, 32, 1);
  EXPECT_NE(fb.color.at(16, 16), glm::vec4(0, 0, 0, 1));
}

TEST_F(Gltf, NoCameraGetsTheDefaultFraming) {
  Doc d = quad_doc(dir_);
  d.j.erase("cameras");
  d.j["nodes"][2].erase("camera");
  Result<Scene> s = load_scene(d.write(dir_, "nocamera"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->cameras.size(), 1u);
  const Camera& c = s->cameras[0];
  EXPECT_EQ(c.name, "default");
  // Bounds: x in [0, 2], y in [-1, 1], z = 0: centre (1, 0, 0).
  EXPECT_NEAR(glm::distance(c.target, glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
  const glm::vec3 dir = glm::normalize(c.position - c.target);
  EXPECT_NEAR(dir.y, 0.5f, 1e-6f);  // 30 degrees above the horizon, from +z
  EXPECT_NEAR(dir.z, std::sqrt(0.75f), 1e-6f);
  // The whole quad is in view: the frame's border is background, its centre is not.
  const Framebuffer fb = render(*s, 48, 48);
  for (int i = 0; i < 48; ++i) {
    EXPECT_EQ(fb.color.at(i, 0), glm::vec4(0, 0, 0, 1));
    EXPECT_EQ(fb.color.at(0, i), glm::vec4(0, 0, 0, 1));
    EXPECT_EQ(fb.color.at(i, 47), glm::vec4(0, 0, 0, 1));
    EXPECT_EQ(fb.color.at(47, i), glm::vec4(0, 0, 0, 1));
  }
  EXPECT_NE(fb.color.at(24, 24), glm::vec4(0, 0, 0, 1));
}

TEST_F(Gltf, ReliefExtensionSetsTechniqueParametersAndMaps) {
  Doc d = quad_doc(dir_);
  // An 8-bit height map (1 = top): 0, 64 / 128, 255.
  std::vector<float> h = {0.0f, 64 / 255.0f, 128 / 255.0f, 1.0f};
  Image himg(2, 2);
  for (int i = 0; i < 4; ++i) {
    // write_image encodes 8-bit PNG as sRGB: give it the linear value whose encoding is h.
    const double c = h[i];
    const double lin = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
    himg.at(i % 2, i / 2) = glm::vec4(glm::vec3(static_cast<float>(lin)), 1.0f);
  }
  ASSERT_TRUE(write_image(path("height.png"), himg).ok());
  d.j["images"].push_back({{"uri", "height.png"}});
  d.j["textures"].push_back({{"source", 1}, {"sampler", 0}});
  d.j["materials"][0]["extensions"]["RELIEF_relief_mapping"] = {{"technique", "relief"},
                                                                {"depth_texture", {{"index", 1}}},
                                                                {"depth_is_height", true},
                                                                {"depth_scale", 0.08},
                                                                {"steps", 24},
                                                                {"binary_steps", 6},
                                                                {"self_shadow", true},
                                                                {"silhouette", true},
                                                                {"receives_shadow", false},
                                                                {"params", {{"min_steps", 4}}}};
  Result<Scene> s = load_scene(d.write(dir_, "relief"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  const Material& m = s->materials[0];
  EXPECT_EQ(m.technique, "relief");
  EXPECT_EQ(m.params.at("depth_scale"), 0.08f);
  EXPECT_EQ(m.params.at("steps"), 24.0f);
  EXPECT_EQ(m.params.at("binary_steps"), 6.0f);
  EXPECT_EQ(m.params.at("min_steps"), 4.0f);
  EXPECT_TRUE(m.self_shadow);
  EXPECT_TRUE(m.silhouette);
  EXPECT_FALSE(m.depth_write);
  EXPECT_FALSE(m.receives_shadow);
  EXPECT_TRUE(m.casts_shadow);
  ASSERT_TRUE(m.textures.count("depth"));
  const Texture& depth = *m.textures.at("depth");
  EXPECT_EQ(depth.format(), TexFormat::kR8);
  EXPECT_EQ(depth.levels(), 1);                           // a NEAREST (no mipmap) sampler
  const uint8_t want[4] = {255, 255 - 64, 255 - 128, 0};  // depth = 1 - height, exact in 8 bits
  for (int i = 0; i < 4; ++i) EXPECT_EQ(depth.level(0).data[i], want[i]) << i;
  // No normalTexture: derived from the depth map when a technique reads it (a derived map).
  EXPECT_FALSE(m.textures.count("normal"));
  ASSERT_TRUE(derives_normal_map(m, "normal"));
  Result<TexturePtr> normal = derived_normal_map(m);
  ASSERT_TRUE(normal.ok()) << normal.status().message();
  EXPECT_EQ((*normal)->format(), TexFormat::kRGBA8);
  EXPECT_EQ(m.sampler.filter, Filter::kNearest);
  EXPECT_EQ(m.sampler.wrap_u, Wrap::kClamp);
}

// ---- bad input: one line naming the file and the JSON pointer ----

void expect_error(const std::string& file, const std::string& pointer, const std::string& what) {
  Result<Scene> r = load_scene(file);
  ASSERT_FALSE(r.ok()) << file << " loaded";
  const std::string& m = r.status().message();
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  EXPECT_EQ(m.rfind(file + ": " + pointer + ": ", 0), 0u) << m;
  EXPECT_NE(m.find(what), std::string::npos) << m;
  EXPECT_EQ(r.status().exit_code(), 1);
}

TEST_F(Gltf, ConeMapsGoToTheTechniquesConeSlot) {
  auto load = [&](const json& e, const std::string& name) {
    Doc d = quad_doc(dir_);
    d.j["materials"][0]["extensions"]["RELIEF_relief_mapping"] = e;
    return load_scene(d.write(dir_, name));
  };
  const json tex = {{"index", 0}};
  // No cone map in the file: the renderer bakes it from the depth map, the load succeeds.
  Result<Scene> baked = load({{"technique", "cone"}, {"depth_texture", tex}}, "baked");
  ASSERT_TRUE(baked.ok()) << baked.status().message();
  EXPECT_FALSE(baked->materials[0].textures.count("cone_conservative"));
  Result<Scene> own =
      load({{"technique", "cone"}, {"depth_texture", tex}, {"cone_texture", tex}}, "own");
  ASSERT_TRUE(own.ok()) << own.status().message();
  EXPECT_TRUE(own->materials[0].textures.count("cone_conservative"));
  Result<Scene> quad =
      load({{"depth_texture", tex}, {"cone_texture", tex}, {"cone_kind", "quad"}}, "quad");
  ASSERT_TRUE(quad.ok()) << quad.status().message();
  EXPECT_EQ(quad->materials[0].textures.at("cone_quad")->format(), TexFormat::kRGBA8);
  const std::string f = [&] {
    Doc d = quad_doc(dir_);
    d.j["materials"][0]["extensions"]["RELIEF_relief_mapping"] = {{"depth_texture", tex},
                                                                  {"cone_texture", tex}};
    return d.write(dir_, "kindless");
  }();
  expect_error(f, "/materials/0/extensions/RELIEF_relief_mapping/cone_texture",
               "technique relief reads no cone map: give cone_kind");
}

TEST_F(Gltf, IndexOutOfRange) {
  Doc d = quad_doc(dir_);
  const std::vector<uint16_t> idx = {0, 1, 9};
  d.j["meshes"][0]["primitives"][0]["indices"] = d.accessor(idx, 1, kUShortType, "SCALAR");
  const std::string f = d.write(dir_, "bad");
  Result<Scene> r = load_scene(f);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().message(),
            f + ": /meshes/0/primitives/0/indices: index 9 out of range (4 vertices)");
}

TEST_F(Gltf, AccessorCountsAndTypes) {
  {
    Doc d = quad_doc(dir_);
    const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1};  // 3 normals for 4 positions
    d.j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] =
        d.accessor(nrm, 3, kFloatType, "VEC3");
    expect_error(d.write(dir_, "count"), "/meshes/0/primitives/0/attributes/NORMAL",
                 "has 3 elements, POSITION has 4");
  }
  {
    Doc d = quad_doc(dir_);
    const std::vector<float> uv3(12, 0.0f);  // TEXCOORD_0 as VEC3
    d.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        d.accessor(uv3, 3, kFloatType, "VEC3");
    expect_error(d.write(dir_, "type"), "/meshes/0/primitives/0/attributes/TEXCOORD_0",
                 "is VEC3 of FLOAT, expected VEC2 of FLOAT");
  }
  {
    Doc d = quad_doc(dir_);
    d.j["accessors"][0]["count"] = 40;  // past the end of its buffer view
    expect_error(d.write(dir_, "bounds"), "/accessors/0", "need 480 bytes; buffer view 0 has 48");
  }
  {
    Doc d = quad_doc(dir_);
    const std::vector<uint16_t> idx = {0, 1, 2, 3};  // not whole triangles
    d.j["meshes"][0]["primitives"][0]["indices"] = d.accessor(idx, 1, kUShortType, "SCALAR");
    expect_error(d.write(dir_, "partial"), "/meshes/0/primitives/0/indices",
                 "4 indices do not make whole triangles");
  }
  {
    Doc d = quad_doc(dir_);
    d.j["meshes"][0]["primitives"][0]["mode"] = 1;  // LINES
    expect_error(d.write(dir_, "lines"), "/meshes/0/primitives/0/mode",
                 "LINES is not supported (only TRIANGLES)");
  }
}

TEST_F(Gltf, NanInPositions) {
  Doc d = quad_doc(dir_);
  std::vector<float> pos = {-0.5f, 0.5f, 0, 0.5f, 0.5f, 0, 0.5f, -0.5f, 0, -0.5f, -0.5f, 0};
  pos[7] = std::numeric_limits<float>::quiet_NaN();
  d.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] =
      d.accessor(pos, 3, kFloatType, "VEC3");
  expect_error(d.write(dir_, "nan"), "/meshes/0/primitives/0/attributes/POSITION",
               "element 2 is not finite (NaN)");
}

TEST_F(Gltf, MissingTextureFile) {
  Doc d = quad_doc(dir_);
  d.j["images"][0]["uri"] = "no_such.png";
  expect_error(d.write(dir_, "missing"), "/images/0/uri", "no_such.png: no such file");
}

TEST_F(Gltf, ReliefExtensionErrorsNameTheirPath) {
  const std::string ext = "/materials/0/extensions/RELIEF_relief_mapping";
  auto with = [&](const json& e, const std::string& name) {
    Doc d = quad_doc(dir_);
    d.j["materials"][0]["extensions"]["RELIEF_relief_mapping"] = e;
    return d.write(dir_, name);
  };
  const json depth = {{"index", 0}};
  expect_error(with({{"technique", "reliefff"}, {"depth_texture", depth}}, "technique"),
               ext + "/technique", "unknown technique 'reliefff'");
  expect_error(with({{"steps", -3}, {"depth_texture", depth}}, "steps"), ext + "/steps",
               "-3 is outside 1..");
  expect_error(with({{"binary_steps", 2.5}, {"depth_texture", depth}}, "binary"),
               ext + "/binary_steps", "expected an integer");
  // In range for JSON, out of the relief plugin's declared range (steps 1..256).
  expect_error(with({{"steps", 1000}, {"depth_texture", depth}}, "range"), ext + "/steps",
               "relief parameter 'steps'");
  expect_error(with({{"params", {{"no_such_param", 1}}}, {"depth_texture", depth}}, "param"),
               ext + "/params/no_such_param", "no technique has a parameter 'no_such_param'");
  expect_error(with({{"stepz", 8}, {"depth_texture", depth}}, "typo"), ext + "/stepz",
               "unknown property");
  expect_error(with({{"self_shadow", "yes"}, {"depth_texture", depth}}, "bool"),
               ext + "/self_shadow", "expected true or false");
  expect_error(with({{"technique", "relief"}}, "nodepth"), ext,
               "technique relief needs a 'depth' texture");
  expect_error(with({{"depth_texture", {{"index", 7}}}}, "noindex"), ext + "/depth_texture/index",
               "texture 7 does not exist");
}

TEST_F(Gltf, OneSamplerAndTransformPerMaterial) {
  Doc d = quad_doc(dir_);
  d.j["samplers"].push_back({{"wrapS", 10497}});
  d.j["textures"].push_back({{"source", 0}, {"sampler", 1}});
  d.j["materials"][0]["normalTexture"] = {{"index", 1}};
  expect_error(d.write(dir_, "samplers"), "/materials/0/normalTexture",
               "sampler differs from that of /materials/0/pbrMetallicRoughness/baseColorTexture");
}

TEST_F(Gltf, TruncatedGlb) {
  Result<Scene> plane = make_builtin_scene("plane");
  ASSERT_TRUE(plane.ok());
  ASSERT_TRUE(save_gltf(*plane, path("plane.glb")).ok());
  const auto size = fs::file_size(path("plane.glb"));
  for (const uintmax_t keep : {size - 1, size / 2, uintmax_t{20}}) {
    fs::copy_file(path("plane.glb"), path("cut.glb"), fs::copy_options::overwrite_existing);
    fs::resize_file(path("cut.glb"), keep);
    Result<Scene> r = load_scene(path("cut.glb"));
    ASSERT_FALSE(r.ok()) << keep;
    const std::string& m = r.status().message();
    EXPECT_EQ(m.rfind(path("cut.glb") + ": ", 0), 0u) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_NE(m.find("truncated GLB"), std::string::npos) << m;
  }
}

TEST_F(Gltf, NonIndexedPrimitivesAndDefaultMaterial) {
  Doc d = quad_doc(dir_);
  const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const int p = d.accessor(pos, 3, kFloatType, "VEC3");
  d.j["meshes"].push_back({{"primitives", json::array({{{"attributes", {{"POSITION", p}}}}})}});
  d.j["nodes"].push_back({{"mesh", 1}});
  d.j["scenes"][0]["nodes"].push_back(3);
  Result<Scene> s = load_scene(d.write(dir_, "plain"));
  ASSERT_TRUE(s.ok()) << s.status().message();
  ASSERT_EQ(s->instances.size(), 2u);
  const Mesh& m = s->meshes[s->instances[1].mesh];
  EXPECT_EQ(m.indices, (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  ASSERT_EQ(m.normals.size(), 6u);  // made by mesh_prep
  EXPECT_EQ(m.normals[0], glm::vec3(0, 0, 1));
  EXPECT_EQ(m.tangents.size(), 6u);
  EXPECT_EQ(s->materials[s->instances[1].material].name, "default");
  EXPECT_EQ(s->materials[s->instances[1].material].technique, "flat");
}

}  // namespace
}  // namespace relief

namespace relief {
namespace {

// quad_doc with a skin (every vertex on joint node 3, identity inverse bind), a morph target
// moving every vertex by +1 along z, and an animation: the joint's translation LINEAR from 0 to
// (0, 2, 0) over 2 s, the morph weight STEP 0 then 1 from t = 1, the camera node's translation
// LINEAR from (0, 0, 10) to (0, 2, 10).
Doc animated_quad_doc(const fs::path& dir) {
  Doc d = quad_doc(dir);
  json& j = d.j;
  json& prim = j["meshes"][0]["primitives"][0];
  const std::vector<uint8_t> joints(16, 0);
  const std::vector<float> weights = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  prim["attributes"]["JOINTS_0"] = d.accessor(joints, 4, 5121, "VEC4");
  prim["attributes"]["WEIGHTS_0"] = d.accessor(weights, 4, kFloatType, "VEC4");
  const std::vector<float> delta = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  prim["targets"] = json::array({{{"POSITION", d.accessor(delta, 3, kFloatType, "VEC3")}}});
  j["meshes"][0]["weights"] = {0.0};
  j["nodes"].push_back({{"name", "joint"}});  // node 3
  j["scenes"][0]["nodes"].push_back(3);
  j["nodes"][1]["skin"] = 0;
  j["skins"] = json::array({{{"joints", {3}}}});
  const std::vector<float> times = {0, 2}, moves = {0, 0, 0, 0, 2, 0}, wtimes = {0, 1},
                           wvalues = {0, 1};
  const int ti = d.accessor(times, 1, kFloatType, "SCALAR");
  const int mi = d.accessor(moves, 3, kFloatType, "VEC3");
  const int wt = d.accessor(wtimes, 1, kFloatType, "SCALAR");
  const int wv = d.accessor(wvalues, 1, kFloatType, "SCALAR");
  const std::vector<float> cam_moves = {0, 0, 10, 0, 2, 10};
  const int cm = d.accessor(cam_moves, 3, kFloatType, "VEC3");
  j["animations"] = json::array(
      {{{"name", "lift"},
        {"samplers", json::array({{{"input", ti}, {"output", mi}},
                                  {{"input", wt}, {"output", wv}, {"interpolation", "STEP"}},
                                  {{"input", ti}, {"output", cm}}})},
        {"channels",
         json::array({{{"sampler", 0}, {"target", {{"node", 3}, {"path", "translation"}}}},
                      {{"sampler", 1}, {"target", {{"node", 1}, {"path", "weights"}}}},
                      {{"sampler", 2}, {"target", {{"node", 2}, {"path", "translation"}}}}})}}});
  return d;
}

glm::vec3 world_vertex(const Scene& s, size_t v) {
  const Instance& inst = s.instances.at(0);
  return glm::vec3(inst.transform * glm::vec4(s.meshes[inst.mesh].positions[v], 1.0f));
}

TEST_F(Gltf, AnimationsSkinsAndMorphTargetsArePosedPerFrame) {
  Result<Scene> r = load_scene(animated_quad_doc(dir_).write(dir_, "animated"));
  ASSERT_TRUE(r.ok()) << r.status().message();
  Scene& s = *r;
  ASSERT_TRUE(s.animation);
  ASSERT_EQ(s.animation->clips.size(), 1u);
  EXPECT_EQ(s.animation->clips[0].name, "lift");
  EXPECT_EQ(s.animation->clips[0].duration, 2.0);
  ASSERT_EQ(s.animation->deformers.size(), 1u);
  const glm::vec3 rest[4] = {
      {-0.5f, 0.5f, 0}, {0.5f, 0.5f, 0}, {0.5f, -0.5f, 0}, {-0.5f, -0.5f, 0}};
  // Loaded at t = 0: the skin places the vertices where the joint (at the origin) puts them,
  // whatever the mesh node's own transform (glTF 3.7.3).
  for (size_t v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(world_vertex(s, v)[c], rest[v][c], 1e-6f) << v;
  pose_scene(*s.animation, PoseOptions{}, 0.5, s);  // joint at y 0.5, weight still 0
  EXPECT_EQ(s.cameras.at(0).position, glm::vec3(0.0f, 0.5f, 10.0f));  // the camera node moves
  EXPECT_EQ(s.cameras[0].target.y, 0.5f);                             // still looking down -z
  for (size_t v = 0; v < 4; ++v) {
    const glm::vec3 w = world_vertex(s, v);
    EXPECT_NEAR(w.y, rest[v].y + 0.5f, 1e-6f) << v;
    EXPECT_NEAR(w.z, 0.0f, 1e-6f) << v;
  }
  pose_scene(*s.animation, PoseOptions{}, 1.5, s);  // joint at y 1.5, morph weight 1
  for (size_t v = 0; v < 4; ++v) {
    const glm::vec3 w = world_vertex(s, v);
    EXPECT_NEAR(w.x, rest[v].x, 1e-6f) << v;
    EXPECT_NEAR(w.y, rest[v].y + 1.5f, 1e-6f) << v;
    EXPECT_NEAR(w.z, 1.0f, 1e-6f) << v;
  }
}

TEST_F(Gltf, AnimationErrorsNameTheirPath) {
  {
    Doc d = animated_quad_doc(dir_);
    d.j["animations"][0]["samplers"][0]["interpolation"] = "SMOOTH";
    expect_error(d.write(dir_, "interp"), "/animations/0/samplers/0/interpolation",
                 "unknown interpolation 'SMOOTH'");
  }
  {
    Doc d = animated_quad_doc(dir_);
    d.j["animations"][0]["channels"][1]["target"]["node"] = 3;  // the joint has no mesh
    expect_error(d.write(dir_, "weights"), "/animations/0/channels/1/target/path",
                 "no mesh with morph targets");
  }
  {
    Doc d = animated_quad_doc(dir_);
    const std::vector<float> times = {0, 0};
    d.j["animations"][0]["samplers"][0]["input"] = d.accessor(times, 1, kFloatType, "SCALAR");
    expect_error(d.write(dir_, "times"), "/animations/0/samplers/0/input", "strictly increasing");
  }
  {
    Doc d = animated_quad_doc(dir_);
    d.j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] =
        d.j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"];
    expect_error(d.write(dir_, "joints1"), "/meshes/0/primitives/0/attributes/JOINTS_1",
                 "at most four joint influences");
  }
  {
    Doc d = animated_quad_doc(dir_);
    const std::vector<uint8_t> joints(16, 4);  // the skin has one joint
    d.j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] =
        d.accessor(joints, 4, 5121, "VEC4");
    expect_error(d.write(dir_, "joint"), "/meshes/0/primitives/0/attributes/JOINTS_0",
                 "names joint 4");
  }
}

}  // namespace
}  // namespace relief
