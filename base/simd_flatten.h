// RELIEF_LANE_FLATTEN, for the current Highway target (a per-target header: its toggle guard
// redefines the macro in every foreach_target pass). The per-target entry points (the packet lane
// loop, the tile traversal, the sampler entries) inline what they call: a matter of speed only,
// since every callee is the same target's code and nothing depends on it. Not on the baseline
// target (the fallback) nor where RELIEF_NO_FLATTEN is defined (CI's sanitizer builds): flattened
// copies of every kernel variant are what compile time is spent on.
#if defined(RELIEF_BASE_SIMD_FLATTEN_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_BASE_SIMD_FLATTEN_H_
#undef RELIEF_BASE_SIMD_FLATTEN_H_
#else
#define RELIEF_BASE_SIMD_FLATTEN_H_
#endif

#include <hwy/highway.h>

#undef RELIEF_LANE_FLATTEN
#if defined(RELIEF_NO_FLATTEN) || HWY_TARGET == HWY_STATIC_TARGET
#define RELIEF_LANE_FLATTEN
#else
#define RELIEF_LANE_FLATTEN __attribute__((flatten))
#endif

#endif  // RELIEF_BASE_SIMD_FLATTEN_H_
