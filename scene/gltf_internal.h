// Internal to scene/gltf*.cpp (not installed, cmake/install.cmake): what glTF reading and writing
// share, and the Reader class behind load_gltf (scene/gltf.h, docs/scene-format.md). glTF 2.0
// (Khronos specification) with the extensions named below. Each part of the Reader is defined in
// the file its section names; every error names the file and the JSON pointer of the value.
#pragma once

#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include <glm/mat2x2.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "base/status.h"
#include "rasterizer/safe_file.h"
#include "scene/animation.h"
#include "scene/image_io.h"
#include "scene/scene.h"

namespace relief::gltf_detail {

namespace fs = std::filesystem;
using json = nlohmann::json;

inline constexpr const char* kTextureTransform = "KHR_texture_transform";
inline constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";
inline constexpr const char* kUnlit = "KHR_materials_unlit";
inline constexpr const char* kMetallicRoughnessSlot = "metallic_roughness";  // a material-wide slot
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

// The slot read_material loads a cone map under when the file leaves its kind to the technique;
// it moves to MaterialSource::cone_texture before the material is returned.
inline constexpr const char* kConeOfTechnique = "cone_?";

// A texture transform (KHR_texture_transform): uv' = T(offset) R(rotation) S(scale) uv.
struct UvTransform {
  glm::dvec2 offset{0.0};
  glm::dvec2 scale{1.0};
  double rotation = 0.0;
  bool operator==(const UvTransform&) const = default;
  int tex_coord = 0;  // the TEXCOORD_n it reads (textureInfo's, or the extension's override)
  glm::vec2 apply(glm::vec2 uv) const {
    const double c = std::cos(rotation), s = std::sin(rotation);
    const double u = scale.x * uv.x, v = scale.y * uv.y;
    return glm::vec2(static_cast<float>(c * u + s * v + offset.x),
                     static_cast<float>(-s * u + c * v + offset.y));
  }
  // The linear part (columns) and offset of apply.
  glm::dmat2 linear() const {
    const double c = std::cos(rotation), s = std::sin(rotation);
    return glm::dmat2(glm::dvec2(c * scale.x, -s * scale.x), glm::dvec2(s * scale.y, c * scale.y));
  }
};

// A texture reference (textureInfo) wherever it appears.
struct TexRef {
  std::string pointer;  // JSON pointer of the textureInfo object
  int index = -1;
  int tex_coord = 0;
  json transform;  // KHR_texture_transform object, or null
};

enum class TexUse { kColor, kLinear, kDepth, kHeight, kCone };

struct PrimitiveKey {
  int mesh, primitive;
  auto operator<=>(const PrimitiveKey&) const = default;
};

class Reader {
 public:
  // `model` has passed validate_gltf_text (schema, hierarchy, draw limits) in load_gltf.
  Reader(std::string path, tinygltf::Model& model) : path_(std::move(path)), m_(model) {}

  Result<Scene> read();

  // Where the scene's URIs resolve (load_gltf sets it from its options).
  void set_scene_folder(SceneFolder folder) { folder_ = std::move(folder); }

 private:
  struct MaterialInfo {
    Material material;
    bool bake_uv = false;   // a rotated texture transform, applied to the primitives' uvs
    UvTransform uv;         // the main texture's (the uv varying's)
    std::string needs_uv1;  // pointer of a textureInfo reading TEXCOORD_1, empty if none
  };
  struct CameraNode {
    int camera, node, order;
    glm::dmat4 world;
  };
  // A texture a material reads: (slot, reference, use).
  struct TextureSlot {
    std::string name;
    TexRef ref;
    TexUse use;
  };
  struct View {
    const uint8_t* data = nullptr;
    size_t stride = 0;
    size_t count = 0;
    int comps = 0;
    int ctype = 0;
    bool normalized = false;
  };

  // ---- JSON helpers for extension objects (gltf_read_json.cpp) ----
  Status fail(const std::string& pointer, const std::string& what) const;
  static Result<json> parse_json(const std::string& text);
  Result<json> extension(const std::string& extensions_json, const char* name,
                         const std::string& pointer) const;
  Status check_keys(const json& obj, const std::string& pointer,
                    const std::vector<std::string>& known) const;
  Status get_number(const json& obj, const char* key, const std::string& pointer, double& out,
                    double lo = -std::numeric_limits<double>::infinity(),
                    double hi = std::numeric_limits<double>::infinity()) const;
  Status get_int(const json& obj, const char* key, const std::string& pointer, int& out, int lo,
                 int hi) const;
  Status get_bool(const json& obj, const char* key, const std::string& pointer, bool& out) const;
  template <int N>
  Status get_vec(const json& obj, const char* key, const std::string& pointer,
                 glm::vec<N, double>& out, double lo, double hi) const;  // below
  static std::string fmt(double v);

  // ---- top level (gltf.cpp) ----
  Status check_required_extensions() const;
  Status read_root_extension();

