// Lane-parallel texture reads as out-of-line entry points, one per SIMD target
// (shaders_cpp/sampling_simd.cpp is compiled for every target of base/simd.h): same IEEE
// operations, same bits as texture_r_lod / texture_grad (sampling.h). Kernels call these instead
// of inlining the sampler: inlined, every format, filter and level path of the sampler is copied
// into every kernel variant, which made the kernels too large to compile in reasonable time
// (docs/performance.md); out of line they cost a call a read. Each takes and returns the target's
// native lanes (FN) by value: caller and callee are always compiled for the same target.
//
// Per-target header (lanes.h says how).
#if defined(RELIEF_SHADERS_CPP_SAMPLING_SIMD_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_SAMPLING_SIMD_H_
#undef RELIEF_SHADERS_CPP_SAMPLING_SIMD_H_
#else
#define RELIEF_SHADERS_CPP_SAMPLING_SIMD_H_
#endif

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/sampling.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

// texture_r_lod over the native lanes.
FN texture_r_lod_lanes(const Texture& t, const SamplerState& s, const V2<FN>& uv, const FN& lod);

// Whether a[0..kLanes) and b[0..kLanes) hold the same bits (memcmp's answer, in one vector test:
// the XOR of the two is zero in every lane).
inline bool same_lane_bits(const float* a, const float* b) {
  return !any(MV<kLanes>{bits_of(FN::load(a)).v ^ bits_of(FN::load(b)).v});
}

// texture_r_lod prepared for many reads at one texture, sampler and LOD per lane (a depth
// search: the LOD is per quad and fixed along the ray). prepare_r_lod chooses the mip levels,
// their sizes and where their texels come from once; each read then computes only its
// coordinates, texel loads and lerps, in an entry specialised for the texture's format and the
// filter (nearest, one bilinear level or two blended). When the lanes' LODs fall on different
// levels it reads through texture_r_lod_lanes. Same bits as texture_r_lod either way.
//
// A plan is a cache that every depth source holds (TextureDepth, one a group of lanes), so it is
// cheap to make: only `texture` (null: not prepared) and the small fields start set, and the
// arrays are written by prepare_r_lod before any read uses them (zeroing them in every
// TextureDepth took 1.9% of the lean relief's time). A copy starts unprepared rather than
// copying: the copy's owner may be retargeted (relief_dual's back layer), and it reads nothing
// of the original.
struct RLodPlan {
  using Level = detail::LevelAccess<int32_t>;  // what bilinear_at / nearest_at read, per plan
  using Read = FN (*)(const RLodPlan&, const V2<FN>&);
  RLodPlan() {}  // user-provided: value-initialising a plan (`{}`) does not zero it either
  RLodPlan(const RLodPlan&) {}
  RLodPlan& operator=(const RLodPlan&) {
    texture = nullptr;
    return *this;
  }
  const Texture* texture = nullptr;
  SamplerState sampler;
  float lod[kLanes];  // the LODs it was prepared for (compared bit for bit)
  float f[kLanes];    // the second level's weight per lane (two levels)
  // Lanes on two neighbouring pairs of levels (straddling): level[0..2] are three levels in a
  // row, and upper[i] is 1 where lane i reads level[1] and level[2] rather than level[0] and
  // level[1], else 0.
  float upper[kLanes];
  bool straddles = false;  // the lanes straddle (planned_straddle reads)
  Level level[3];
  bool pow2 = false;
  const float* lut = nullptr;  // srgb8_table() for an sRGB texture's footprint reads, else null
  // level[0..1] again in lanes, for footprint and nearest reads (PlannedFilter in
  // sampling_simd.cpp)
  detail::LevelLanes<FN> lanes[2];
  bool shared_levels =
      false;  // every lane on level[0] (and level[1]), or straddling: planned reads
  Read read = nullptr;

  // Whether this plan serves texture t, sampler s and the lanes' LODs lod[0..kLanes).
  bool prepared_for(const Texture& t, const SamplerState& s, const float* l) const {
    return texture == &t && sampler.filter == s.filter && sampler.wrap_u == s.wrap_u &&
           sampler.wrap_v == s.wrap_v && same_lane_bits(lod, l);
  }
};

