// docs/scene-format.md's support table, kept true: every row is parsed and a small file that uses
// the row's feature is loaded; its outcome (no warning / a warning naming it / an error naming
// it) must be the row's status. A row without a fixture here, or a fixture without a row, fails.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/validate.h"
#include "scene/gltf.h"
#include "scene/gltf_extensions.h"
#include "tests/test_dir.h"

namespace relief {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr int kFloat = 5126, kUShort = 5123, kUByte = 5121, kUInt = 5125;
// A 1x1 opaque white PNG.
constexpr const char* kPng =
    "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP4//8/AAX+"
    "Av4N70a4AAAAAElFTkSuQmCC";

struct Row {
  std::string feature, status, token;
};

// The table between the support-table markers: | feature | status | notes |.
std::vector<Row> table_rows() {
  std::ifstream in(std::string(RELIEF_SOURCE_DIR) + "/docs/scene-format.md");
  std::string line;
  std::vector<Row> rows;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("<!-- support-table", 0) == 0) inside = true;
    if (line.rfind("<!-- end support-table", 0) == 0) break;
    if (!inside || line.rfind("| ", 0) != 0 || line.rfind("| feature |", 0) == 0) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string c;
    while (std::getline(ss, c, '|')) {
      const size_t a = c.find_first_not_of(' '), b = c.find_last_not_of(' ');
      cells.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
    }
    if (cells.size() < 2) continue;
    Row r{cells[0], cells[1], ""};
    const size_t q = r.feature.find('`');
    if (q != std::string::npos)
      r.token = r.feature.substr(q + 1, r.feature.find('`', q + 1) - q - 1);
    rows.push_back(r);
  }
  return rows;
}

// One triangle with normals and uvs, a flat material 0, a camera: the base every fixture edits.
struct Doc {
  json j;
  std::vector<uint8_t> bin;

