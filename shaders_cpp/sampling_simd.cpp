// The out-of-line lane samplers of sampling_simd.h, compiled once per SIMD target.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shaders_cpp/sampling_simd.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include "shaders_cpp/sampling_simd.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

// One entry per format of the lane-parallel path (texture_r_lod's own switch, taken before the
// call): the depth searches' R8 read is compiled, and its registers allocated, without the other
// formats' code around it (measured: 9% fewer instructions a read than one entry for all).
// flatten here and below: the read inlined into one function (speed only; plugins/shading.h).
template <TexFormat kFmt>
[[gnu::noinline]] RELIEF_LANE_FLATTEN FN r_lod_fmt(const Texture& t, const SamplerState& s,
                                                   const V2<FN>& uv, const FN& lod) {
  return detail::sample_lod_texels<kFmt, 1, FN>(t, s, uv, lod).x;
}

// How a planned read filters a level: nearest, bilinear (bilinear_at, with all its paths), or
// bilinear from footprint words alone (bilinear_footprint_at: R8 levels that all have them, a
// depth search's usual read; without bilinear_at's fallbacks the entry needs no aligned stack
// frame and saves three registers instead of five; callgrind: 132 to 113 instructions a read on
// AVX2).
enum class PlannedFilter { kNearest, kBilinear, kFootprints };

// Reads through a prepared plan: every lane on the plan's level(s), kLevels of them (1 or 2),
// filtered by kFilter.
template <TexFormat kFmt, PlannedFilter kFilter>
[[gnu::always_inline]] inline FN planned_level(const RLodPlan& p, const V2<FN>& uv, int k) {
  const RLodPlan::Level& l = p.level[k];
  if constexpr (kFilter == PlannedFilter::kFootprints) {
    return detail::bilinear_footprint_at<FN>(p.sampler, uv, p.lanes[k], p.pow2, p.lut);
  } else if constexpr (kFilter == PlannedFilter::kNearest) {
    const detail::LevelLanes<FN>& n = p.lanes[k];
    const IN idx = detail::nearest_index_sized<FN>(p.sampler, uv, n.w, n.h, n.size, p.pow2);
    return detail::nearest_texel<kFmt, 1, FN>(*p.texture, idx, IN(l.lvl), l.src).x;
  } else {
    const detail::LevelAccess<IN> at{
        IN(l.lvl), {IN(l.size.w), IN(l.size.h), IN(l.size.w_shift)}, l.src};
    return detail::bilinear_at<kFmt, 1, FN>(*p.texture, p.sampler, uv, at, p.pow2).x;
  }
}
template <TexFormat kFmt, int kLevels, PlannedFilter kFilter>
RELIEF_LANE_FLATTEN FN planned(const RLodPlan& p, const V2<FN>& uv) {
  const FN r = planned_level<kFmt, kFilter>(p, uv, 0);
  if constexpr (kLevels == 1) {
    return r;
  } else {
    const FN r2 = planned_level<kFmt, kFilter>(p, uv, 1);
    return mix(r, r2, FN::load(p.f));  // lerp4's bits: r + (r2 - r) * f
  }
}
// Lanes on two neighbouring pairs of levels: all three levels read, each lane's pair blended
// (a top-level lane's weight is 0, its second level its first repeated).
template <TexFormat kFmt>
RELIEF_LANE_FLATTEN FN planned_straddle(const RLodPlan& p, const V2<FN>& uv) {
  constexpr PlannedFilter kBilinear = PlannedFilter::kBilinear;
  const FN r0 = planned_level<kFmt, kBilinear>(p, uv, 0);
  const FN r1 = planned_level<kFmt, kBilinear>(p, uv, 1);
  const FN r2 = planned_level<kFmt, kBilinear>(p, uv, 2);
  const FN f = FN::load(p.f);
  return select(FN::load(p.upper) != FN(0.0f), mix(r1, r2, f), mix(r0, r1, f));
}
// Lanes on different levels otherwise: the whole sampler per read.
FN planned_mixed(const RLodPlan& p, const V2<FN>& uv) {
  return texture_r_lod_lanes(*p.texture, p.sampler, uv, FN::load(p.lod));
}

template <TexFormat kFmt>
RLodPlan::Read planned_read(int levels, bool nearest) {
  if (nearest) return &planned<kFmt, 1, PlannedFilter::kNearest>;
  return levels == 1 ? &planned<kFmt, 1, PlannedFilter::kBilinear>
                     : &planned<kFmt, 2, PlannedFilter::kBilinear>;
}

}  // namespace

