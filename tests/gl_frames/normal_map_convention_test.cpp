// glTF normal maps from files the tests write, on the CPU and (where there is a context) the GL
// backend (docs/scene-format.md, "Tangents and normal maps"):
// - a glTF-convention map (green = +Y toward the image top) lights a bump from the side the light
//   is on, with and without TANGENT, and so does the map `relief bake --normal` makes
//   (normal_map_from_depth); the DirectX one does the opposite;
// - a normal-mapped sphere without TANGENT renders like the same file with MikkTSpace tangents in
//   the file's (glTF) convention: PSNR >= 45 dB. The file's tangents are the reference
//   implementation's (tests/gl_frames/normal_map_convention_data.h), written by this test into a
//   buffer of its own (not through save_gltf, whose w negation would cancel the loader's).
// Renders are tiny (64 x 64, 96 x 96): CI time.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bake/normal_map.h"
#include "builtin/builtin_curved.h"
#include "builtin/builtin_parts.h"
#include "gl/gl_backend.h"
#include "render/compare.h"
#include "render/render.h"
#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/mesh_prep.h"
#include "tests/gl/gl_test_util.h"
#include "tests/gl_frames/normal_map_convention_data.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// Adds a TANGENT attribute holding `file_tangents` (glTF convention) to every primitive of the
// .gltf at `path`, in a buffer of its own.
void add_file_tangents(const std::string& path, const std::vector<glm::vec4>& file_tangents) {
  nlohmann::json j = nlohmann::json::parse(slurp(path));
  const std::string bin = path.substr(0, path.size() - 5) + "_tangents.bin";
  {
    std::ofstream f(bin, std::ios::binary);
    f.write(reinterpret_cast<const char*>(file_tangents.data()),
            std::streamsize(file_tangents.size() * sizeof(glm::vec4)));
  }
  const size_t bytes = file_tangents.size() * sizeof(glm::vec4);
  j["buffers"].push_back({{"uri", bin.substr(bin.find_last_of('/') + 1)}, {"byteLength", bytes}});
  j["bufferViews"].push_back(
      {{"buffer", j["buffers"].size() - 1}, {"byteLength", bytes}, {"target", 34962}});
  j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1},
                            {"componentType", 5126},
                            {"count", file_tangents.size()},
                            {"type", "VEC4"}});
  for (auto& mesh : j["meshes"])
    for (auto& prim : mesh["primitives"]) {
      const size_t pos = prim["attributes"]["POSITION"];
      ASSERT_EQ(j["accessors"][pos]["count"], file_tangents.size());
      prim["attributes"]["TANGENT"] = j["accessors"].size() - 1;
    }
  std::ofstream(path) << j.dump(1);
}

// One normal-mapped mesh (technique normal, white) under a light travelling along `light_dir`,
// seen from +z.
Scene one_mesh_scene(Mesh mesh, TexturePtr normal_map, glm::vec3 light_dir, glm::vec3 eye) {
  Scene s;
  s.name = "n";
  s.meshes.push_back(std::move(mesh));
  Material m;
  m.name = "m";
  m.technique = "normal";
  m.textures = {{"normal", std::move(normal_map)}};
  m.sampler.filter = Filter::kBilinear;
  s.materials.push_back(m);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  s.lights.push_back(directional_light("sun", light_dir, glm::vec3(1.0f)));
  s.cameras.push_back(look_at("c", eye, glm::vec3(0.0f), 40.0f, 20.0f));
  s.ambient = glm::vec3(0.02f);
  return s;
}

// Saves `s` (its mesh without tangents) as dir/name.gltf; with `with_tangents`, adds TANGENT:
// `file_tangents` when given, else the mesh's MikkTSpace tangents in the glTF convention (w
// negated). Returns the path.
std::string write_file(const std::filesystem::path& dir, const std::string& name, Scene s,
                       bool with_tangents, std::vector<glm::vec4> file_tangents = {}) {
  Mesh& mesh = s.meshes[0];
  if (file_tangents.empty()) {
    Mesh computed = mesh;
    computed.tangents.clear();
    compute_tangents(computed);
    EXPECT_EQ(computed.positions.size(), mesh.positions.size()) << "no split on the test meshes";
    for (const glm::vec4& t : computed.tangents) file_tangents.emplace_back(glm::vec3(t), -t.w);
  }
  mesh.tangents.clear();
  const std::string path = (dir / (name + ".gltf")).string();
  const Status st = save_gltf(s, path);
  EXPECT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(slurp(path).find("TANGENT"), std::string::npos);
  if (with_tangents) add_file_tangents(path, file_tangents);
  return path;
}

struct Backends {
  std::unique_ptr<Backend> cpu = make_cpu_backend({.threads = 2});
  std::unique_ptr<Backend> gl;  // null without a context
  Backends() {
    std::string why;
    if (gl::testing::shared_context(&why)) {
      Result<std::unique_ptr<Backend>> g =
          make_gl_backend({.gl_interpolation = GlInterpolation::kCpuPlanes});
      if (g.ok()) gl = std::move(*g);
    }
  }
};

