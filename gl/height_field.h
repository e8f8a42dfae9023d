// The max-mip height field of the `exact` twin (gl/shaders/exact.glsl, HeightFieldBuffer), packed
// for a shader storage block from the same data the CPU's shaders_cpp/exact_trace.h HeightField is
// built from: the first channel of level 0 of the depth texture (Texture::fetch_r, as
// HeightField::from_texture reads it) and the sampler's wrap modes. Tevs, Ihrke and Seidel,
// "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008.
//
// The field is built once by HeightField::from_texture and copied through its read-only layout
// view, so both backends traverse the same numbers; tests/gl/height_field_test.cpp checks the
// packed field against HeightField::depth_at and the hierarchy against its definition.
#pragma once

#include <cstdint>
#include <vector>

#include "base/status.h"
#include "rasterizer/texture.h"

namespace relief::gl {

inline constexpr int kMaxFieldLevels = 16;  // exact.glsl kMaxFieldLevels

// std430 layout of HeightFieldBuffer, in 32-bit words: ints, then the floats of hf_data.
struct PackedHeightField {
  static constexpr int kPeriodic = 0, kSize = 2, kPeriod = 4, kCells = 6, kNumLevels = 8,
                       kLevelOffset = 9, kNx = kLevelOffset + kMaxFieldLevels,
                       kNy = kNx + kMaxFieldLevels, kHeaderWords = kNy + kMaxFieldLevels;
  std::vector<uint32_t> words;

  int header(int index) const { return static_cast<int>(words[index]); }
  float data(size_t i) const;  // hf_data[i]
  // texel (i, j) of the expanded field, node (i, j) of a level
  float texel(int i, int j) const;
  float node(int level, int i, int j) const;
};

// Packs level 0 of `depth` with the sampler's wraps. Fails when the max-mip would need more than
// kMaxFieldLevels levels (an axis above 32768 cells) or the texture is empty.
Result<PackedHeightField> pack_height_field(const Texture& depth, const SamplerState& sampler);

}  // namespace relief::gl
