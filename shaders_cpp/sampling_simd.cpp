#include "shaders_cpp/sampling_simd.h"

namespace relief {
namespace {

// Vectors cross the baseline/AVX2 boundary through memory: passing 32-byte vectors by value
// between functions compiled for different targets would change the calling convention.
struct RLodArgs {
  const Texture* t;
  const SamplerState* s;
  const V2<F8>* uv;
  const F8* lod;
  F8* out;
};

[[gnu::always_inline]] inline void r_lod_body(const RLodArgs& a) {
  *a.out = texture_r_lod(*a.t, *a.s, *a.uv, *a.lod);
}
RELIEF_BASE_ENTRY void r_lod_base(const RLodArgs& a) { r_lod_body(a); }
RELIEF_AVX2_ENTRY void r_lod_avx2(const RLodArgs& a) { r_lod_body(a); }

}  // namespace

void texture_r_lod_into(const Texture& t, const SamplerState& s, const V2<F8>& uv, const F8& lod,
                        F8* out) {
  const RLodArgs a{&t, &s, &uv, &lod, out};
  if (simd_avx2())
    r_lod_avx2(a);
  else
    r_lod_base(a);
}

}  // namespace relief