Image render_file(Backend& backend, const std::string& path, int size) {
  Result<Scene> s = load_scene(path);
  EXPECT_TRUE(s.ok()) << s.status().message();
  if (!s.ok()) return Image(size, size);
  RenderOptions opt;
  opt.width = opt.height = size;
  Result<Plan> plan = make_plan(*s, opt);
  EXPECT_TRUE(plan.ok()) << plan.status().message();
  if (!plan.ok()) return Image(size, size);
  Result<RenderResult> r = backend.render(*s, *plan);
  EXPECT_TRUE(r.ok()) << r.status().message();
  return r.ok() ? r->framebuffer.color : Image(size, size);
}

// Mean red over the image's central half.
double centre_brightness(const Image& img) {
  double sum = 0.0;
  int n = 0;
  for (int y = img.height / 4; y < img.height * 3 / 4; ++y)
    for (int x = img.width / 4; x < img.width * 3 / 4; ++x, ++n) sum += img.at(x, y).x;
  return n ? sum / n : 0.0;
}

// A quad in z = 0 facing +z laid out as glTF files have it: uv (0, 0) at the top left (+y), v
// running down the image (-y).
Mesh gltf_quad() {
  Mesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.normals.assign(4, glm::vec3(0, 0, 1));
  m.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  prepare_mesh(m);
  return m;
}

TexturePtr uniform_normal_map(glm::vec3 rgb) {
  std::vector<float> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {rgb.x, rgb.y, rgb.z, 1.0f});
  return std::make_shared<Texture>(
      Texture::from_floats(TexFormat::kRGBA8, 4, 4, px.data(), ColorSpace::kLinear));
}

// A depth ramp, deepest along the image's top row: its surface faces the image top.
TexturePtr baked_map(NormalConvention c) {
  std::vector<float> d(16 * 16);
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) d[y * 16 + x] = 1.0f - (y + 0.5f) / 16.0f;
  const Texture depth = Texture::from_floats(TexFormat::kR32F, 16, 16, d.data());
  return std::make_shared<Texture>(normal_map_from_depth(depth, 0.8f, false, c));
}

TEST(NormalMapConvention, GreenUpIsLitFromAboveWithAndWithoutTangent) {
  const auto dir = test::fresh_test_dir("normal_convention");
  Backends b;
  const glm::vec3 from_above(0.0f, -0.8f, -0.6f);  // travelling down and into the quad
  const glm::vec3 eye(0.0f, 0.0f, 3.0f);
  struct Map {
    const char* name;
    TexturePtr tex;
  };
  const Map maps[] = {{"up", uniform_normal_map({0.5f, 0.9f, 0.7f})},
                      {"flat", uniform_normal_map({0.5f, 0.5f, 1.0f})},
                      {"down", uniform_normal_map({0.5f, 0.1f, 0.7f})},
                      {"baked", baked_map(NormalConvention::kGltf)},
                      {"baked_directx", baked_map(NormalConvention::kDirectX)}};
  for (bool tangents : {false, true})
    for (Backend* be : {b.cpu.get(), b.gl.get()}) {
      if (!be) continue;
      SCOPED_TRACE(std::string(be == b.cpu.get() ? "cpu" : "gl") +
                   (tangents ? " with TANGENT" : " without TANGENT"));
      double v[5];
      for (int i = 0; i < 5; ++i) {
        const std::string path =
            write_file(dir, std::string(maps[i].name) + (tangents ? "_t" : ""),
                       one_mesh_scene(gltf_quad(), maps[i].tex, from_above, eye), tangents);
        v[i] = centre_brightness(render_file(*be, path, 64));
      }
      // lambert: up n.l ~ 0.99, flat 0.6, down ~ -0.2 (ambient only)
      EXPECT_GT(v[0], v[1] * 1.3) << "green-up map lit as if from below";
      EXPECT_LT(v[2], v[1] * 0.5);
      EXPECT_GT(v[3], v[1] * 1.1) << "bake --normal's map lit as if from below";
      EXPECT_LT(v[4], v[1] * 0.9) << "the DirectX map should be the flipped one";
    }
}

