// SIMD code paths chosen at run time, so one binary runs everywhere (issue 9).
//
// The build targets baseline x86-64 (SSE2). Hot entry points (the rasterizer's tile traversal,
// every plugin's 8-lane packet loop in plugins/shading.h, the sampler entries of
// shaders_cpp/sampling_simd.cpp) are compiled twice from one body: once for the baseline and
// once under __attribute__((target("avx2"))) with everything below them inlined
// (RELIEF_AVX2_ENTRY). A baseline function called out of line from an AVX2 clone must not take
// or return a 32-byte vector by value (the two targets pass it differently): vectors cross
// through pointers. The test simd.Avx2ClonesPassNoVectorByValue (scripts/check-avx2-calls.sh)
// checks every call out of the clones in the built binary. simd_level() picks one per call.
// Both paths do the same IEEE operations in the same order and the build sets -ffp-contract=off
// (no FMA contraction), so they produce bit-identical images (tested in
// tests/rasterizer/simd_test.cpp).
//
// The environment variable RELIEF_SIMD=baseline (or sse2) forces the baseline path;
// RELIEF_SIMD=avx2 asks for AVX2 and falls back to baseline where the CPU lacks it.
#pragma once

#include <cstdint>

namespace relief {

// GCC vector types shared by the rasterizer and the lane types of shaders_cpp/lanes.h.
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
typedef float v4f __attribute__((vector_size(16)));
typedef int32_t v4i __attribute__((vector_size(16)));

enum class SimdLevel : uint8_t { kBaseline, kAvx2 };

// The best level this CPU supports.
SimdLevel simd_supported();
// The level in use: RELIEF_SIMD at start-up, else simd_supported(); set_simd_level overrides it.
SimdLevel simd_level();
// Sets the level (clamped to what the CPU supports) and returns the level now in use. Call it
// between frames, not while a frame renders.
SimdLevel set_simd_level(SimdLevel level);
const char* simd_level_name(SimdLevel level);

namespace detail {
extern bool g_simd_avx2;  // simd_level() == kAvx2, read once per packet/tile
}
inline bool simd_avx2() {
  return detail::g_simd_avx2;
}

}  // namespace relief

// An AVX2 clone of an entry point: everything it calls inline is compiled for AVX2 with it.
#if defined(__x86_64__) || defined(__i386__)
#define RELIEF_AVX2_ENTRY __attribute__((target("avx2"), flatten, noinline))
#define RELIEF_HAVE_AVX2_PATH 1
#else
#define RELIEF_AVX2_ENTRY __attribute__((flatten, noinline))
#define RELIEF_HAVE_AVX2_PATH 0
#endif
#define RELIEF_BASE_ENTRY __attribute__((flatten, noinline))
