// Internal to scene/gltf*.cpp (not installed, cmake/install.cmake): what glTF reading (gltf.cpp)
// and writing (gltf_write.cpp) share (scene/gltf.h, docs/scene-format.md): glTF 2.0 (Khronos
// specification) with the extensions named below.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace relief::gltf_detail {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline constexpr const char* kTextureTransform = "KHR_texture_transform";
inline constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";
inline constexpr const char* kUnlit = "KHR_materials_unlit";
inline constexpr const char* kLightsPunctual = "KHR_lights_punctual";
inline constexpr double kPi = 3.14159265358979323846;

// GL enums used by glTF samplers and accessors.
inline constexpr int kNearest = 9728, kLinear = 9729, kNearestMipNearest = 9984,
                     kLinearMipNearest = 9985, kNearestMipLinear = 9986, kLinearMipLinear = 9987;
inline constexpr int kClampToEdge = 33071, kMirroredRepeat = 33648, kRepeat = 10497;
inline constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125,
                     kFloat = 5126;

// Whether `s` ends with `suffix` (given in lower case), in any case (gltf.cpp).
bool has_suffix(const std::string& s, const char* suffix);

// The normal map load_gltf derives from a relief material's depth map when the file gives none
// (gltf.cpp); save_gltf leaves out a normal map equal to it.
Texture derived_normal_map(const Material& mat, const Texture& depth);

}  // namespace relief::gltf_detail