TEST(NormalMapConvention, SphereWithoutTangentRendersLikeTheFileWithMikkTSpaceTangents) {
  const auto dir = test::fresh_test_dir("normal_convention_sphere");
  Backends b;
  // bumps: a dome per tile, wrapped
  std::vector<float> d(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const float fx = (x % 16 + 0.5f) / 16.0f - 0.5f, fy = (y % 16 + 0.5f) / 16.0f - 0.5f;
      d[y * 64 + x] = std::min(1.0f, 4.0f * (fx * fx + 2.0f * fy * fy));
    }
  const Texture depth = Texture::from_floats(TexFormat::kR32F, 64, 64, d.data());
  auto map = std::make_shared<Texture>(normal_map_from_depth(depth, 0.1f, true));
  Scene s = one_mesh_scene(parametric_mesh("sphere", sphere_surface(1.0f), 24, 12, {2, 1}), map,
                           {-0.5f, -0.6f, -0.6f}, {0.3f, 0.5f, 2.8f});
  s.materials[0].sampler.wrap_u = s.materials[0].sampler.wrap_v = Wrap::kRepeat;
  const float* ref = normal_map_convention_data::k_sphere_gltf_tangents;
  const size_t n = std::size(normal_map_convention_data::k_sphere_gltf_tangents) / 4;
  ASSERT_EQ(s.meshes[0].positions.size(), n);
  std::vector<glm::vec4> reference;
  for (size_t k = 0; k < n; ++k)
    reference.emplace_back(ref[k * 4], ref[k * 4 + 1], ref[k * 4 + 2], ref[k * 4 + 3]);
  const std::string without = write_file(dir, "without", s, false);
  const std::string with = write_file(dir, "with", s, true, reference);
  for (Backend* be : {b.cpu.get(), b.gl.get()}) {
    if (!be) continue;
    SCOPED_TRACE(be == b.cpu.get() ? "cpu" : "gl");
    const Image a = render_file(*be, without, 96), c = render_file(*be, with, 96);
    const ImageDiff diff = compare_images(a, c);
    EXPECT_GE(diff.psnr_db, 45.0);
    ::testing::Test::RecordProperty(be == b.cpu.get() ? "cpu_psnr" : "gl_psnr",
                                    std::to_string(diff.psnr_db));
    std::printf("[   info   ] %s: PSNR without vs with TANGENT %.2f dB\n",
                be == b.cpu.get() ? "cpu" : "gl", diff.psnr_db);
  }
}

// The relief searches map a tangent-space ray to a uv step with B along +v: a file's TANGENT
// (glTF's w, bitangent toward the image top) must give the same search as computed tangents.
TEST(NormalMapConvention, ReliefOnAFileWithTangentMatchesComputedTangents) {
  const auto dir = test::fresh_test_dir("normal_convention_relief");
  Backends b;
  std::vector<float> d(64 * 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {  // asymmetric ridges: a backwards march would show
      const float fx = (x % 16 + 0.5f) / 16.0f, fy = (y % 32 + 0.5f) / 32.0f;
      d[y * 64 + x] = std::clamp(fx * 1.2f + 0.3f * fy, 0.0f, 1.0f);
    }
  auto depth = std::make_shared<Texture>(
      Texture::from_floats(TexFormat::kR8, 64, 64, d.data(), ColorSpace::kLinear));
  Scene s = one_mesh_scene(parametric_mesh("sphere", sphere_surface(1.0f), 24, 12, {2, 1}), nullptr,
                           {-0.5f, -0.6f, -0.6f}, {0.3f, 0.5f, 2.8f});
  Material& m = s.materials[0];
  m.technique = "relief";
  // a colour checker: the search's uv offset shows in the colour (white albedo alone would not)
  std::vector<uint8_t> rgba(64 * 64 * 4, 255);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      if (((x / 4) + (y / 4)) & 1)
        for (int c = 0; c < 3; ++c) rgba[(y * 64 + x) * 4 + c] = uint8_t(40 + 60 * c);
  auto color = std::make_shared<Texture>(TexFormat::kRGBA8, 64, 64, rgba.data(), ColorSpace::kSRGB);
  m.textures = {{"depth", depth}, {"base_color", color}};
  m.params = {{"depth_scale", 0.08f}};
  m.sampler.wrap_u = m.sampler.wrap_v = Wrap::kRepeat;
  const float* ref = normal_map_convention_data::k_sphere_gltf_tangents;
  std::vector<glm::vec4> reference;
  for (size_t k = 0; k < std::size(normal_map_convention_data::k_sphere_gltf_tangents) / 4; ++k)
    reference.emplace_back(ref[k * 4], ref[k * 4 + 1], ref[k * 4 + 2], ref[k * 4 + 3]);
  const std::string without = write_file(dir, "without", s, false);
  const std::string with = write_file(dir, "with", s, true, reference);
  for (Backend* be : {b.cpu.get(), b.gl.get()}) {
    if (!be) continue;
    SCOPED_TRACE(be == b.cpu.get() ? "cpu" : "gl");
    const Image a = render_file(*be, without, 96), c = render_file(*be, with, 96);
    const ImageDiff diff = compare_images(a, c);
    EXPECT_GE(diff.psnr_db, 45.0);
    // the relief moves the checker: the same file drawn flat differs (so the test can fail)
    Result<Scene> flat = load_scene(without);
    ASSERT_TRUE(flat.ok());
    flat->materials[0].params["depth_scale"] = 0.0f;
    RenderOptions opt;
    opt.width = opt.height = 96;
    Result<Plan> plan = make_plan(*flat, opt);
    ASSERT_TRUE(plan.ok()) << plan.status().message();
    Result<RenderResult> r = be->render(*flat, *plan);
    ASSERT_TRUE(r.ok());
    EXPECT_LT(compare_images(a, r->framebuffer.color).psnr_db, 30.0);
    std::printf("[   info   ] %s: relief, PSNR without vs with TANGENT %.2f dB\n",
                be == b.cpu.get() ? "cpu" : "gl", diff.psnr_db);
  }
}

}  // namespace
}  // namespace relief
