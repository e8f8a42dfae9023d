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
// One AVX2 clone per format of the lane-parallel path (texture_r_lod's own switch, taken before
// the call): the depth searches' R8 read is compiled, and its registers allocated, without the
// other formats' code around it (measured: 9% fewer instructions a read than one clone for all).
template <TexFormat kFmt>
RELIEF_AVX2_ENTRY void r_lod_fmt_avx2(const RLodArgs& a) {
  *a.out = detail::sample_lod_texels<kFmt, 1, F8>(*a.t, *a.s, *a.uv, *a.lod).x;
}

struct GradArgs {
  const Texture* t;
  const SamplerState* s;
  const V2<F8>* uv;
  const V2<F8>* dx;
  const V2<F8>* dy;
  V4<F8>* out;
};

[[gnu::always_inline]] inline void grad_body(const GradArgs& a) {
  *a.out = texture_grad(*a.t, *a.s, *a.uv, *a.dx, *a.dy);
}
RELIEF_BASE_ENTRY void grad_base(const GradArgs& a) { grad_body(a); }
RELIEF_AVX2_ENTRY void grad_avx2(const GradArgs& a) { grad_body(a); }

}  // namespace

void texture_r_lod_into(const Texture& t, const SamplerState& s, const V2<F8>& uv, const F8& lod,
                        F8* out) {
  const RLodArgs a{&t, &s, &uv, &lod, out};
  if (!simd_avx2()) return r_lod_base(a);
  if (!detail::vector_sampling_ok(t, s)) return r_lod_avx2(a);  // the scalar sampler per lane
  switch (t.format()) {
    case TexFormat::kR8:
      return r_lod_fmt_avx2<TexFormat::kR8>(a);
    case TexFormat::kRG8:
      return r_lod_fmt_avx2<TexFormat::kRG8>(a);
    case TexFormat::kR32F:
      return r_lod_fmt_avx2<TexFormat::kR32F>(a);
    default:
      return r_lod_fmt_avx2<TexFormat::kRGBA8>(a);
  }
}

void texture_grad_into(const Texture& t, const SamplerState& s, const V2<F8>& uv,
                       const V2<F8>& dx, const V2<F8>& dy, V4<F8>* out) {
  const GradArgs a{&t, &s, &uv, &dx, &dy, out};
  if (simd_avx2())
    grad_avx2(a);
  else
    grad_base(a);
}

}  // namespace relief
