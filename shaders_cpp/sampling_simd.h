// Lane-parallel texture reads as out-of-line entry points, each compiled once for the whole
// program as baseline code and as an AVX2 clone (rasterizer/simd.h) chosen at run time: same IEEE
// operations, same bits as texture_r_lod / texture_grad (sampling.h) either way. Kernels call
// these instead of inlining the sampler: inlined, every format, filter and level path of the
// sampler is copied into every kernel variant's clone, which made the kernels' AVX2 clones too
// large to compile (docs/performance.md); out of line they cost a call and a few stores a read.
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

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

// texture_r_lod prepared for many reads at one texture, sampler and LOD per lane (a depth
// search: the LOD is per quad and fixed along the ray). prepare_r_lod chooses the mip levels,
// their sizes and where their texels come from once; each read then computes only its
// coordinates, texel loads and lerps, in an entry specialised for the texture's format and the
// filter (nearest, one bilinear level or two blended), picked by prepare_r_lod for the CPU. When
// the lanes' LODs fall on different levels it reads through texture_r_lod_into. Same bits as
// texture_r_lod either way.
struct RLodPlan {
  using Level = detail::LevelAccess<int32_t>;  // what bilinear_at / nearest_at read, per plan
  using Read = void (*)(const RLodPlan&, const V2<F8>&, F8*);
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[8] = {};  // the LODs it was prepared for (compared bit for bit)
  float f[8] = {};    // the second level's weight per lane (two levels)
  Level level[2] = {};
  bool pow2 = false;
  bool shared_levels = false;  // every lane on level[0] (and level[1]): the specialised reads
  Read read = nullptr;

  // Whether this plan serves texture t, sampler s and the lanes' LODs lod[0..8).
  bool prepared_for(const Texture& t, const SamplerState& s, const float* l) const {
    return texture == &t && sampler.filter == s.filter && sampler.wrap_u == s.wrap_u &&
           sampler.wrap_v == s.wrap_v && std::memcmp(lod, l, sizeof(lod)) == 0;
  }
};

void prepare_r_lod(const Texture& t, const SamplerState& s, const float* lod, RLodPlan* plan);

// texture_r_lod at uv with the LODs lod[0..8), through `plan`, which is prepared again when it
// was made for another texture, sampler or LODs.
inline F8 texture_r_lod_planned(const Texture& t, const SamplerState& s, const float* lod,
                                const V2<F8>& uv, RLodPlan& plan) {
  if (!plan.prepared_for(t, s, lod)) prepare_r_lod(t, s, lod, &plan);
  F8 out;
  plan.read(plan, uv, &out);
  return out;
}

// texture_grad over eight lanes into *out (same rules as texture_r_lod_into).
void texture_grad_into(const Texture& t, const SamplerState& s, const V2<F8>& uv,
                       const V2<F8>& dx, const V2<F8>& dy, V4<F8>* out);

inline V4<F8> texture_grad_dispatch(const Texture& t, const SamplerState& s, const V2<F8>& uv,
                                    const V2<F8>& dx, const V2<F8>& dy) {
  V4<F8> out;
  texture_grad_into(t, s, uv, dx, dy, &out);
  return out;
}

// texture_grad for kernels over either lane type: F8 through the out-of-line entry.
template <class F>
inline V4<F> texture_grad_call(const Texture& t, const SamplerState& s, const V2<F>& uv,
                               const V2<F>& dx, const V2<F>& dy) {
  if constexpr (std::is_same_v<F, F8>)
    return texture_grad_dispatch(t, s, uv, dx, dy);
  else
    return texture_grad(t, s, uv, dx, dy);
}

}  // namespace relief
