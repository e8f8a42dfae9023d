// The prepared depth reads (shaders_cpp/sampling_simd.h RLodPlan) on every SIMD level this CPU
// runs, at that level's native lanes: the gathers of AVX2 and AVX-512, and the R8 footprint words
// (rasterizer/texture.h Texture::r8_footprints) they read, give the scalar sample_r_lod's bits per
// lane. The other sampling tests run at the static target, which has no gathers.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/shaders_cpp/sampling_targets_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "rasterizer/texture.h"
#include "shaders_cpp/sampling_simd.h"
#include "tests/shaders_cpp/random_texture.h"

#include <hwy/highway.h>

#ifndef RELIEF_TESTS_SAMPLING_TARGETS_ONCE
#define RELIEF_TESTS_SAMPLING_TARGETS_ONCE
namespace relief {
// What one level's check found (one type for every target's function).
struct PlannedCheck {
  long checked = 0, mismatched = 0;
  long footprint_plans = 0;  // plans whose first level reads footprint words
  std::string first_mismatch;
};
}  // namespace relief
#endif

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

PlannedCheck check_planned_r8(uint32_t seed) {
  PlannedCheck c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uvd(-3.0f, 3.0f), lodd(-1.5f, 7.0f);
  constexpr float kFar[8] = {-3e9f, 3e9f, -1e5f, 1e5f, 0.0f, 1.0f, -0.0f, 2.0f};
  for (auto [w, h] : {std::pair{64, 32}, std::pair{37, 20}, std::pair{256, 256}, std::pair{1, 1}}) {
    const Texture t = testing::random_texture(TexFormat::kR8, w, h, ColorSpace::kLinear,
                                              seed + static_cast<uint32_t>(w * 7 + h));
    for (Filter filter : {Filter::kBilinear, Filter::kTrilinear})
      for (Wrap wu : {Wrap::kRepeat, Wrap::kClamp})
        for (Wrap wv : {Wrap::kRepeat, Wrap::kClamp}) {
          const SamplerState s = testing::sampler_state(filter, wu, wv);
          RLodPlan plan;
          for (int n = 0; n < 16; ++n) {
            float lod[kLanes];
            // one LOD per quad; level 0 for every quad in a quarter of the packets
            for (int i = 0; i < kLanes; i += 4) {
              const float l = n % 4 == 0 ? 0.0f : lodd(rng);
              for (int k = 0; k < 4; ++k) lod[i + k] = l;
            }
            for (int r = 0; r < 3; ++r) {
              alignas(64) float u[kLanes], v[kLanes];
              for (int i = 0; i < kLanes; ++i) {
                u[i] = r == 2 ? kFar[(i + n) % 8] : uvd(rng);
                v[i] = r == 2 ? kFar[(i + 3 * n + 1) % 8] : uvd(rng);
              }
              const V2<FN> uv(FN::load(u), FN::load(v));
              alignas(64) float got[kLanes];
              texture_r_lod_planned(t, s, lod, uv, plan).store(got);
              for (int i = 0; i < kLanes; ++i) {
                const float want = sample_r_lod(t, s, glm::vec2(u[i], v[i]), lod[i]);
                ++c.checked;
                if (std::memcmp(&got[i], &want, sizeof(float)) != 0) {
                  if (c.mismatched++ == 0)
                    c.first_mismatch = std::to_string(w) + "x" + std::to_string(h) + " uv " +
                                       std::to_string(u[i]) + "," + std::to_string(v[i]) + " lod " +
                                       std::to_string(lod[i]) + ": " + std::to_string(got[i]) +
                                       " vs " + std::to_string(want);
                }
              }
            }
            if (plan.shared_levels && plan.level[0].src.footprints.words) ++c.footprint_plans;
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

namespace relief {
namespace {

HWY_EXPORT(check_planned_r8);

TEST(SamplingTargets, PlannedR8ReadsGiveSampleRLodBitsOnEveryLevel) {
  const SimdLevel saved = simd_level();
  for (SimdLevel level : simd_levels_supported()) {
    set_simd_level(level);
    const PlannedCheck c = HWY_DYNAMIC_DISPATCH(check_planned_r8)(11);
    EXPECT_EQ(c.mismatched, 0) << simd_level_name(level) << ": " << c.first_mismatch;
    EXPECT_EQ(c.checked % 4, 0);
    EXPECT_GT(c.checked, 4 * 2 * 4 * 16 * 3 * 4) << simd_level_name(level);
    // the gather levels read footprint words wherever the lanes share a level: at least in every
    // packet at level 0 (a quarter) of the three textures large enough for gathers
    if (level != SimdLevel::kBaseline)
      EXPECT_GE(c.footprint_plans, 3 * 2 * 4 * 4) << simd_level_name(level);
    else
      EXPECT_EQ(c.footprint_plans, 0);
  }
  set_simd_level(saved);
}

}  // namespace
}  // namespace relief
#endif  // HWY_ONCE
