#include "base/simd.h"

#include <cstdlib>
#include <cstring>

#include <hwy/highway.h>
#include <hwy/targets.h>

namespace relief {
namespace {

// The Highway target of each level (SimdLevel's order).
int64_t target_of(SimdLevel level) {
#if HWY_ARCH_X86
  switch (level) {
    case SimdLevel::kAvx512:
      return HWY_AVX3;
    case SimdLevel::kAvx2:
      return HWY_AVX2;
    default:
      break;
  }
#endif
  (void)level;
  return HWY_STATIC_TARGET;
}

bool runs(SimdLevel level) {
  if (level == SimdLevel::kBaseline) return true;
  const int64_t t = target_of(level);
  return t != HWY_STATIC_TARGET && (hwy::SupportedTargets() & HWY_TARGETS & t) != 0;
}

SimdLevel clamp_level(SimdLevel level) {
  while (level != SimdLevel::kBaseline && !runs(level))
    level = static_cast<SimdLevel>(static_cast<int>(level) - 1);
  return level;
}

SimdLevel g_level = SimdLevel::kBaseline;

void apply(SimdLevel level) {
  g_level = level;
  // HWY_DYNAMIC_DISPATCH picks the best target in this mask that a module compiled; the baseline
  // (static) target is always in it.
  hwy::GetChosenTarget().Update(level == SimdLevel::kBaseline ? 0 : target_of(level));
}

SimdLevel from_env() {
  const SimdLevel best = simd_supported();
  const char* e = std::getenv("RELIEF_SIMD");
  if (e == nullptr || *e == '\0') return best;
  if (std::strcmp(e, "baseline") == 0 || std::strcmp(e, "sse2") == 0) return SimdLevel::kBaseline;
  if (std::strcmp(e, "avx2") == 0) return clamp_level(SimdLevel::kAvx2);
  return best;  // "avx512", "avx3" or anything else: the best available
}

// Applied before main(): the first dynamic dispatch must already see the chosen level.
const bool g_initialised = [] {
  apply(from_env());
  return true;
}();

}  // namespace

SimdLevel simd_supported() {
  return clamp_level(SimdLevel::kAvx512);
}

std::vector<SimdLevel> simd_levels_supported() {
  std::vector<SimdLevel> out;
  for (SimdLevel l : {SimdLevel::kBaseline, SimdLevel::kAvx2, SimdLevel::kAvx512})
    if (runs(l)) out.push_back(l);
  return out;
}

SimdLevel simd_level() {
  (void)g_initialised;
  return g_level;
}

SimdLevel set_simd_level(SimdLevel level) {
  apply(clamp_level(level));
  return g_level;
}

const char* simd_level_name(SimdLevel level) {
  switch (level) {
    case SimdLevel::kAvx512:
      return "avx512";
    case SimdLevel::kAvx2:
      return "avx2";
    default:
      return "baseline";
  }
}

}  // namespace relief
