// Inputs of the sampler tests: a texture of random texels with a full mip chain, a sampler.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "rasterizer/texture.h"

namespace relief::testing {

inline Texture random_texture(TexFormat f, int w, int h, ColorSpace cs, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> texels(size_t(w) * h * format_bytes_per_texel(f));
  for (auto& b : texels) b = static_cast<uint8_t>(rng());
  Texture t(f, w, h, texels.data(), cs);
  t.generate_mips();
  return t;
}

inline SamplerState sampler_state(Filter filter, Wrap wrap_u, Wrap wrap_v) {
  SamplerState s;
  s.filter = filter;
  s.wrap_u = wrap_u;
  s.wrap_v = wrap_v;
  return s;
}

}  // namespace relief::testing
