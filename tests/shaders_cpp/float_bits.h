// The bit pattern of a float, for tests that compare results bit for bit.
#pragma once

#include <cstdint>
#include <cstring>

namespace relief::testing {

inline uint32_t float_bits(float x) {
  uint32_t b;
  std::memcpy(&b, &x, 4);
  return b;
}

}  // namespace relief::testing