  Doc() {
    j["asset"] = {{"version", "2.0"}};
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int p = floats(pos, "VEC3", 3);
    j["accessors"][p]["min"] = {0, 0, 0};
    j["accessors"][p]["max"] = {1, 1, 0};
    const int n = floats({0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    const int t = floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    j["meshes"] = json::array(
        {{{"primitives",
           json::array({{{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}},
                         {"material", 0}}})}}});
    j["materials"] = json::array({{{"name", "m"}}});
    j["nodes"] = json::array({{{"mesh", 0}}, {{"camera", 0}, {"translation", {0.3, 0.3, 3}}}});
    j["cameras"] =
        json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}});
    j["scenes"] = json::array({{{"nodes", {0, 1}}}});
    j["scene"] = 0;
  }
  json& prim() { return j["meshes"][0]["primitives"][0]; }
  json& mat() { return j["materials"][0]; }
  int view(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}});
    const uint8_t* b = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), b, b + bytes);
    return static_cast<int>(j["bufferViews"].size()) - 1;
  }
  template <class T>
  int accessor(const std::vector<T>& v, int type, const char* t, int width, bool norm = false) {
    json a = {{"bufferView", view(v.data(), v.size() * sizeof(T))},
              {"componentType", type},
              {"count", v.size() / width},
              {"type", t}};
    if (norm) a["normalized"] = true;
    j["accessors"].push_back(a);
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  int floats(const std::vector<float>& v, const char* t, int width) {
    return accessor(v, kFloat, t, width);
  }
  // A texture (1x1 PNG) with sampler `sampler` (or none): its index.
  int texture(json sampler = nullptr) {
    j["images"].push_back({{"uri", kPng}});
    json tex = {{"source", j["images"].size() - 1}};
    if (!sampler.is_null()) {
      j["samplers"].push_back(sampler);
      tex["sampler"] = j["samplers"].size() - 1;
    }
    j["textures"].push_back(tex);
    return static_cast<int>(j["textures"].size()) - 1;
  }
  void use(const std::string& ext, bool required = false) {
    j["extensionsUsed"].push_back(ext);
    if (required) j["extensionsRequired"].push_back(ext);
  }
  std::string write(const fs::path& dir, const std::string& name) {
    json out = j;
    if (!bin.empty())
      out["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(dir / (name + ".gltf")) << out.dump(1);
    return (dir / (name + ".gltf")).string();
  }
};

// A skinned triangle: joints 2 and 3 (nodes), JOINTS_0 / WEIGHTS_0, one LINEAR rotation channel.
void add_skin(Doc& d) {
  d.prim()["attributes"]["JOINTS_0"] =
      d.accessor(std::vector<uint16_t>{0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0}, kUShort, "VEC4", 4);
  d.prim()["attributes"]["WEIGHTS_0"] =
      d.floats({1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 1, 0, 0, 0}, "VEC4", 4);
  d.j["nodes"].push_back({{"name", "root"}, {"children", {3}}});
  d.j["nodes"].push_back({{"name", "tip"}, {"translation", {0, 1, 0}}});
  d.j["scenes"][0]["nodes"].push_back(2);
  d.j["nodes"][0]["skin"] = 0;
  d.j["skins"] = json::array({{{"joints", {2, 3}}}});
}

using Fixture = std::function<std::string(Doc&)>;  // edits the base; returns the token to find

std::map<std::string, Fixture> fixtures() {
  std::map<std::string, Fixture> f;
  auto none = [](Doc&) { return std::string(); };
  f["`POSITION` VEC3 FLOAT"] = none;
  f["`NORMAL` VEC3 FLOAT"] = none;
  f["`TANGENT` VEC4 FLOAT"] = [](Doc& d) {
    d.prim()["attributes"]["TANGENT"] = d.floats({1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4", 4);
    return std::string();
  };
  f["`TEXCOORD_0` FLOAT"] = none;
  f["`TEXCOORD_0` normalized UNSIGNED_SHORT"] = [](Doc& d) {
    d.prim()["attributes"]["TEXCOORD_0"] =
        d.accessor(std::vector<uint16_t>{0, 0, 65535, 0, 0, 65535}, kUShort, "VEC2", 2, true);
    return std::string();
  };
  f["`TEXCOORD_1`"] = [](Doc& d) {
    d.prim()["attributes"]["TEXCOORD_1"] = d.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", d.texture()}, {"texCoord", 1}};
    return std::string();
  };
  f["`COLOR_0`"] = [](Doc& d) {
    d.prim()["attributes"]["COLOR_0"] = d.floats({1, 0, 0, 0, 1, 0, 0, 0, 1}, "VEC3", 3);
    return std::string();
  };
  f["`TEXCOORD_2` and later sets"] = [](Doc& d) {
    for (const char* a : {"TEXCOORD_1", "TEXCOORD_2"})
      d.prim()["attributes"][a] = d.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    return std::string();
  };
  f["`COLOR_1` and later sets"] = [](Doc& d) {
    for (const char* a : {"COLOR_0", "COLOR_1"})
      d.prim()["attributes"][a] = d.floats({1, 1, 1, 1, 1, 1, 1, 1, 1}, "VEC3", 3);
    return std::string();
  };
  f["`JOINTS_1` / `WEIGHTS_1`"] = [](Doc& d) {
    add_skin(d);
    d.prim()["attributes"]["JOINTS_1"] =
        d.accessor(std::vector<uint16_t>(12, 0), kUShort, "VEC4", 4);
    d.prim()["attributes"]["WEIGHTS_1"] = d.floats(std::vector<float>(12, 0.0f), "VEC4", 4);
    return std::string();
  };
  f["indices UNSIGNED_BYTE / SHORT / INT"] = [](Doc& d) {
    d.j["meshes"][0]["primitives"].push_back(d.prim());
    d.j["meshes"][0]["primitives"].push_back(d.prim());
    auto& ps = d.j["meshes"][0]["primitives"];
    ps[0]["indices"] = d.accessor(std::vector<uint8_t>{0, 1, 2, 0}, kUByte, "SCALAR", 1);
    d.j["accessors"].back()["count"] = 3;
    ps[1]["indices"] = d.accessor(std::vector<uint16_t>{0, 1, 2, 0}, kUShort, "SCALAR", 1);
    d.j["accessors"].back()["count"] = 3;
    ps[2]["indices"] = d.accessor(std::vector<uint32_t>{0, 1, 2}, kUInt, "SCALAR", 1);
    return std::string();
  };
  f["non-indexed primitives"] = none;
  f["`sparse` accessors"] = [](Doc& d) {
    const int p = d.prim()["attributes"]["POSITION"];
    const int iv = d.view(std::vector<uint8_t>{1, 0, 0, 0}.data(), 4);
    const std::vector<float> v = {0.5f, 0, 0};
    const int vv = d.view(v.data(), 12);
    d.j["accessors"][p]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", iv}, {"componentType", kUByte}}},
                                     {"values", {{"bufferView", vv}}}};
    return std::string();
  };
  f["mode TRIANGLES"] = [](Doc& d) {
    d.prim()["mode"] = 4;
    return std::string();
  };
  f["mode `LINES` (and POINTS, LINE_LOOP, LINE_STRIP)"] = [](Doc& d) {
    d.prim()["mode"] = 1;
    return std::string();
  };
  f["mode `TRIANGLE_STRIP` / TRIANGLE_FAN"] = [](Doc& d) {
    d.prim()["mode"] = 5;
    return std::string();
  };
  f["node `matrix`, `translation` / `rotation` / `scale`, hierarchy"] = [](Doc& d) {
    d.j["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.1, 0, 0, 1};
    d.j["nodes"].push_back({{"translation", {1, 0, 0}},
                            {"rotation", {0, 0, 0, 1}},
                            {"scale", {1, 2, 1}},
                            {"children", {3}}});
    d.j["nodes"].push_back({{"mesh", 0}});
    d.j["scenes"][0]["nodes"].push_back(2);
    return std::string();
  };
  f["scenes: the default `scene` (else scene 0)"] = [](Doc& d) {
    d.j["scenes"].push_back({{"nodes", {0}}});
    d.j["scene"] = 1;
    return std::string();
  };
  f["perspective cameras"] = [](Doc& d) {
    d.j["cameras"][0]["perspective"]["aspectRatio"] = 1.5;
    d.j["cameras"][0]["perspective"]["zfar"] = 100;
    return std::string();
  };
  f["orthographic cameras"] = [](Doc& d) {
    d.j["cameras"][0] = {
        {"type", "orthographic"},
        {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}};
    return std::string();
  };
  f["skins (`JOINTS_0`, `WEIGHTS_0`, `inverseBindMatrices`)"] = [](Doc& d) {
    add_skin(d);
    std::vector<float> ibm;
    for (int k = 0; k < 2; ++k)
      ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, k ? -1.0f : 0.0f, 0, 1});
    d.j["skins"][0]["inverseBindMatrices"] = d.floats(ibm, "MAT4", 16);
    return std::string();
  };
  f["morph targets and `weights`"] = [](Doc& d) {
    const int t = d.floats({0, 0, 0.1f, 0, 0, 0, 0, 0, 0}, "VEC3", 3);
    d.j["accessors"][t]["min"] = {0, 0, 0};
    d.j["accessors"][t]["max"] = {0, 0, 0.1};
    d.prim()["targets"] = json::array({{{"POSITION", t}}});
    d.j["meshes"][0]["weights"] = {0.5};
    return std::string();
  };
  f["animations (STEP, LINEAR, CUBICSPLINE)"] = [](Doc& d) {
    d.j["nodes"].push_back({{"children", {0}}});
    d.j["scenes"][0]["nodes"] = {1, 2};
    const int in = d.floats({0, 1}, "SCALAR", 1);
    d.j["accessors"][in]["min"] = {0};
    d.j["accessors"][in]["max"] = {1};
    const int lin = d.floats({0, 0, 0, 0, 0.5f, 0}, "VEC3", 3);
    const int step = d.floats({1, 1, 1, 1, 2, 1}, "VEC3", 3);
    const int cub = d.floats(
        {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}, "VEC4", 4);
    d.j["animations"] = json::array(
        {{{"samplers",
           json::array({{{"input", in}, {"output", lin}, {"interpolation", "LINEAR"}},
                        {{"input", in}, {"output", step}, {"interpolation", "STEP"}},
                        {{"input", in}, {"output", cub}, {"interpolation", "CUBICSPLINE"}}})},
          {"channels",
           json::array({{{"sampler", 0}, {"target", {{"node", 2}, {"path", "translation"}}}},
                        {{"sampler", 1}, {"target", {{"node", 2}, {"path", "scale"}}}},
                        {{"sampler", 2}, {"target", {{"node", 2}, {"path", "rotation"}}}}})}}});
    return std::string();
  };
  f["samplers: wrap modes"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", d.texture({{"wrapS", 33648}, {"wrapT", 33071}})}};
    return std::string();
  };
  f["sampler `magFilter` other than the minification's"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", d.texture({{"magFilter", 9728}, {"minFilter", 9987}})}};
    return std::string();
  };
  f["sampler minFilter `NEAREST_MIPMAP_LINEAR`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", d.texture({{"minFilter", 9986}})}};
    return std::string();
  };
  f["PNG and JPEG images, data URIs, GLB buffers"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", d.texture()}};
    return std::string();
  };
  f["`baseColorFactor`, `baseColorTexture`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"] = {{"baseColorFactor", {0.5, 0.5, 0.5, 1}},
                                       {"baseColorTexture", {{"index", d.texture()}}}};
    return std::string();
  };
  f["`normalTexture` with `scale`"] = [](Doc& d) {
    d.mat()["normalTexture"] = {{"index", d.texture()}, {"scale", 0.5}};
    return std::string();
  };
  f["`occlusionTexture`"] = [](Doc& d) {
    d.mat()["occlusionTexture"] = {{"index", d.texture()}, {"strength", 0.5}};
    return std::string();
  };
  f["`emissiveFactor`, `emissiveTexture`"] = [](Doc& d) {
    d.mat()["emissiveFactor"] = {0.2, 0.1, 0};
    d.mat()["emissiveTexture"] = {{"index", d.texture()}};
    return std::string();
  };
  f["`alphaMode` MASK with `alphaCutoff`"] = [](Doc& d) {
    d.mat()["alphaMode"] = "MASK";
    d.mat()["alphaCutoff"] = 0.3;
    return std::string();
  };
  f["`alphaMode` BLEND"] = [](Doc& d) {
    d.mat()["alphaMode"] = "BLEND";
    return std::string();
  };
  f["`doubleSided`"] = [](Doc& d) {
    d.mat()["doubleSided"] = true;
    return std::string();
  };
  f["`metallicRoughnessTexture`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", d.texture()}};
    return std::string();
  };
  f["`metallicFactor`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["metallicFactor"] = 0.7;
    return std::string();
  };
  f["`roughnessFactor`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["roughnessFactor"] = 0.4;
    return std::string();
  };

  // Extensions: each on the object it extends, listed in extensionsUsed.
  auto on_material = [](const char* name, json value) {
    return [name, value](Doc& d) {
      d.mat()["extensions"][name] = value;
      d.use(name);
      return std::string();
    };
  };
  f["`RELIEF_relief_mapping`"] = on_material("RELIEF_relief_mapping", {{"technique", "flat"}});
  f["`KHR_lights_punctual`"] = [](Doc& d) {
    d.j["extensions"]["KHR_lights_punctual"] = {
        {"lights", json::array({{{"type", "point"}, {"intensity", 2}}})}};
    d.j["nodes"][1]["extensions"]["KHR_lights_punctual"] = {{"light", 0}};
    d.use("KHR_lights_punctual");
    return std::string();
  };
  f["`KHR_texture_transform`"] = [](Doc& d) {
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {
        {"index", d.texture()},
        {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0}}, {"scale", {2, 2}}}}}}};
    d.use("KHR_texture_transform");
    return std::string();
  };
  f["`KHR_mesh_quantization`"] = [](Doc& d) {
    d.prim()["attributes"]["NORMAL"] = d.accessor(
        std::vector<int8_t>{0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0}, 5120, "VEC3", 3, true);
    d.j["bufferViews"].back()["byteStride"] = 4;
    d.j["accessors"].back()["count"] = 3;
    d.use("KHR_mesh_quantization", true);
    return std::string();
  };
  // Listed as used (decoding is tested with files their encoders write: tests/scene/*decode*).
  for (const char* name :
       {"KHR_draco_mesh_compression", "EXT_meshopt_compression", "EXT_texture_webp"})
    f[std::string("`") + name + "`"] = [name](Doc& d) {
      d.use(name);
      return std::string();
    };
  f["`KHR_materials_emissive_strength`"] = [](Doc& d) {
    d.mat()["emissiveFactor"] = {1, 1, 1};
    d.mat()["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", 3}};
    d.use("KHR_materials_emissive_strength");
    return std::string();
  };
  f["`KHR_materials_unlit`"] = on_material("KHR_materials_unlit", json::object());
  for (const char* name :
       {"KHR_materials_clearcoat", "KHR_materials_ior", "KHR_materials_iridescence",
        "KHR_materials_sheen", "KHR_materials_specular", "KHR_materials_transmission",
        "KHR_materials_volume", "KHR_materials_anisotropy", "KHR_materials_dispersion",
        "KHR_materials_diffuse_transmission", "KHR_materials_pbrSpecularGlossiness",
        "KHR_techniques_webgl"})
    f[std::string("`") + name + "`"] = on_material(name, json::object());
  f["`KHR_materials_variants`"] = [](Doc& d) {
    d.j["extensions"]["KHR_materials_variants"] = {{"variants", json::array({{{"name", "a"}}})}};
    d.prim()["extensions"]["KHR_materials_variants"] = {
        {"mappings", json::array({{{"material", 0}, {"variants", {0}}}})}};
    d.use("KHR_materials_variants");
    return std::string();
  };
  f["`KHR_texture_basisu`"] = [](Doc& d) {
    const int t = d.texture();
    d.j["textures"][t]["extensions"]["KHR_texture_basisu"] = {{"source", 0}};
    d.mat()["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", t}};
    d.use("KHR_texture_basisu");
    return std::string();
  };
  f["`KHR_animation_pointer`"] = [](Doc& d) {
    const int in = d.floats({0, 1}, "SCALAR", 1);
    d.j["accessors"][in]["min"] = {0};
    d.j["accessors"][in]["max"] = {1};
    const int out = d.floats({0, 1}, "SCALAR", 1);
    d.j["animations"] = json::array(
        {{{"samplers", json::array({{{"input", in}, {"output", out}}})},
          {"channels", json::array({{{"sampler", 0},
                                     {"target",
                                      {{"path", "pointer"},
                                       {"extensions",
                                        {{"KHR_animation_pointer",
                                          {{"pointer", "/materials/0/alphaCutoff"}}}}}}}}})}}});
    d.use("KHR_animation_pointer");
    return std::string();
  };
  for (const char* name : {"KHR_xmp_json_ld", "KHR_xmp"})
    f[std::string("`") + name + "`"] = [name](Doc& d) {
      d.j["asset"]["extensions"][name] = {{"packet", 0}};
      d.use(name);
      return std::string();
    };
  f["`EXT_mesh_gpu_instancing`"] = [](Doc& d) {
    const int t = d.floats({0, 0, 0, 1, 0, 0}, "VEC3", 3);
    d.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = {
        {"attributes", {{"TRANSLATION", t}}}};
    d.use("EXT_mesh_gpu_instancing");
    return std::string();
  };
  f["`EXT_lights_image_based`"] = [](Doc& d) {
    d.j["extensions"]["EXT_lights_image_based"] = {{"lights", json::array()}};
    d.use("EXT_lights_image_based");
    return std::string();
  };
  f["`EXT_any_other_extension` (any name not listed)"] =
      on_material("EXT_any_other_extension", {{"x", 1}});
  f["an extension used on an object but not in `extensionsUsed`"] = [](Doc& d) {
    d.mat()["extensions"]["KHR_materials_sheen"] = json::object();
    return std::string("KHR_materials_sheen");
  };
  f["`extensionsRequired` naming an extension relief ignores"] = [](Doc& d) {
    d.mat()["extensions"]["KHR_materials_clearcoat"] = json::object();
    d.use("KHR_materials_clearcoat", true);
    return std::string("KHR_materials_clearcoat");
  };
  return f;
}

