// Lane-parallel texture reads for kernels whose packet loop is baseline code (the relief family:
// flattening their large kernels into AVX2 clones costs too much compile time). The sampler is the
// hot part of their searches, so it gets its own entry points with AVX2 clones (rasterizer/simd.h)
// chosen at run time: same IEEE operations, same bits as texture_r_lod (sampling.h) either way.
#pragma once

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/sampling.h"

namespace relief {

// texture_r_lod over eight lanes, through the AVX2 clone where the CPU has it.
F8 texture_r_lod_dispatch(const Texture& t, const SamplerState& s, const V2<F8>& uv, const F8& lod);

}  // namespace relief
