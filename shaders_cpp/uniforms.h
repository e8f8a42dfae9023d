// What a pass and a draw hand every kernel (DESIGN.md, "The fragment-shader plugin ABI"): the
// standard varying layout and the frame, light and material uniforms. Part of the plugin ABI
// (plugins/plugin.h includes it; kPluginAbiVersion covers it), kept here so that kernels need not
// depend on plugins: plugins depend on kernels, never the reverse.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/image.h"
#include "rasterizer/texture.h"
#include "shaders_cpp/environment_maps.h"

namespace relief {

inline constexpr int kMaxTextureSlots = 8;
inline constexpr int kMaxParams = 32;

// ---- the standard varying layout the scene feeds every plugin ----
namespace varying {
inline constexpr int kPosition = 0;    // world position xyz
inline constexpr int kNormal = 3;      // world normal xyz (not normalised)
inline constexpr int kTangent = 6;     // world tangent xyz, bitangent sign w
inline constexpr int kUv = 10;         // texture coordinates (material tiling applied)
inline constexpr int kQuadric = 12;    // per-vertex quadric coefficients a, b; for a layered
                                       // material (PluginDescriptor::layers) instead the shell
                                       // index i and the layer count N, as floats
inline constexpr int kTileScale = 14;  // texture-tile size sx, sy in object units
inline constexpr int kCount = 16;
// Present only when the mesh has COLOR_0 or TEXCOORD_1 (FragmentPacket::num_varyings is then
// kCountExtended; absent ones read colour 1 and uv1 0).
inline constexpr int kColor = 16;  // vertex colour rgba (COLOR_0, linear)
inline constexpr int kUv1 = 20;    // second texture coordinates (TEXCOORD_1, untransformed)
inline constexpr int kCountExtended = 22;
}  // namespace varying

// ---- uniforms ----
// glTF material.alphaMode: OPAQUE ignores alpha; MASK discards fragments whose alpha is below
// alpha_cutoff (main and shadow passes); BLEND composites over the opaque image
// (docs/scene-format.md).
enum class AlphaMode : uint8_t { kOpaque, kMask, kBlend };

enum class LightType : uint8_t { kDirectional, kPoint, kSpot };

// How a material turns light into colour (shaders_cpp/lighting.h shade_direct): Blinn-Phong with
// `specular` and `shininess` (the papers' scenes, the built-in ones), or the glTF 2.0
// metallic-roughness BRDF (specification appendix B; what glTF files get unless they ask for
// Blinn-Phong).
enum class ShadingModel : uint8_t { kBlinnPhong, kMetallicRoughness };
// The smallest GGX alpha (roughness^2) the metallic-roughness BRDF uses: at alpha 0 the
// distribution is a delta (0/0 at n = h). Filament's fp32 bound (alpha 0.002025, roughness 0.045);
// a punctual light's highlight then peaks at about 1/(pi alpha^2) = 7.8e4 times its illuminance,
// finite in float.
inline constexpr float kMinGgxAlpha = 0.002025f;

struct ShadowMapView;  // defined by the renderer; opaque to plugins that do not receive shadows

struct LightUniform {
  LightType type = LightType::kDirectional;
  glm::vec3 position{0.0f};       // point and spot
  glm::vec3 direction{0, -1, 0};  // direction the light travels (directional, spot)
  glm::vec3 color{1.0f};          // linear radiance scale, intensity included
  float range = 0.0f;             // 0: no cut-off
  float inner_cone_cos = 1.0f;    // spot
  float outer_cone_cos = 0.0f;    // spot
  const ShadowMapView* shadow = nullptr;
};
inline constexpr int kMaxLights = 8;

// Per pass: camera and lights, the same for every draw of the pass.
struct FrameUniforms {
  glm::mat4 view{1.0f};
  glm::mat4 view_proj{1.0f};     // world -> clip, reversed-Z [0, 1]
  glm::vec3 eye{0.0f};           // camera (or light) position, world
  bool orthographic = false;     // eye rays are parallel to view_dir
  glm::vec3 view_dir{0, 0, -1};  // world, for orthographic views
  glm::vec3 ambient{0.03f};      // the indirect light when there is no environment
  // Image-based light (docs/environment.md): when set, it replaces `ambient` as the indirect
  // light of every material (shaders_cpp/lighting.h indirect_light).
  const EnvironmentMaps* environment = nullptr;
  EnvironmentView env_view;
  LightUniform lights[kMaxLights];
  int num_lights = 0;
  AovMask aovs = 0;           // AOVs the pass writes
  bool scalar_lanes = false;  // kernels one fragment at a time (reference path)
  int width = 0, height = 0;
};

// An affine map of texture coordinates, uv' = col0 * uv.x + col1 * uv.y + offset, from the uv
// varying (set 0: the main texture's transformed uv) or the raw TEXCOORD_1 (set 1). A slot's map
// is its KHR_texture_transform composed with the inverse of the main one (docs/scene-format.md).
struct UvMap {
  glm::vec2 col0{1.0f, 0.0f};
  glm::vec2 col1{0.0f, 1.0f};
  glm::vec2 offset{0.0f};
  int set = 0;
  bool identity = true;  // the identity on set 0: the varying uv as is
};

// Ambient occlusion from the height field (shaders_cpp/height_ao.h; the techniques built on
// plugins/relief_shell.h): `rays` azimuth directions (0: off, no work; at most 16) of radius
// `radius` uv units (the relief's depth_scale is in the same units), SurfaceColor::occlusion
// multiplied by 1 - strength * (1 - AO). docs/effects.md, "Height-field ambient occlusion".
struct HeightAoParams {
  int rays = 0;
  float radius = 0.05f;
  float strength = 1.0f;
};
inline constexpr int kMaxHeightAoRays = 16;

// Per draw: the material's parameter values (schema order), textures by slot and base colour.
struct MaterialUniforms {
  float params[kMaxParams] = {};
  const Texture* textures[kMaxTextureSlots] = {};
  SamplerState samplers[kMaxTextureSlots];
  glm::vec4 base_color{1.0f};
  ShadingModel shading = ShadingModel::kBlinnPhong;
  float specular = 0.25f;   // Blinn-Phong
  float shininess = 32.0f;  // Blinn-Phong
  // Metallic-roughness: the factors, times the metallicRoughness texture's blue (metallic) and
  // green (roughness) channels when one is bound.
  float metallic = 1.0f;
  float roughness = 1.0f;
  const Texture* metallic_roughness_texture = nullptr;  // linear
  SamplerState metallic_roughness_sampler;
  UvMap metallic_roughness_uv;
  AlphaMode alpha_mode = AlphaMode::kOpaque;
  float alpha_cutoff = 0.5f;  // MASK only
  // glTF material terms every plugin's final colour goes through (plugins/surface.h
  // finish_surface): material-wide, not plugin slots.
  UvMap uv_maps[kMaxTextureSlots];            // per slot, from the uv varying
  glm::vec3 emissive{0.0f};                   // emissiveFactor * emissive_strength, linear
  const Texture* emissive_texture = nullptr;  // sRGB, decoded to linear; multiplies `emissive`
  SamplerState emissive_sampler;
  UvMap emissive_uv;
  const Texture* occlusion_texture = nullptr;  // red channel: ambient term only
  SamplerState occlusion_sampler;
  UvMap occlusion_uv;
  float occlusion_strength = 1.0f;
  float normal_scale = 1.0f;  // normalTexture.scale: the decoded map's x and y
  bool unlit = false;         // KHR_materials_unlit: base colour only, no lights or shadows
  HeightAoParams height_ao;   // rays 0: off (no work)
};

}  // namespace relief
