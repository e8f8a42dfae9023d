// The prepared depth reads (shaders_cpp/sampling_simd.h RLodPlan) on every SIMD level this CPU
// runs, at that level's native lanes: the gathers of AVX2 and AVX-512, and the R8 footprint words
// (rasterizer/texture.h Texture::r8_footprints) they read, give the scalar sample_r_lod's bits per
// lane. The other sampling tests run at the static target, which has no gathers.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/shaders_cpp/sampling_targets_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include "rasterizer/texture.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/search.h"
#include "tests/shaders_cpp/random_texture.h"

#include <hwy/highway.h>

#ifndef RELIEF_TESTS_SAMPLING_TARGETS_ONCE
#define RELIEF_TESTS_SAMPLING_TARGETS_ONCE
namespace relief {
// What one level's check found (one type for every target's function).
struct PlannedCheck {
  long checked = 0, mismatched = 0;
  long footprint_plans = 0;  // plans whose first level reads footprint words
  long straddle_plans = 0;   // plans of lanes on two neighbouring pairs of levels
  long one_lod_blends = 0;   // plans of one LOD for every lane that blend two levels
  long lut_plans = 0;        // plans that read through the sRGB table (footprint reads)
  std::string first_mismatch;
};
}  // namespace relief
#endif

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

// Packets of reads against the scalar sampler, lane by lane: for each texture size (random texels
// of `format` in colour space `space`, full mip chains), filter and pair of wraps, 16 packets with
// one LOD per quad (every quad on level 0 in packets 0 and 4, every quad at LOD 0.5 in packet 8
// and 1.5 in packet 12) and three reads each, the third at uvs far off the texture and on its
// edges. read(t, s, plan, n, lod, uv) reads packet n; want(t, s, n, lane, lod, u, v)
// is that lane's scalar value; counted(plan) says whether the packet's plan adds to
// footprint_plans.
template <class Read, class Want, class Counted>
PlannedCheck check_packets(uint32_t seed, TexFormat format, ColorSpace space,
                           std::initializer_list<Filter> filters,
                           std::initializer_list<Wrap> wraps_u, const Read& read, const Want& want,
                           const Counted& counted) {
  PlannedCheck c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uvd(-3.0f, 3.0f), lodd(-1.5f, 7.0f);
  constexpr float kFar[8] = {-3e9f, 3e9f, -1e5f, 1e5f, 0.0f, 1.0f, -0.0f, 2.0f};
  for (auto [w, h] : {std::pair{64, 32}, std::pair{37, 20}, std::pair{256, 256}, std::pair{1, 1}}) {
    const Texture t =
        testing::random_texture(format, w, h, space, seed + static_cast<uint32_t>(w * 7 + h));
    for (Filter filter : filters)
      for (Wrap wu : wraps_u)
        for (Wrap wv : {Wrap::kRepeat, Wrap::kClamp}) {
          const SamplerState s = testing::sampler_state(filter, wu, wv);
          RLodPlan plan;
          for (int n = 0; n < 16; ++n) {
            float lod[kLanes];
            for (int i = 0; i < kLanes; i += 4) {
              const float l = n % 4 != 0 ? lodd(rng)
                              : n < 8    ? 0.0f
                                         : 0.5f + static_cast<float>(n / 4 - 2);
              for (int k = 0; k < 4; ++k) lod[i + k] = l;
            }
            for (int r = 0; r < 3; ++r) {
              alignas(64) float u[kLanes], v[kLanes];
              for (int i = 0; i < kLanes; ++i) {
                u[i] = r == 2 ? kFar[(i + n) % 8] : uvd(rng);
                v[i] = r == 2 ? kFar[(i + 3 * n + 1) % 8] : uvd(rng);
              }
              alignas(64) float got[kLanes];
              read(t, s, plan, n, lod, V2<FN>(FN::load(u), FN::load(v))).store(got);
              for (int i = 0; i < kLanes; ++i) {
                const float expected = want(t, s, n, i, lod[i], u[i], v[i]);
                ++c.checked;
                if (std::memcmp(&got[i], &expected, sizeof(float)) != 0 && c.mismatched++ == 0)
                  c.first_mismatch = std::to_string(w) + "x" + std::to_string(h) + " uv " +
                                     std::to_string(u[i]) + "," + std::to_string(v[i]) + " lod " +
                                     std::to_string(lod[i]) + ": " + std::to_string(got[i]) +
                                     " vs " + std::to_string(expected);
              }
            }
            if (counted(plan)) ++c.footprint_plans;
            if (plan.straddles) ++c.straddle_plans;
            if (plan.lut) ++c.lut_plans;
            if (n >= 8 && n % 4 == 0 && plan.shared_levels && plan.f[0] != 0.0f) ++c.one_lod_blends;
          }
        }
  }
  return c;
}

