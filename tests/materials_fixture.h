// Tiny glTF files for the material-feature tests (tests/render/materials_test.cpp on the CPU,
// tests/gl/materials_agreement_test.cpp against GL): one 2x2 quad facing +z with uv (0, 0) at its
// top-left corner, seen straight on by an orthographic camera that it fills exactly, so the pixel
// at (u W, v H) shows raw uv (u, v). Textures are 2x2 PNGs (nearest, clamped); ambient and one
// optional directional light (travelling -z, straight onto the quad) are the test's.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include "rasterizer/image.h"
#include "scene/image_io.h"

namespace relief::test {

struct MaterialDoc {
  nlohmann::json j = nlohmann::json::object();
  std::vector<uint8_t> bin;
  std::filesystem::path dir;

  int view(const void* data, size_t bytes) {
    while (bin.size() % 4) bin.push_back(0);
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}});
    const uint8_t* p = static_cast<const uint8_t*>(data);
    bin.insert(bin.end(), p, p + bytes);
    return static_cast<int>(j["bufferViews"].size()) - 1;
  }
  // An accessor over v (count = v.size() / components); `normalized` for integer colours.
  template <class T>
  int accessor(const std::vector<T>& v, int components, int component_type, const char* type,
               bool normalized = false) {
    const int bv = view(v.data(), v.size() * sizeof(T));
    nlohmann::json a = {{"bufferView", bv},
                        {"componentType", component_type},
                        {"count", v.size() / components},
                        {"type", type}};
    if (normalized) a["normalized"] = true;
    j["accessors"].push_back(a);
    return static_cast<int>(j["accessors"].size()) - 1;
  }
  // A 2x2 texture of texels t[0] (top-left), t[1] (top-right), t[2], t[3] (bottom row), written
  // as an 8-bit PNG (write_image: linear values sRGB-encoded); returns its texture index.
  int texture(const std::string& name, const glm::vec4 (&t)[4]) {
    Image img(2, 2);
    for (int i = 0; i < 4; ++i) img.at(i % 2, i / 2) = t[i];
    EXPECT_TRUE(write_image((dir / (name + ".png")).string(), img).ok());
    j["images"].push_back({{"uri", name + ".png"}});
    j["textures"].push_back({{"source", static_cast<int>(j["images"].size()) - 1}, {"sampler", 0}});
    return static_cast<int>(j["textures"].size()) - 1;
  }
  std::string write(const std::string& name) {
    nlohmann::json out = j;
    out["buffers"] = nlohmann::json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    std::ofstream(dir / (name + ".bin"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bin.data()), static_cast<std::streamsize>(bin.size()));
    std::ofstream(dir / (name + ".gltf")) << out.dump(1);
    return (dir / (name + ".gltf")).string();
  }
  nlohmann::json& primitive() { return j["meshes"][0]["primitives"][0]; }
  nlohmann::json& material() { return j["materials"][0]; }
};

inline constexpr int kFloatType = 5126, kUByteType = 5121, kUShortType = 5123;

// The quad with `material` (a glTF material object) as material 0, ambient `ambient`, and a
// directional light of intensity `light` when light > 0.
inline MaterialDoc material_quad(const std::filesystem::path& dir, const nlohmann::json& material,
                                 float ambient, float light) {
  MaterialDoc d;
  d.dir = dir;
  nlohmann::json& j = d.j;
  j["asset"] = {{"version", "2.0"}};
  const std::vector<float> pos = {-1, 1, 0, 1, 1, 0, 1, -1, 0, -1, -1, 0};
  const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<float> uv = {0, 0, 1, 0, 1, 1, 0, 1};
  const std::vector<uint16_t> idx = {0, 3, 2, 0, 2, 1};  // counter-clockwise seen from +z
  const int p = d.accessor(pos, 3, kFloatType, "VEC3");
  j["accessors"][p]["min"] = {-1, -1, 0};
  j["accessors"][p]["max"] = {1, 1, 0};
  const int n = d.accessor(nrm, 3, kFloatType, "VEC3");
  const int t = d.accessor(uv, 2, kFloatType, "VEC2");
  const int i = d.accessor(idx, 1, kUShortType, "SCALAR");
  j["meshes"] = nlohmann::json::array(
      {{{"primitives", nlohmann::json::array(
                           {{{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}},
                             {"indices", i},
                             {"material", 0}}})}}});
  j["images"] = nlohmann::json::array();
  j["textures"] = nlohmann::json::array();
  j["samplers"] = nlohmann::json::array(
      {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}});
  j["materials"] = nlohmann::json::array({material});
  j["nodes"] = nlohmann::json::array(
      {{{"mesh", 0}}, {{"camera", 0}, {"translation", {0, 0, 10}}, {"name", "front"}}});
  j["cameras"] = nlohmann::json::array(
      {{{"type", "orthographic"},
        {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 100}}}}});
  j["scenes"] = nlohmann::json::array({{{"nodes", {0, 1}}}});
  j["scene"] = 0;
  j["extensions"]["RELIEF_relief_mapping"] = {{"ambient", {ambient, ambient, ambient}},
                                              {"background", {0, 0, 0, 1}}};
  j["extensionsUsed"] = {"RELIEF_relief_mapping"};
  if (light > 0.0f) {
    j["extensionsUsed"].push_back("KHR_lights_punctual");
    j["extensions"]["KHR_lights_punctual"]["lights"] =
        nlohmann::json::array({{{"type", "directional"}, {"intensity", light}}});
    j["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    j["scenes"][0]["nodes"].push_back(2);
  }
  return d;
}

// Adds an extension name to extensionsUsed once.
inline void use_extension(MaterialDoc& d, const char* name) {
  for (const auto& e : d.j["extensionsUsed"])
    if (e == name) return;
  d.j["extensionsUsed"].push_back(name);
}

}  // namespace relief::test