FN texture_r_lod_lanes(const Texture& t, const SamplerState& s, const V2<FN>& uv, const FN& lod) {
  if (!detail::vector_sampling_ok(t, s)) return texture_r_lod(t, s, uv, lod);  // scalar per lane
  switch (t.format()) {
    case TexFormat::kR8:
      return r_lod_fmt<TexFormat::kR8>(t, s, uv, lod);
    case TexFormat::kRG8:
      return r_lod_fmt<TexFormat::kRG8>(t, s, uv, lod);
    case TexFormat::kR32F:
      return r_lod_fmt<TexFormat::kR32F>(t, s, uv, lod);
    default:
      return r_lod_fmt<TexFormat::kRGBA8>(t, s, uv, lod);
  }
}

namespace {

// A plan for t, s and lod that reads through the whole sampler (planned_mixed) until the caller
// specialises it.
void begin_plan(const Texture& t, const SamplerState& s, const float* lod, RLodPlan& p) {
  p.texture = &t;
  p.sampler = s;
  std::memcpy(p.lod, lod, sizeof(p.lod));
  p.read = &planned_mixed;
  p.shared_levels = false;
  p.straddles = false;
  p.lut = nullptr;
}

// quad_cone_lanes' plan: level[0] and pow2 set, and shared_levels, where the lanes can be read
// together (an RGBA16F texture, nearest filtering, clamp or repeat wraps, one level for every
// lane).
void prepare_quad_cone(const Texture& t, const SamplerState& s, const float* lod, RLodPlan& p) {
  begin_plan(t, s, lod, p);
  if (t.format() != TexFormat::kRGBA16F || s.filter != Filter::kNearest || t.empty() ||
      !detail::lane_wraps_ok(s))
    return;
  const int lvl = detail::lod_levels(t.levels(), s.filter, lod[0]).lo;
  for (int i = 1; i < kLanes; ++i)
    if (detail::lod_levels(t.levels(), s.filter, lod[i]).lo != lvl) return;
  p.shared_levels = true;
  p.pow2 = detail::pow2_texture(t);
  const MipLevel& m = t.level(lvl);
  p.level[0] = {lvl, detail::level_size(t, lvl), {&m, detail::can_gather<FN>(m)}};
}

}  // namespace

FN quad_cone_lanes(const Texture& t, const SamplerState& s, const float* lod, const V2<FN>& uv,
                   const IN& shift_u, const IN& shift_v, RLodPlan& plan) {
  if (!plan.prepared_for(t, s, lod)) prepare_quad_cone(t, s, lod, plan);
  if (!plan.shared_levels) {  // lane by lane: any format, filter or wrap, lanes on several levels
    FN r;
    for (int i = 0; i < kLanes; ++i) {
      const glm::vec4 c = sample_lod(t, s, glm::vec2(lane(uv.x, i), lane(uv.y, i)), lod[i]);
      set_lane(r, i, quad_cone_pick(c, lane(shift_u, i), lane(shift_v, i)));
    }
    return r;
  }
  // texture.cpp's sample_nearest at the plan's level
  const RLodPlan::Level& l = plan.level[0];
  const detail::LevelSize<IN> n{IN(l.size.w), IN(l.size.h), IN(l.size.w_shift)};
  const IN idx = detail::nearest_index<FN>(s, uv, n, plan.pow2);
  IN lo, hi;  // each lane's texel: channels 0 and 1, channels 2 and 3
  bool gathered = false;
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX2
  if (l.src.gather) {  // an 8-byte texel is the 4-byte words 2 idx and 2 idx + 1
    detail::gather_pair4(*l.src.level, idx * IN(2), lo, hi);
    gathered = true;
  }
#endif
  if (!gathered) {
    const uint8_t* d = l.src.level->data.data();
    for (int i = 0; i < kLanes; ++i) {
      uint32_t w[2];
      std::memcpy(w, d + size_t(lane(idx, i)) * 8, 8);
      set_lane(lo, i, static_cast<int32_t>(w[0]));
      set_lane(hi, i, static_cast<int32_t>(w[1]));
    }
  }
  const FN a = detail::half_to_float_lanes<FN>((lo >> shift_u) & IN(0xffff));
  const FN b = detail::half_to_float_lanes<FN>((hi >> shift_v) & IN(0xffff));
  return select(a < b, b, a);
}

