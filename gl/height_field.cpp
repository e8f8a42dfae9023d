// Packs the max-mip of shaders_cpp/exact_trace.cpp (Tevs, Ihrke and Seidel, "Maximum Mipmaps for
// Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008) for
// gl/shaders/exact.glsl.
#include "gl/height_field.h"

#include <cstring>
#include <string>

#include "shaders_cpp/exact_trace.h"

namespace relief::gl {
namespace {

uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}

}  // namespace

float PackedHeightField::data(size_t i) const {
  float f;
  std::memcpy(&f, &words[kHeaderWords + i], sizeof(f));
  return f;
}
float PackedHeightField::texel(int i, int j) const {
  return data(static_cast<size_t>(j) * header(kPeriod) + i);
}
float PackedHeightField::node(int level, int i, int j) const {
  return data(static_cast<size_t>(header(kLevelOffset + level)) +
              static_cast<size_t>(j) * header(kNx + level) + i);
}

Result<PackedHeightField> pack_height_field(const Texture& depth, const SamplerState& sampler) {
  if (depth.empty()) return Status::error("exact: the depth texture is empty");
  const HeightField hf = HeightField::from_texture(depth, sampler);
  const int levels = hf.num_levels();
  if (levels > kMaxFieldLevels)
    return Status::error("exact: a " + std::to_string(hf.size(0)) + "x" +
                         std::to_string(hf.size(1)) + " depth map needs " + std::to_string(levels) +
                         " max-mip levels, the GL twin holds " + std::to_string(kMaxFieldLevels));
  PackedHeightField p;
  std::vector<uint32_t>& out = p.words;
  out.assign(PackedHeightField::kHeaderWords, 0u);
  for (int a = 0; a < 2; ++a) {
    out[PackedHeightField::kPeriodic + a] = hf.periodic(a);
    out[PackedHeightField::kSize + a] = hf.size(a);
    out[PackedHeightField::kPeriod + a] = hf.period(a);
    out[PackedHeightField::kCells + a] = hf.cells(a);
  }
  out[PackedHeightField::kNumLevels] = levels;
  size_t offset = hf.texels().size();
  for (int l = 0; l < levels; ++l) {
    out[PackedHeightField::kLevelOffset + l] = static_cast<uint32_t>(offset);
    out[PackedHeightField::kNx + l] = hf.level_width(l);
    out[PackedHeightField::kNy + l] = hf.level_height(l);
    offset += hf.level(l).size();
  }
  out.reserve(out.size() + offset);
  for (float v : hf.texels()) out.push_back(float_bits(v));
  for (int l = 0; l < levels; ++l)
    for (float v : hf.level(l)) out.push_back(float_bits(v));
  return p;
}

}  // namespace relief::gl
