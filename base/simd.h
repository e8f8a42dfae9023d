// SIMD targets chosen at run time, so one binary runs everywhere (DESIGN.md, "The fragment-shader
// plugin ABI").
//
// The build targets baseline x86-64 (SSE2). Every piece of code that works on lane vectors (the
// technique kernels and their packet loops, the lane-parallel samplers, the rasterizer's tile
// traversal) is compiled once per SIMD target by Google Highway's foreach_target.h, each copy in
// its own namespace relief::HWY_NAMESPACE (N_EMU128, N_AVX2, N_AVX3) under that target's compiler
// options. Code of one target can only name code of its own target, so no call can cross targets
// with a vector argument, whatever the compiler chooses to inline. The entry points carry no
// vector in their signatures (a packet shader, a tile) and are chosen per draw through
// HWY_DYNAMIC_DISPATCH, which reads the level set here.
//
// Levels: kBaseline is Highway's EMU128 target (SSE2 code; eight lanes as two 4-wide halves),
// kAvx2 eight lanes in one register, kAvx512 Highway's AVX3 target (AVX-512 F/VL/DQ/BW) with
// sixteen lanes. Every level does the same IEEE operations in the same order per lane and the
// build sets -ffp-contract=off (no FMA contraction), so all give bit-identical images (tested in
// tests/frames/simd_test.cpp for every level this CPU runs).
//
// The environment variable RELIEF_SIMD=baseline (or sse2), avx2 or avx512 (or avx3) asks for a
// level at start-up; one the CPU lacks falls back to the best it has below it.
#pragma once

#include <cstdint>
#include <vector>

namespace relief {

enum class SimdLevel : uint8_t { kBaseline, kAvx2, kAvx512 };

// The best level this CPU supports (among those the build compiles).
SimdLevel simd_supported();
// Every level this CPU runs, baseline first.
std::vector<SimdLevel> simd_levels_supported();
// The level in use: RELIEF_SIMD at start-up, else simd_supported(); set_simd_level overrides it.
SimdLevel simd_level();
// Sets the level (clamped to what the CPU supports) and returns the level now in use. Call it
// between frames, not while a frame renders: draws choose their target when they are planned.
SimdLevel set_simd_level(SimdLevel level);
// "baseline", "avx2", "avx512".
const char* simd_level_name(SimdLevel level);

}  // namespace relief
