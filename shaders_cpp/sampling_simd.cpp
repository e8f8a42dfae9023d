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

// Reads through a prepared plan: every lane on the plan's level(s), kLevels of them (1 or 2),
// with the filter of the plan's sampler (kNearest: nearest, else bilinear). A function, not a
// lambda: GCC left the lambda out of line as baseline code returning an F8, which the AVX2 clone
// called with the wrong calling convention.
template <TexFormat kFmt, bool kNearest>
[[gnu::always_inline]] inline F8 planned_level(const RLodPlan& p, const V2<F8>& uv, int k) {
  const RLodPlan::Level& l = p.level[k];
  const detail::LevelAccess<I8> at{I8(l.lvl), {I8(l.size.w), I8(l.size.h), I8(l.size.w_shift)},
                                   l.src};
  if constexpr (kNearest)
    return detail::nearest_at<kFmt, 1, F8>(*p.texture, p.sampler, uv, at, p.pow2).x;
  else
    return detail::bilinear_at<kFmt, 1, F8>(*p.texture, p.sampler, uv, at, p.pow2).x;
}
template <TexFormat kFmt, int kLevels, bool kNearest>
[[gnu::always_inline]] inline F8 planned_body(const RLodPlan& p, const V2<F8>& uv) {
  const F8 r = planned_level<kFmt, kNearest>(p, uv, 0);
  if constexpr (kLevels == 1) {
    return r;
  } else {
    const F8 r2 = planned_level<kFmt, kNearest>(p, uv, 1);
    return mix(r, r2, F8::load(p.f));  // lerp4's bits: r + (r2 - r) * f
  }
}
template <TexFormat kFmt, int kLevels, bool kNearest>
RELIEF_BASE_ENTRY void planned_base(const RLodPlan& p, const V2<F8>& uv, F8* out) {
  *out = planned_body<kFmt, kLevels, kNearest>(p, uv);
}
template <TexFormat kFmt, int kLevels, bool kNearest>
RELIEF_AVX2_ENTRY void planned_avx2(const RLodPlan& p, const V2<F8>& uv, F8* out) {
  *out = planned_body<kFmt, kLevels, kNearest>(p, uv);
}
// Lanes on different levels: the whole sampler per read.
void planned_mixed(const RLodPlan& p, const V2<F8>& uv, F8* out) {
  texture_r_lod_into(*p.texture, p.sampler, uv, F8::load(p.lod), out);
}

template <TexFormat kFmt, int kLevels, bool kNearest>
RLodPlan::Read planned_read() {
  if (simd_avx2()) return &planned_avx2<kFmt, kLevels, kNearest>;
  return &planned_base<kFmt, kLevels, kNearest>;
}
template <TexFormat kFmt>
RLodPlan::Read planned_read(int levels, bool nearest) {
  if (nearest) return planned_read<kFmt, 1, true>();
  return levels == 1 ? planned_read<kFmt, 1, false>() : planned_read<kFmt, 2, false>();
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

void prepare_r_lod(const Texture& t, const SamplerState& s, const float* lod, RLodPlan* plan) {
  RLodPlan& p = *plan;
  p.texture = &t;
  p.sampler = s;
  std::memcpy(p.lod, lod, sizeof(p.lod));
  p.read = &planned_mixed;
  p.shared_levels = false;
  if (!detail::vector_sampling_ok(t, s)) return;
  // Lane by lane in float (the same bits as lod_levels over F8), once per distinct LOD: kernels
  // hold one LOD per quad, so lanes usually repeat their neighbour's.
  detail::LodLevels<float> l = detail::lod_levels(t.levels(), s.filter, lod[0]);
  const int lo = l.lo, hi = l.hi;
  bool two = false, one_level = true;
  for (int i = 0; i < 8; ++i) {
    if (i > 0 && std::memcmp(&lod[i], &lod[i - 1], sizeof(float)) != 0)
      l = detail::lod_levels(t.levels(), s.filter, lod[i]);
    p.f[i] = l.f;
    two = two || l.f != 0.0f;
    one_level = one_level && l.lo == lo && l.hi == hi;
  }
  if (!one_level) return;
  p.shared_levels = true;
  p.pow2 = detail::pow2_texture(t);
  const int idx[2] = {lo, hi};
  for (int k = 0; k < 2; ++k) {
    const MipLevel& m = t.level(idx[k]);
    p.level[k] = {idx[k], detail::level_size(t, idx[k]), {&m, detail::can_gather<F8>(m)}};
  }
  const bool nearest = s.filter == Filter::kNearest;
  const int levels = two ? 2 : 1;
  switch (t.format()) {
    case TexFormat::kR8:
      p.read = planned_read<TexFormat::kR8>(levels, nearest);
      break;
    case TexFormat::kRG8:
      p.read = planned_read<TexFormat::kRG8>(levels, nearest);
      break;
    case TexFormat::kR32F:
      p.read = planned_read<TexFormat::kR32F>(levels, nearest);
      break;
    default:
      p.read = planned_read<TexFormat::kRGBA8>(levels, nearest);
      break;
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