TEST(SupportTable, EveryRowHoldsTrue) {
  const std::vector<Row> rows = table_rows();
  ASSERT_GT(rows.size(), 40u) << "docs/scene-format.md: support table not found";
  std::map<std::string, Fixture> f = fixtures();
  const fs::path dir = test::fresh_test_dir("support_table");
  int n = 0;
  std::vector<std::string> failed;
  for (const Row& row : rows) {
    SCOPED_TRACE(row.feature);
    auto it = f.find(row.feature);
    if (it == f.end()) {
      ADD_FAILURE() << "no fixture for the row '" << row.feature << "'";
      continue;
    }
    Doc d;
    std::string token = it->second(d);
    if (token.empty()) token = row.token;
    f.erase(it);
    const std::string file = d.write(dir, "row" + std::to_string(n++));
    std::vector<GltfIgnored> ignored;
    GltfLoadOptions opt;
    opt.ignored = &ignored;
    Result<Scene> s = load_scene(file, opt);
    std::string lines;
    for (const GltfIgnored& g : ignored)
      if (g.warn) lines += ignored_line(file, g) + "\n";
    bool ok = true;
    if (row.status == "supported") {
      ok = s.ok() && lines.empty();
      EXPECT_TRUE(s.ok()) << s.status().message();
      EXPECT_EQ(lines, "") << "a supported feature warns";
    } else if (row.status == "ignored with a warning") {
      ok = s.ok() && !token.empty() && lines.find(token) != std::string::npos;
      EXPECT_TRUE(s.ok()) << s.status().message();
      EXPECT_NE(lines.find(token), std::string::npos) << "no warning names " << token << ":\n"
                                                      << lines;
      // --strict: the same line is the error.
      GltfLoadOptions strict;
      strict.strict = true;
      Result<Scene> st = load_scene(file, strict);
      ok = ok && !st.ok();
      EXPECT_FALSE(st.ok()) << "--strict accepted it";
      if (!st.ok()) {
        EXPECT_NE(st.status().message().find(token), std::string::npos);
      }
    } else if (row.status == "refused") {
      ok = !s.ok() && s.status().message().find(token) != std::string::npos;
      EXPECT_FALSE(s.ok()) << "refused feature loaded";
      if (!s.ok()) {
        EXPECT_NE(s.status().message().find(token), std::string::npos) << s.status().message();
        EXPECT_EQ(s.status().message().find('\n'), std::string::npos);
      }
    } else {
      ok = false;
      ADD_FAILURE() << "unknown status '" << row.status << "'";
    }
    if (!ok) failed.push_back(row.feature);
  }
  for (const auto& [name, unused] : f) ADD_FAILURE() << "fixture without a row: " << name;
  std::string list;
  for (const std::string& r : failed) list += "  " + r + "\n";
  std::printf("support table: %d rows, %zu fail%s\n%s", n, failed.size(), failed.empty() ? "" : ":",
              list.c_str());
}

