// Lane-parallel texture reads for kernels whose packet loop is baseline code (the relief family:
// flattening their large kernels into AVX2 clones costs too much compile time). The sampler is the
// hot part of their searches, so it gets its own entry points with AVX2 clones (rasterizer/simd.h)
// chosen at run time: same IEEE operations, same bits as texture_r_lod (sampling.h) either way.
#pragma once

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/sampling.h"

namespace relief {

// texture_r_lod over eight lanes into *out, through the AVX2 clone where the CPU has it. Out of
// line, so it must not pass or return vectors by value: a struct holding a 32-byte vector is
// returned in a register by AVX code and through memory by baseline code, and an AVX2 clone
// calling this baseline function would read its result from the wrong place.
void texture_r_lod_into(const Texture& t, const SamplerState& s, const V2<F8>& uv, const F8& lod,
                        F8* out);

inline F8 texture_r_lod_dispatch(const Texture& t, const SamplerState& s, const V2<F8>& uv,
                                 const F8& lod) {
  F8 out;
  texture_r_lod_into(t, s, uv, lod, &out);
  return out;
}

}  // namespace relief