  // ---- textures (gltf_read_textures.cpp) ----
  Result<TexturePtr> exact_texels(const TexRef& r, TexUse use, bool mipmapped);
  Result<TexRef> tex_ref_from_json(const json& j, const std::string& pointer) const;
  Result<TexRef> tex_ref(int index, int tex_coord, const std::string& extensions_json,
                         const std::string& pointer) const;
  Result<UvTransform> uv_transform(const TexRef& r) const;
  Result<SamplerState> sampler_of(const TexRef& r, bool& mipmapped) const;
  Result<TexturePtr> texture(const TexRef& r, TexUse use, bool mipmapped);
  static std::string renamed(const std::string& message, const ResolvedUri& file);
  static Result<Texture> decode_in_memory(const tinygltf::Image& img,
                                          const TextureLoadOptions& opt);

  // ---- materials (gltf_read_materials.cpp) ----
  Result<MaterialInfo> read_material(int index);
  Status read_core_material(const tinygltf::Material& gm, const std::string& mp, Material& mat,
                            std::vector<TextureSlot>& slots) const;
  Status read_khr_material_extensions(const tinygltf::Material& gm, const std::string& mp,
                                      Material& mat) const;
  Status read_relief_material(const json& e, const std::string& ep, Material& mat,
                              std::vector<TextureSlot>& slots, bool& normal_from_depth,
                              int& max_aniso) const;
  Status read_relief_textures(const json& e, const std::string& ep, bool depth_is_height,
                              Material& mat, std::vector<TextureSlot>& slots) const;
  Status read_relief_params(const json& e, const std::string& ep, Material& mat) const;
  Status read_height_ao(const json& e, const std::string& ep, Material& mat) const;
  Status load_material_textures(const std::vector<TextureSlot>& slots, MaterialInfo& info);

  // ---- accessors and meshes (gltf_read_meshes.cpp) ----
  Result<View> view(int index, const std::string& where) const;
  static float component(const uint8_t* p, int ctype, bool normalized);
  template <int N>
  Status read_attr(int index, const std::string& where, bool allow_normalized,
                   std::vector<glm::vec<N, float>>& out) const;
  bool uses_extension(const char* name) const;
  Status read_indices(int index, const std::string& where, std::vector<uint32_t>& out) const;
  Result<int> primitive_mesh(int mesh, int prim, int material_index, int deform_node = -1);
  Status read_vertices(const tinygltf::Primitive& p, const std::string& ap, int material_index,
                       Mesh& out) const;
  Status read_triangles(const tinygltf::Primitive& p, const std::string& pp, Mesh& out) const;
  Status read_deformation(const tinygltf::Primitive& p, const std::string& pp, Deformer& d) const;
  Status read_floats(int index, const std::string& where, int type, std::vector<int> ctypes,
                     std::vector<float>& out) const;

  // ---- nodes, lights and cameras (gltf_read_nodes.cpp) ----
  Result<glm::dmat4> local_matrix(int index) const;
  Status read_nodes();
  Status read_node_light(int node, const glm::dmat4& world);
  Status camera_hint(const CameraNode& cn, Camera& c) const;
  Status place_cameras();
  static Camera default_camera(const glm::dvec3& centre, double radius);

  // ---- animations, skins, morph weights (gltf_read_animation.cpp) ----
  Status read_animation();
  Status read_skins(SceneAnimation& anim) const;
  Status node_weights(int i, std::vector<float>& out) const;
  Result<AnimationClip> read_clip(int index, const SceneAnimation& anim) const;

  SceneFolder folder_;
  std::string path_;
  tinygltf::Model& m_;
  Scene scene_;
  std::vector<MaterialInfo> materials_;
  int default_material_ = -1;
  std::map<PrimitiveKey, int> meshes_;
  std::map<std::tuple<int, int, bool>, TexturePtr> textures_;
  std::vector<CameraNode> camera_nodes_;
  // Animation: parents, which node each instance, camera and light follows, deformed meshes.
  std::vector<int> node_parent_;
  std::vector<NodeBinding> instance_nodes_, camera_nodes_bound_, light_nodes_;
  std::vector<Deformer> deformers_;
  glm::dvec3 centre_{0.0};
};

template <int N>
Status Reader::get_vec(const json& obj, const char* key, const std::string& pointer,
                       glm::vec<N, double>& out, double lo, double hi) const {
  auto it = obj.find(key);
  if (it == obj.end()) return {};
  const std::string p = pointer + "/" + key;
  if (!it->is_array() || it->size() != N)
    return fail(p, "expected an array of " + std::to_string(N) + " numbers");
  for (int i = 0; i < N; ++i) {
    const json& x = (*it)[i];
    if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
        x.get<double>() > hi)
      return fail(p + "/" + std::to_string(i),
                  "expected a number in [" + fmt(lo) + ", " + fmt(hi) + "], got " + x.dump());
    out[i] = x.get<double>();
  }
  return {};
}

}  // namespace relief::gltf_detail
