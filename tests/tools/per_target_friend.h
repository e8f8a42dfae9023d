// A per-target header with the mistake scripts/check-per-target.sh exists to catch (the simd test
// in tests/CMakeLists.txt expects the check to fail on it). Not compiled.
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <int N>
struct Lanes {
  float v[N];
  friend Lanes operator+(Lanes a, Lanes b) { return a; }
};

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();
