// Runs a check at every SIMD level this CPU runs (base/simd.h), for the tests of lane code
// compiled per target.
#ifndef RELIEF_TESTS_SHADERS_CPP_EVERY_LEVEL_H_
#define RELIEF_TESTS_SHADERS_CPP_EVERY_LEVEL_H_

#include "base/simd.h"

namespace relief::testing {

// Calls check(level) at every SIMD level this CPU runs, that level set, then restores the level.
template <class Check>
void on_every_level(const Check& check) {
  const SimdLevel saved = simd_level();
  for (SimdLevel level : simd_levels_supported()) {
    set_simd_level(level);
    check(level);
  }
  set_simd_level(saved);
}

}  // namespace relief::testing

#endif  // RELIEF_TESTS_SHADERS_CPP_EVERY_LEVEL_H_
