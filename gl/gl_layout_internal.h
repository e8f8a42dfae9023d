// What the GL backend's C++ side and its GLSL twins agree on beyond the uniforms: texture units,
// storage-block bindings and the layouts of the buffers the backend fills. The generated prelude
// (gl/tools/glsl_prelude.cpp) writes every value here for GLSL under the same name, so the twins
// copy none of them by hand (docs/plugins.md, "Adding a built-in technique").
#pragma once

#include "shaders_cpp/uniforms.h"

namespace relief::gl_layout {

// Texture units: the material's slots at 0 .. kMaxTextureSlots - 1 (common.glsl textures[]), one
// shadow-map array per light from kShadowUnit (shadow_map.glsl shadow_depth[]), then the glTF
// emissive, occlusion and metallic-roughness textures, then the frame's environment: its
// prefiltered specular chain and split-sum table (common.glsl).
inline constexpr int kShadowUnit = kMaxTextureSlots;
inline constexpr int kEmissiveUnit = 16;
inline constexpr int kOcclusionUnit = 17;
inline constexpr int kMetallicRoughnessUnit = 18;
inline constexpr int kEnvSpecularUnit = 19;
inline constexpr int kEnvBrdfUnit = 20;
static_assert(kShadowUnit + kMaxLights <= kEmissiveUnit, "shadow units overlap the emissive unit");

// Storage-block bindings.
inline constexpr int kCountersBinding = 0;        // common.glsl WorkCountersBuffer
inline constexpr int kHeightFieldBinding = 1;     // exact.glsl HeightFieldBuffer
inline constexpr int kShadowViewsBinding = 2;     // shadow_map.glsl ShadowViewsBuffer
inline constexpr int kTrianglePlanesBinding = 3;  // common.glsl TrianglePlanesBuffer

// TrianglePlanesBuffer: per triangle a header of kTriangleHeader words (first part's offset, part
// count, varying count, unused), then its parts (gl_resources.cpp upload_draws).
inline constexpr int kTriangleHeader = 4;

// ShadowViewsBuffer: per light kShadowViewHeader floats (size, faces, orthographic, position,
// direction, biases, PCF radius), then kMaxShadowFaces view and as many projection matrices.
inline constexpr int kShadowViewHeader = 16;

// WorkCountersBuffer: kCounterSlots slots (pixels hash into them, to spread the atomics) of
// kCounterCount counters each, in this order; GlBackend::read_counters sums them.
inline constexpr int kCounterSlots = 256;
inline constexpr int kCounterFragments = 0, kCounterFetches = 1, kCounterSearchSteps = 2,
                     kCounterShadowSteps = 3, kCounterDiscarded = 4, kCounterCount = 5;

}  // namespace relief::gl_layout