void prepare_r_lod(const Texture& t, const SamplerState& s, const float* lod, RLodPlan* plan) {
  RLodPlan& p = *plan;
  begin_plan(t, s, lod, p);
  if (!detail::vector_sampling_ok(t, s)) return;
  // Lane by lane in float (the same bits as lod_levels over FN), once per distinct LOD: kernels
  // hold one LOD per quad, so lanes usually repeat their neighbour's; one LOD for every lane (a
  // `lod=zero` search) is derived once.
  detail::LodLevels<float> l = detail::lod_levels(t.levels(), s.filter, lod[0]);
  const int lo = l.lo, hi = l.hi;
  bool two = l.f != 0.0f, one_level = true;
  int lane_lo[kLanes] = {}, lane_hi[kLanes] = {};
  if (!any(MV<kLanes>{bits_of(FN::load(lod)).v ^ IN(bits_of(lod[0])).v})) {
    FN(l.f).store(p.f);
  } else {
    for (int i = 0; i < kLanes; ++i) {
      if (i > 0 && std::memcmp(&lod[i], &lod[i - 1], sizeof(float)) != 0)
        l = detail::lod_levels(t.levels(), s.filter, lod[i]);
      p.f[i] = l.f;
      lane_lo[i] = l.lo;
      lane_hi[i] = l.hi;
      two = two || l.f != 0.0f;
      one_level = one_level && l.lo == lo && l.hi == hi;
    }
  }
  const bool nearest = s.filter == Filter::kNearest;
  // Lanes on levels (b, b + 1) and (b + 1, b + 2), bilinear within a level: three levels read
  // (planned_straddle); further apart, the whole sampler per read.
  const int top = t.levels() - 1;
  int lo_min = lo;
  bool straddle = false;
  if (!one_level && !nearest) {
    for (int i = 1; i < kLanes; ++i) lo_min = std::min(lo_min, lane_lo[i]);
    straddle = true;
    for (int i = 0; i < kLanes && straddle; ++i)
      straddle = (lane_lo[i] == lo_min || lane_lo[i] == lo_min + 1) &&
                 lane_hi[i] == std::min(lane_lo[i] + 1, top);
  }
  if (!one_level && !straddle) return;
  p.shared_levels = true;
  p.straddles = straddle;
  p.pow2 = detail::pow2_texture(t);
  const int n_levels = straddle ? 3 : two ? 2 : 1;  // the levels the read below uses
  int idx[3] = {lo, hi, hi};
  if (straddle) {
    idx[0] = lo_min;
    idx[1] = lo_min + 1;
    idx[2] = std::min(lo_min + 2, top);  // a top-level lane blends level[1] with itself at 0
    for (int i = 0; i < kLanes; ++i) p.upper[i] = lane_lo[i] == lo_min ? 0.0f : 1.0f;
  }
  for (int k = 0; k < n_levels; ++k) {
    const MipLevel& m = t.level(idx[k]);
    p.level[k] = {idx[k], detail::level_size(t, idx[k]), {&m, detail::can_gather<FN>(m)}};
    // R8 bilinear reads on a gather target: one footprint word a read (bilinear_at), built on
    // the first plan that reads the level
    if (t.format() == TexFormat::kR8 && !nearest && p.level[k].src.gather)
      p.level[k].src.footprints = t.r8_footprints(idx[k], s.wrap_u, s.wrap_v);
  }
  if (straddle) {
    switch (t.format()) {
      case TexFormat::kR8:
        p.read = &planned_straddle<TexFormat::kR8>;
        break;
      case TexFormat::kRG8:
        p.read = &planned_straddle<TexFormat::kRG8>;
        break;
      case TexFormat::kR32F:
        p.read = &planned_straddle<TexFormat::kR32F>;
        break;
      default:
        p.read = &planned_straddle<TexFormat::kRGBA8>;
        break;
    }
    return;
  }
  const int levels = two ? 2 : 1;
  bool words = t.format() == TexFormat::kR8 && !nearest;
  for (int k = 0; k < levels; ++k) words = words && p.level[k].src.footprints.words;
  if (words || nearest)  // the reads that take their levels in lanes
    for (int k = 0; k < levels; ++k)
      p.lanes[k] = detail::level_lanes<FN>(p.level[k].size, p.level[k].src.footprints);
  if (words) {
    p.lut = t.color_space() == ColorSpace::kSRGB ? srgb8_table() : nullptr;
    constexpr TexFormat kR8 = TexFormat::kR8;
    p.read = levels == 1 ? &planned<kR8, 1, PlannedFilter::kFootprints>
                         : &planned<kR8, 2, PlannedFilter::kFootprints>;
    return;
  }
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

RELIEF_LANE_FLATTEN V4<FN> texture_lod_lanes(const Texture& t, const SamplerState& s,
                                             const V2<FN>& uv, const FN& lod) {
  return detail::sample_lod_lanes<4>(t, s, uv, lod);
}

RELIEF_LANE_FLATTEN V4<FN> texture_grad_lanes(const Texture& t, const SamplerState& s,
                                              const V2<FN>& uv, const V2<FN>& dx,
                                              const V2<FN>& dy) {
  return texture_grad(t, s, uv, dx, dy);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();
