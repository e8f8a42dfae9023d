// The fragment-shader plugin ABI (DESIGN.md, "The fragment-shader plugin ABI").
//
// A plugin is a PluginDescriptor: a name, a one-line description, a parameter schema, the texture
// slots it reads, the effects it supports, and `select`, which returns the packet shader for one
// combination of effects. Effects are compile-time parameters of the kernels, so `select` hands
// back a different template instantiation per combination and an unused effect costs nothing per
// fragment. The shader is called once per packet of quads (rasterizer/fragment.h); dispatch is
// resolved per draw, never per fragment.
//
// Built-in plugins mark their descriptor (plugins/builtin_plugins.h). An external plugin is a
// shared object exporting `extern "C" const relief::PluginDescriptor* relief_plugin_entry(void)`
// whose abi_version equals kPluginAbiVersion.
#pragma once

#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "rasterizer/fragment.h"
#include "rasterizer/texture.h"
#include "shaders_cpp/uniforms.h"

namespace relief {

inline constexpr uint32_t kPluginAbiVersion = 6;  // 2: reads_texture; 3: glTF material terms;
                                                  // 4: height-field AO uniforms; 5: layers;
                                                  // 6: shadow maps drawn on demand

// ---- parameters ----
enum class ParamType : uint8_t { kFloat, kInt, kBool, kEnum };

// One entry of a plugin's parameter schema. Values travel as float in schema order; an int or
// bool is a whole float, an enum the index of its choice in `choices` ("a|b|c").
struct ParamSpec {
  const char* name;
  ParamType type;
  float default_value;
  float min_value;
  float max_value;
  const char* choices;  // enums only, else nullptr
  const char* help;
};

// ---- textures ----
// Texture slots a plugin reads. Conventional names: "base_color" (sRGB colour), "normal"
// (tangent-space normal map, linear RGB, z up), "depth" (depth map: 0 at the reference surface,
// 1 deepest, linear), "cone" (cone ratios, derived).
struct TextureSlotSpec {
  const char* name;
  bool required;
  const char* help;
};

// ---- effects ----
enum Effect : uint32_t {
  kEffectSelfShadow = 1u << 0,     // trace a shadow ray through the height field to each light
  kEffectDepthWrite = 1u << 1,     // write the depth of the relief hit (depth correction)
  kEffectSilhouette = 1u << 2,     // discard rays that leave the surface (curved silhouettes)
  kEffectShadowPass = 1u << 3,     // running in a light's depth pass: intersection and depth only
  kEffectReceiveShadow = 1u << 4,  // look up shadow maps
  kEffectHeightAo = 1u << 5,       // ambient occlusion from the height field (a uniform branch)
};
using EffectMask = uint32_t;

// How a shader's depth relates to the polygon's: decides the rasterizer's depth-test path.
enum class DepthOutput : uint8_t {
  kNone,     // polygon depth: early test
  kFarther,  // relief depth, never closer than the polygon's: conservative early + late test
  kAny,      // arbitrary: late test only
};

// ---- the standard varying layout and the uniforms: shaders_cpp/uniforms.h ----

struct ShadeContext {
  const FrameUniforms* frame;
  const MaterialUniforms* material;
  const void* state;   // from PluginDescriptor::create_state, may be null
  EffectMask effects;  // the effects this variant was selected for
};

using ShadeFn = void (*)(const ShadeContext& ctx, const FragmentPacket& in, FragmentOutput& out,
                         WorkCounters& counters);

struct PluginDescriptor {
  uint32_t abi_version;
  const char* name;
  const char* description;
  const ParamSpec* params;
  int num_params;
  const TextureSlotSpec* textures;
  int num_textures;
  EffectMask supported_effects;
  // The packet shader for `effects` (a subset of supported_effects).
  ShadeFn (*select)(EffectMask effects);
  // Depth the variant writes.
  DepthOutput (*depth_output)(EffectMask effects);
  // Optional: derived data built once per material (max-mips, ...); freed by destroy_state.
  void* (*create_state)(const MaterialUniforms& material);
  void (*destroy_state)(void* state);
  // Optional: whether the shader, with these parameter values (schema order), reads texture slot
  // `slot`; null means it reads every slot it declares. The planner neither requires nor bakes
  // (derived maps) a slot that is not read, so a parameter that switches a map off saves its bake.
  bool (*reads_texture)(const float* params, int slot);
  // Optional: how many offset copies of the surface the prepare stage draws for a material with
  // these parameter values (schema order); null means 1, the plain surface. With the hook, copy
  // k of N (drawn in order k = 0..N-1, N >= 1) is the shell of height fraction h = (N-1-k)/N,
  // moved (1 - h) relief heights along -N (the polygon is the level of depth 0), and carries its
  // shell index N-1-k and N in varying::kQuadric (render/prepare.cpp); the planner alpha-tests
  // (MASK) such materials. Shell (fur) techniques use it.
  int (*layers)(const float* params);
};

}  // namespace relief