PlannedCheck check_planned_r8(uint32_t seed, bool srgb) {
  return check_packets(
      seed, TexFormat::kR8, srgb ? ColorSpace::kSRGB : ColorSpace::kLinear,
      {Filter::kBilinear, Filter::kTrilinear}, {Wrap::kRepeat, Wrap::kClamp},
      [](const Texture& t, const SamplerState& s, RLodPlan& plan, int, const float* lod,
         const V2<FN>& uv) { return texture_r_lod_planned(t, s, lod, uv, plan); },
      [](const Texture& t, const SamplerState& s, int, int, float lod, float u, float v) {
        return sample_r_lod(t, s, glm::vec2(u, v), lod);
      },
      [](const RLodPlan& plan) {
        return plan.shared_levels && plan.level[0].src.footprints.words;
      });
}

// The channel pair of lane i in packet n: 0 or 16 each (the +-u and +-v halves of a texel).
int quad_shift(int n, int i, int axis) {
  return 16 * (((i * (axis + 3)) ^ (n >> axis) ^ (i >> 2)) & 1);
}

// quad_cone_lanes against the larger of the two channels of the scalar sample_lod, per lane, on
// random RGBA16F texels (any finite half: subnormals, -0, both signs; the texture replaces
// infinities and NaNs), with every wrap (mirrored ones read lane by lane) and LODs that put the
// lanes on one level or on several.
PlannedCheck check_quad_cone(uint32_t seed) {
  return check_packets(
      seed, TexFormat::kRGBA16F, ColorSpace::kLinear, {Filter::kNearest},
      {Wrap::kRepeat, Wrap::kClamp, Wrap::kMirror},
      [](const Texture& t, const SamplerState& s, RLodPlan& plan, int n, const float* lod,
         const V2<FN>& uv) {
        IN shift_u, shift_v;
        for (int i = 0; i < kLanes; ++i) {
          set_lane(shift_u, i, quad_shift(n, i, 0));
          set_lane(shift_v, i, quad_shift(n, i, 1));
        }
        return quad_cone_lanes(t, s, lod, uv, shift_u, shift_v, plan);
      },
      [](const Texture& t, const SamplerState& s, int n, int i, float lod, float u, float v) {
        const glm::vec4 texel = sample_lod(t, s, glm::vec2(u, v), lod);
        const float a = texel[quad_shift(n, i, 0) / 16], b = texel[2 + quad_shift(n, i, 1) / 16];
        return a < b ? b : a;
      },
      [](const RLodPlan& plan) { return plan.shared_levels; });  // here: read over the lanes
}

// Copies of a prepared plan start unprepared (RLodPlan's copy constructor and assignment), and a
// copied TextureDepth retargeted to another texture (relief_dual's back layer) reads that
// texture: for 16 packets of random LODs per quad on two random R8 textures, trilinear. A plan
// that says it serves what it does not, or a read that differs from the scalar sampler's bits,
// counts as a mismatch.
PlannedCheck check_plan_copies(uint32_t seed) {
  PlannedCheck c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uvd(-3.0f, 3.0f), lodd(-1.5f, 7.0f);
  const Texture front = testing::random_texture(TexFormat::kR8, 64, 32, ColorSpace::kLinear, seed);
  const Texture back =
      testing::random_texture(TexFormat::kR8, 64, 32, ColorSpace::kLinear, seed + 1);
  const SamplerState s = testing::sampler_state(Filter::kTrilinear, Wrap::kRepeat, Wrap::kRepeat);
  const auto mismatch = [&](bool bad, const std::string& what) {
    ++c.checked;
    if (bad && c.mismatched++ == 0) c.first_mismatch = what;
  };
  for (int n = 0; n < 16; ++n) {
    TextureDepth a;
    a.texture = &front;
    a.sampler = &s;
    for (int i = 0; i < kLanes; i += 4) std::fill(a.lod + i, a.lod + i + 4, lodd(rng));
    alignas(64) float u[kLanes], v[kLanes], got[kLanes];
    for (int i = 0; i < kLanes; ++i) {
      u[i] = uvd(rng);
      v[i] = uvd(rng);
    }
    const V2<FN> uv(FN::load(u), FN::load(v));
    a.lanes(uv);  // prepares a's plan
    mismatch(!a.plan.prepared_for(front, s, a.lod), "the read left its plan unprepared");
    RLodPlan assigned;
    assigned = a.plan;
    mismatch(RLodPlan(a.plan).prepared_for(front, s, a.lod), "a copied plan is prepared");
    mismatch(assigned.prepared_for(front, s, a.lod), "an assigned plan is prepared");
    TextureDepth b = a;
    b.texture = &back;
    for (const TextureDepth* d : {&b, &a}) {
      d->lanes(uv).store(got);
      for (int i = 0; i < kLanes; ++i) {
        const float want = sample_r_lod(*d->texture, s, glm::vec2(u[i], v[i]), d->lod[i]);
        mismatch(std::memcmp(&got[i], &want, sizeof(float)) != 0,
                 std::string(d == &b ? "back" : "front") + " lane " + std::to_string(i));
      }
    }
  }
  return c;
}

}  // namespace
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <gtest/gtest.h>