// The extension rows of the table are the code's table (scene/gltf_extensions.cpp), both ways.
TEST(SupportTable, ExtensionRowsAreTheLoadersTable) {
  std::map<std::string, std::string> doc;
  for (const Row& r : table_rows())
    if (r.feature.size() > 2 && r.feature.front() == '`' && r.feature.back() == '`')
      doc[r.token] = r.status;
  for (const ExtensionInfo& e : gltf_extensions()) {
    ASSERT_TRUE(doc.count(e.name)) << e.name << " has no row";
    EXPECT_EQ(doc[e.name], extension_status_text(e.status)) << e.name;
  }
}

// One line per extension, however many objects use it, naming the materials.
TEST(ExtensionWarnings, OneLinePerExtensionNamingIt) {
  Doc d;
  d.j["materials"].push_back({{"name", "b"}});
  d.j["materials"].push_back({{"name", "c"}});
  for (int m : {0, 2})
    d.j["materials"][m]["extensions"]["KHR_materials_clearcoat"] = json::object();
  d.j["materials"][1]["extensions"]["KHR_materials_sheen"] = json::object();
  d.use("KHR_materials_clearcoat");
  d.use("KHR_materials_sheen");
  d.use("KHR_materials_volume");  // listed, used nowhere
  const fs::path dir = test::fresh_test_dir("ext_warn");
  const std::string file = d.write(dir, "s");
  std::vector<GltfIgnored> ignored;
  GltfLoadOptions opt;
  opt.ignored = &ignored;
  ASSERT_TRUE(load_scene(file, opt).ok());
  std::vector<std::string> lines;
  for (const GltfIgnored& g : ignored)
    if (g.warn) lines.push_back(ignored_line(file, g));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[0].find("/materials/0/extensions/KHR_materials_clearcoat: extension "
                          "KHR_materials_clearcoat is not supported, ignored"),
            std::string::npos)
      << lines[0];
  EXPECT_NE(lines[0].find("materials 0, 2"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("/materials/1/extensions/KHR_materials_sheen"), std::string::npos);
  EXPECT_NE(lines[2].find("/extensionsUsed/2: extension KHR_materials_volume"), std::string::npos);
  // --explain's view: each material its own entries.
  int on_material_2 = 0;
  for (const GltfIgnored& g : ignored) on_material_2 += g.material == 2;
  EXPECT_EQ(on_material_2, 1);
}

// Extras are the application's: an "extensions" key inside them is not an extension use.
TEST(ExtensionWarnings, ExtrasAreNotScanned) {
  Doc d;
  d.mat()["extras"] = {{"extensions", {{"KHR_materials_sheen", json::object()}}}};
  const fs::path dir = test::fresh_test_dir("ext_extras");
  std::vector<GltfIgnored> ignored;
  GltfLoadOptions opt;
  opt.ignored = &ignored;
  ASSERT_TRUE(load_scene(d.write(dir, "s"), opt).ok());
  EXPECT_TRUE(ignored.empty());
}

}  // namespace
}  // namespace relief