void prepare_r_lod(const Texture& t, const SamplerState& s, const float* lod, RLodPlan* plan);

// texture_r_lod at uv with the LODs lod[0..kLanes), through `plan`, which is prepared again when
// it was made for another texture, sampler or LODs.
inline FN texture_r_lod_planned(const Texture& t, const SamplerState& s, const float* lod,
                                const V2<FN>& uv, RLodPlan& plan) {
  if (!plan.prepared_for(t, s, lod)) prepare_r_lod(t, s, lod, &plan);
  return plan.read(plan, uv);
}

// The quad-directional cone map's value in one texel c (its four channels): the larger of
// channels shift_u / 16 and 2 + shift_v / 16 (shifts 0 or 16).
inline float quad_cone_pick(const glm::vec4& c, int shift_u, int shift_v) {
  const float a = c[shift_u / 16], b = c[2 + shift_v / 16];
  return a < b ? b : a;
}

// The quad-directional cone read (shaders_cpp/cone.h QuadTextureCone): per lane i, the larger
// (`a < b ? b : a`) of channels 0 + shift_u[i] / 16 and 2 + shift_v[i] / 16 (shifts 0 or 16) of
// sample_lod(t, s, uv, lod[i]), with its bits. An RGBA16F texture (the baked quad cone map) read
// with nearest filtering and clamp or repeat wraps, every lane on one mip level, is read over the
// lanes: the level chosen once for the LODs (`plan`, prepared again when the texture, sampler or
// LODs change), one 8-byte load a lane (gathered on AVX2 and AVX-512), the two halves decoded
// over the lanes. Anything else reads sample_lod lane by lane. `plan.read` stays a valid read of
// channel 0 (the whole sampler per read).
FN quad_cone_lanes(const Texture& t, const SamplerState& s, const float* lod, const V2<FN>& uv,
                   const IN& shift_u, const IN& shift_v, RLodPlan& plan);

// texture_r_lod for kernels over either lane type: native lanes through the out-of-line entry.
template <class F>
inline F texture_r_lod_call(const Texture& t, const SamplerState& s, const V2<F>& uv,
                            const F& lod) {
  if constexpr (std::is_same_v<F, FN>)
    return texture_r_lod_lanes(t, s, uv, lod);
  else
    return texture_r_lod(t, s, uv, lod);
}

// texture_grad over the native lanes.
V4<FN> texture_grad_lanes(const Texture& t, const SamplerState& s, const V2<FN>& uv,
                          const V2<FN>& dx, const V2<FN>& dy);

// texture_grad for kernels over either lane type: native lanes through the out-of-line entry.
template <class F>
inline V4<F> texture_grad_call(const Texture& t, const SamplerState& s, const V2<F>& uv,
                               const V2<F>& dx, const V2<F>& dy) {
  if constexpr (std::is_same_v<F, FN>)
    return texture_grad_lanes(t, s, uv, dx, dy);
  else
    return texture_grad(t, s, uv, dx, dy);
}

// texture_lod (4 channels) over the native lanes; t and s must be on the lane path
// (grad_reads_at_lod).
V4<FN> texture_lod_lanes(const Texture& t, const SamplerState& s, const V2<FN>& uv, const FN& lod);

// texture_grad_call with the LOD kept in `memo` between reads (GradLodMemo): the same bits.
template <class F>
inline V4<F> texture_grad_call(const Texture& t, const SamplerState& s, const V2<F>& uv,
                               const V2<F>& dx, const V2<F>& dy, GradLodMemo<F>& memo) {
  if (!grad_reads_at_lod(t, s)) return texture_grad_call(t, s, uv, dx, dy);
  const F& lod = memo.lod_for(t, dx, dy);
  if constexpr (std::is_same_v<F, FN>)
    return texture_lod_lanes(t, s, uv, lod);
  else
    return texture_lod(t, s, uv, lod);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_SAMPLING_SIMD_H_