#include "base/simd.h"
#include "tests/shaders_cpp/every_level.h"

namespace relief {
namespace {

HWY_EXPORT(check_planned_r8);
HWY_EXPORT(check_quad_cone);
HWY_EXPORT(check_plan_copies);

TEST(SamplingTargets, PlannedR8ReadsGiveSampleRLodBitsOnEveryLevel) {
  testing::on_every_level([](SimdLevel level) {
    for (bool srgb : {false, true}) {
      const PlannedCheck c = HWY_DYNAMIC_DISPATCH(check_planned_r8)(11, srgb);
      const std::string where = simd_level_name(level) + std::string(srgb ? " sRGB" : " linear");
      EXPECT_EQ(c.mismatched, 0) << where << ": " << c.first_mismatch;
      EXPECT_EQ(c.checked % 4, 0);
      EXPECT_GT(c.checked, 4 * 2 * 4 * 16 * 3 * 4) << where;
      // quads on neighbouring pairs of levels are read through three levels
      EXPECT_GE(c.straddle_plans, 5) << where;
      // one fractional LOD for every lane blends two shared levels: both such packets of the
      // trilinear filter on the three textures with more than one level, at all four wraps
      EXPECT_EQ(c.one_lod_blends, 3 * 4 * 2) << where;
      // the gather levels read footprint words wherever the lanes share a level: at least in
      // every packet of one LOD for every quad (a quarter) of the three textures large enough
      // for gathers; an sRGB texture's footprint reads decode through the table
      if (level != SimdLevel::kBaseline) {
        EXPECT_GE(c.footprint_plans, 3 * 2 * 4 * 4) << where;
        if (srgb)
          EXPECT_GE(c.lut_plans, 3 * 2 * 4 * 4) << where;
        else
          EXPECT_EQ(c.lut_plans, 0) << where;
      } else {
        EXPECT_EQ(c.footprint_plans, 0);
        EXPECT_EQ(c.lut_plans, 0);
      }
    }
  });
}

TEST(SamplingTargets, QuadConeReadsGiveSampleLodBitsOnEveryLevel) {
  testing::on_every_level([](SimdLevel level) {
    const PlannedCheck c = HWY_DYNAMIC_DISPATCH(check_quad_cone)(17);
    EXPECT_EQ(c.mismatched, 0) << simd_level_name(level) << ": " << c.first_mismatch;
    constexpr long kReads = 4 * 3 * 2 * 16 * 3;  // sizes, wraps, packets, reads
    EXPECT_TRUE(c.checked == kReads * 8 || c.checked == kReads * 16) << c.checked;
    // read over the lanes: at least the packets of one LOD for every quad (a quarter) with
    // unmirrored wraps
    EXPECT_GE(c.footprint_plans, 4 * 2 * 2 * 4) << simd_level_name(level);
  });
}

TEST(SamplingTargets, PlanCopiesStartUnpreparedAndRetargetedCopiesReadTheirTexture) {
  testing::on_every_level([](SimdLevel level) {
    const PlannedCheck c = HWY_DYNAMIC_DISPATCH(check_plan_copies)(23);
    EXPECT_EQ(c.mismatched, 0) << simd_level_name(level) << ": " << c.first_mismatch;
    // three plan checks and both depth sources' lanes a packet, at 8 or 16 lanes
    EXPECT_TRUE(c.checked == 16 * (3 + 2 * 8) || c.checked == 16 * (3 + 2 * 16)) << c.checked;
  });
}

}  // namespace
}  // namespace relief
#endif  // HWY_ONCE
