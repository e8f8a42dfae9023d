// A program with the calls that scripts/check-avx2-calls.sh exists to catch: an AVX2 clone
// calling a baseline function that takes and returns a 32-byte vector by value (GCC passes it
// in a ymm register on one side and in memory on the other), and one returning a vector from a
// non-template function, whose mangled name does not show the return type. Never run; the check
// reads its disassembly and must report both (tests/CMakeLists.txt,
// simd.Avx2CallCheckCatchesAVectorByValue).
#include <cstdio>
#include <cstring>

namespace relief {
typedef float f8v __attribute__((vector_size(32)));
struct F8 {
  f8v v;
};

__attribute__((noinline)) F8 twice(F8 a) {
  a.v = a.v + a.v;
  return a;
}

__attribute__((noinline)) F8 load(const float* in) {
  F8 a;
  std::memcpy(&a, in, sizeof a);
  return a;
}

__attribute__((target("avx2"), noinline)) void twice_avx2(const float* in, float* out) {
  F8 a = load(in);
  a.v = a.v * a.v;
  const F8 r = twice(a);
  std::memcpy(out, &r, sizeof r);
}
}  // namespace relief

int main() {
  float in[8] = {1, 2, 3, 4, 5, 6, 7, 8}, out[8];
  relief::twice_avx2(in, out);
  std::printf("%g\n", out[7]);
  return 0;
}
