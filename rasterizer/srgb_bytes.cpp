#include "rasterizer/srgb_bytes.h"

#include <bit>

#include "rasterizer/texture.h"

namespace relief {
namespace {

constexpr uint32_t kOneBits = 0x3f800000u;  // 1.0f
constexpr int kRunShift = 16;               // a run: 2^16 float bit patterns
constexpr uint32_t kRuns = (kOneBits >> kRunShift) + 1;

struct SrgbTables {
  float threshold[256] = {};     // [k]: the smallest float whose byte is k (k >= 1)
  uint8_t run_byte[kRuns] = {};  // the byte of the float with bits (i << kRunShift)
  SrgbTables() {
    for (int k = 1; k < 256; ++k) {
      uint32_t lo = 0, hi = kOneBits;  // byte(lo) < k <= byte(hi)
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (encode_srgb8(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
      }
      threshold[k] = std::bit_cast<float>(hi);
    }
    for (uint32_t i = 0; i < kRuns; ++i)
      run_byte[i] = encode_srgb8(std::bit_cast<float>(i << kRunShift));
  }
};

const SrgbTables& tables() {
  static const SrgbTables t;
  return t;
}

}  // namespace

uint8_t srgb_byte(float c) {
  if (!(c > 0.0f)) return 0;  // zero, negative, NaN
  if (c >= 1.0f) return 255;
  const SrgbTables& t = tables();
  int b = t.run_byte[std::bit_cast<uint32_t>(c) >> kRunShift];
  while (b < 255 && c >= t.threshold[b + 1]) ++b;
  return static_cast<uint8_t>(b);
}

}  // namespace relief
