// A fast 64-bit content hash for cache keys (gl/gl_geometry.cpp keys uploaded meshes by their
// bytes). Four independent multiply-rotate lanes over 32-byte blocks, so a frame can hash a
// 2 M-triangle mesh (about 100 MB) in a few ms; not cryptographic: a key, not a defence.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace relief {

class Hash64 {
 public:
  // Folds n bytes at p into the hash (with their length, so ("ab", "c") and ("a", "bc") differ).
  void bytes(const void* p, size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    uint64_t lane[4] = {h_ + kP1 + kP2, h_ + kP2, h_, h_ - kP1};
    size_t i = 0;
    for (; i + 32 <= n; i += 32)
      for (int k = 0; k < 4; ++k) lane[k] = round(lane[k], load(b + i + 8 * k));
    uint64_t h = n >= 32
                     ? rotl(lane[0], 1) + rotl(lane[1], 7) + rotl(lane[2], 12) + rotl(lane[3], 18)
                     : h_ + kP5;
    h += static_cast<uint64_t>(n);
    for (; i + 8 <= n; i += 8) h = rotl(h ^ round(0, load(b + i)), 27) * kP1 + kP4;
    for (; i < n; ++i) h = rotl(h ^ (b[i] * kP5), 11) * kP1;
    h_ = avalanche(h);
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  // A vector's size and elements (trivially copyable T).
  template <class T>
  void elements(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  uint64_t digest() const { return h_; }

 private:
  static constexpr uint64_t kP1 = 0x9E3779B185EBCA87ull, kP2 = 0xC2B2AE3D27D4EB4Full,
                            kP4 = 0x85EBCA77C2B2AE63ull, kP5 = 0x27D4EB2F165667C5ull;
  static uint64_t rotl(uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }
  static uint64_t load(const unsigned char* p) {
    uint64_t w;
    std::memcpy(&w, p, sizeof w);
    return w;
  }
  static uint64_t round(uint64_t acc, uint64_t w) { return rotl(acc + w * kP2, 31) * kP1; }
  static uint64_t avalanche(uint64_t h) {
    h ^= h >> 33;
    h *= kP2;
    h ^= h >> 29;
    h *= kP3;
    return h ^ (h >> 32);
  }
  static constexpr uint64_t kP3 = 0x165667B19E3779F9ull;
  uint64_t h_ = 0;
};

}  // namespace relief
