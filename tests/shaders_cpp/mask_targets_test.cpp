// The mask reductions any / all / none (shaders_cpp/lanes.h) on every SIMD level this CPU runs,
// for 8- and 16-lane masks: each target tests a whole mask in one instruction where it has one
// (vptest on AVX2, vptestmd on AVX-512), so each level is checked against a lane-by-lane
// reduction over every pattern of true lanes, a true lane written as -1 (what comparisons give)
// and as other non-zero words (1, INT_MIN, 0x100): a lane is true when its word is not zero.
// (The baseline level is the static target's code, which lanes_math_test.cpp checked alone before.)
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "tests/shaders_cpp/mask_targets_test.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <cstdint>
#include <string>

#include "shaders_cpp/lanes.h"

#include <hwy/highway.h>

#ifndef RELIEF_TESTS_MASK_TARGETS_ONCE
#define RELIEF_TESTS_MASK_TARGETS_ONCE
#include <gtest/gtest.h>

#include "tests/shaders_cpp/every_level.h"

namespace relief {
// What one level's check found (one type for every target's function).
struct MaskCheck {
  long checked = 0, mismatched = 0;
  std::string first_mismatch;
};
}  // namespace relief
#endif

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace {

template <int N>
void check_width(MaskCheck& c) {
  const int32_t trues[] = {-1, 1, INT32_MIN, 0x100};
  for (int32_t t : trues) {
    for (uint32_t bits = 0; bits < (1u << N); ++bits) {
      MV<N> m;
      bool any_ref = false, all_ref = true;
      for (int i = 0; i < N; ++i) {
        const bool on = (bits >> i) & 1u;
        m.v[i] = on ? t : 0;
        any_ref = any_ref || on;
        all_ref = all_ref && on;
      }
      ++c.checked;
      if (any(m) != any_ref || all(m) != all_ref || none(m) == any_ref) {
        if (c.mismatched++ == 0)
          c.first_mismatch = std::to_string(N) + " lanes, pattern " + std::to_string(bits) +
                             ", true word " + std::to_string(t);
      }
    }
  }
}

MaskCheck check_masks() {
  MaskCheck c;
  check_width<8>(c);
  check_width<16>(c);
  return c;
}

}  // namespace
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(check_masks);

TEST(MaskTargets, ReductionsMatchLaneByLaneOnEveryLevel) {
  testing::on_every_level([](SimdLevel level) {
    const MaskCheck c = HWY_DYNAMIC_DISPATCH(check_masks)();
    const std::string name = simd_level_name(level);
    EXPECT_EQ(c.mismatched, 0) << name << ": " << c.first_mismatch;
    EXPECT_EQ(c.checked, 4L * ((1L << 8) + (1L << 16))) << name;
  });
}

}  // namespace relief
#endif  // HWY_ONCE
