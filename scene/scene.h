// The scene model (DESIGN.md, "One frame, as data"): meshes, materials, instances, lights and
// cameras, in world units with y up and right-handed coordinates (glTF's convention).
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/texture.h"
#include "shaders_cpp/uniforms.h"

namespace relief {

struct Mesh {
  std::string name;
  std::vector<glm::vec3> positions;
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs;
  std::vector<glm::vec2> uvs1;        // TEXCOORD_1; empty when absent
  std::vector<glm::vec4> colors;      // COLOR_0 rgba (linear); empty when absent
  std::vector<glm::vec4> tangents;    // xyz tangent, w bitangent sign (B = w * cross(N, T))
  std::vector<glm::vec2> quadric;     // per-vertex (a, b); empty unless a material needs it
  std::vector<glm::vec2> tile_scale;  // per-vertex (sx, sy); empty unless a material needs it
  std::vector<uint32_t> indices;      // triangles
};

// A plugin parameter as a scene file wrote it: its JSON value, not yet typed by a technique's
// schema, and the JSON pointer it came from (render/validate.h types it).
struct FileParam {
  enum class Kind { kNumber, kBool, kText } kind = Kind::kNumber;
  double number = 0.0;
  bool boolean = false;
  std::string text;
  std::string pointer;
  // steps, binary_steps and depth_scale at the top of RELIEF_relief_mapping: a number the loader
  // has already read (and ranged) as the file format says; the rest ("params") take the type of
  // the technique that declares them.
  bool top_level = false;
};

// What a scene file said of a material that only the plugin registry can check: scene/ knows no
// technique, so the loader records the values with their JSON pointers, and validate_scene
// (render/validate.h; load_scene runs it) resolves them into Material::params, the cone map's
// "cone_<kind>" slot and the technique check, then clears this. A material built in code leaves
// it empty.
struct MaterialSource {
  std::string file;               // the scene file as messages name it; empty: nothing pending
  std::string technique_pointer;  // where the technique is named ("": the loader chose it)
  std::string slots_pointer;      // where a missing required texture is reported
  std::map<std::string, FileParam> params;  // by name
  TexturePtr cone_texture;  // cone_texture without cone_kind: the technique's cone map
  std::string cone_pointer;
  bool pending() const { return !file.empty(); }
};

struct Material {
  std::string name;
  std::string technique = "normal";            // plugin name
  std::map<std::string, float> params;         // by schema name; missing ones take defaults
  std::map<std::string, TexturePtr> textures;  // by slot name ("base_color", "depth", ...)
  // With no "normal" texture, a technique that reads one gets the normal map of the "depth"
  // texture (render/derived_maps.h: depth_scale from params, else the technique's default; wrap
  // when both sampler axes repeat). glTF files ask for it unless normal_from_depth is false.
  bool normal_from_depth = false;
  MaterialSource source;  // a scene file's values still to check (render/validate.h)
  glm::vec4 base_color{1.0f};
  glm::vec2 uv_scale{1.0f};  // tiling (KHR_texture_transform scale)
  glm::vec2 uv_offset{0.0f};
  SamplerState sampler;
  // Blinn-Phong (specular, shininess) for materials built in code (the papers' scenes); glTF
  // files get metallic-roughness unless RELIEF_relief_mapping asks for Blinn-Phong
  // (docs/scene-format.md, "Shading").
  ShadingModel shading = ShadingModel::kBlinnPhong;
  float specular = 0.25f;
  float shininess = 32.0f;
  float metallic = 1.0f;                  // pbrMetallicRoughness.metallicFactor
  float roughness = 1.0f;                 // pbrMetallicRoughness.roughnessFactor
  TexturePtr metallic_roughness_texture;  // linear: blue metallic, green roughness
  UvMap metallic_roughness_uv;
  bool double_sided = false;
  AlphaMode alpha_mode = AlphaMode::kOpaque;  // glTF alphaMode (shaders_cpp/uniforms.h)
  float alpha_cutoff = 0.5f;                  // glTF alphaCutoff, MASK only
  // Per texture slot (and the emissive and occlusion textures): the map from the uv varying (the
  // main texture's transformed uv, uv_scale/uv_offset above) to the slot's uv; identity if absent.
  std::map<std::string, UvMap> uv_maps;
  glm::vec3 emissive{0.0f};        // emissiveFactor
  float emissive_strength = 1.0f;  // KHR_materials_emissive_strength
  TexturePtr emissive_texture;     // sRGB
  UvMap emissive_uv;
  TexturePtr occlusion_texture;  // red channel
  UvMap occlusion_uv;
  float occlusion_strength = 1.0f;
  float normal_scale = 1.0f;  // normalTexture.scale
  bool unlit = false;         // KHR_materials_unlit
  // Ambient occlusion from the height field (RELIEF_relief_mapping "height_ao"; rays 0: off).
  // Relief materials only (a depth map), techniques built on plugins/relief_shell.h.
  HeightAoParams height_ao;
  // Effects the material asks for; the planner keeps those its plugin supports.
  bool self_shadow = false;
  bool depth_write = false;
  bool silhouette = false;
  bool casts_shadow = true;
  bool receives_shadow = true;
};

struct Instance {
  int mesh = 0;
  int material = 0;
  glm::mat4 transform{1.0f};  // object -> world
};

struct Light {
  std::string name;
  LightType type = LightType::kDirectional;
  glm::vec3 position{0.0f};
  glm::vec3 direction{0.0f, -1.0f, 0.0f};  // direction light travels
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;
  float inner_cone_deg = 20.0f;
  float outer_cone_deg = 30.0f;
  bool casts_shadows = false;
  int shadow_resolution = 1024;
};

struct Camera {
  std::string name;
  glm::vec3 position{0.0f, 0.0f, 3.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  float yfov_deg = 45.0f;
  float znear = 0.05f;
  float zfar = 100.0f;
  bool orthographic = false;
  float ortho_half_height = 1.0f;

  glm::mat4 view() const;
  // Reversed-Z projection onto [0, 1]: depth 1 at znear, 0 at zfar.
  glm::mat4 projection(float aspect) const;
};

struct SceneAnimation;  // scene/animation.h

// The most triangles one frame draws (each instance counts its mesh's triangles); make_plan
// refuses a scene with more, before anything is allocated for it (docs/errors.md, "Limits").
inline constexpr uint64_t kMaxSceneTriangles = uint64_t{1} << 23;
// The most mesh instances one frame draws (one per node and primitive); glTF files are checked
// against it from their JSON counts before any mesh is decoded.
inline constexpr uint64_t kMaxSceneInstances = 65536;
// The most vertices a loaded scene holds: each shared mesh once, each skinned or morphed
// instance its own posed and rest copies and morph targets (3 per triangle of the limit above).
inline constexpr uint64_t kMaxSceneVertices = 3 * kMaxSceneTriangles;
// The deepest node hierarchy a glTF file may have (a root is at depth 1).
inline constexpr int kMaxNodeDepth = 1024;

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Instance> instances;
  std::vector<Light> lights;
  std::vector<Camera> cameras;
  glm::vec3 ambient{0.03f};
  glm::vec4 background{0.0f, 0.0f, 0.0f, 1.0f};
  // Animations, skins and morph targets with the rest data they start from (scene/animation.h,
  // posed per frame by pose_scene); null for a static scene.
  std::shared_ptr<const SceneAnimation> animation;
};

// Reversed-Z perspective and orthographic matrices (clip z = w at near, 0 at far).
glm::mat4 perspective_reversed_z(float yfov_rad, float aspect, float znear, float zfar);
glm::mat4 ortho_reversed_z(float left, float right, float bottom, float top, float znear,
                           float zfar);

}  // namespace relief
