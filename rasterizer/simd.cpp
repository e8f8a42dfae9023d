#include "rasterizer/simd.h"

#include <cstdlib>
#include <cstring>

namespace relief {
namespace {

SimdLevel from_env() {
  const SimdLevel best = simd_supported();
  const char* e = std::getenv("RELIEF_SIMD");
  if (e == nullptr || *e == '\0') return best;
  if (std::strcmp(e, "baseline") == 0 || std::strcmp(e, "sse2") == 0) return SimdLevel::kBaseline;
  return best;  // "avx2" or anything else: the best available
}

}  // namespace

SimdLevel simd_supported() {
#if RELIEF_HAVE_AVX2_PATH
  __builtin_cpu_init();  // may run from a static initializer
  return __builtin_cpu_supports("avx2") ? SimdLevel::kAvx2 : SimdLevel::kBaseline;
#else
  return SimdLevel::kBaseline;
#endif
}

namespace detail {
bool g_simd_avx2 = from_env() == SimdLevel::kAvx2;
}

SimdLevel simd_level() {
  return detail::g_simd_avx2 ? SimdLevel::kAvx2 : SimdLevel::kBaseline;
}

SimdLevel set_simd_level(SimdLevel level) {
  if (level == SimdLevel::kAvx2 && simd_supported() != SimdLevel::kAvx2)
    level = SimdLevel::kBaseline;
  detail::g_simd_avx2 = level == SimdLevel::kAvx2;
  return level;
}

const char* simd_level_name(SimdLevel level) {
  return level == SimdLevel::kAvx2 ? "avx2" : "baseline";
}

}  // namespace relief
