// base/hash.h: the content hash behind the GL backend's geometry cache keys. Equal bytes give
// equal digests; a changed bit, a moved boundary between calls or an extra call gives another;
// every length (blocks of 32 bytes, words of 8, single bytes) reaches the digest.
#include "base/hash.h"

#include <cstdint>
#include <set>
#include <vector>

#include <gtest/gtest.h>

namespace relief {
namespace {

uint64_t digest(const std::vector<uint8_t>& bytes) {
  Hash64 h;
  h.bytes(bytes.data(), bytes.size());
  return h.digest();
}

TEST(Hash64, EqualBytesEqualDigestsAndEveryFlippedBitChangesIt) {
  std::vector<uint8_t> data(100);
  for (size_t i = 0; i < data.size(); ++i) data[i] = static_cast<uint8_t>(i * 37 + 11);
  const uint64_t base = digest(data);
  EXPECT_EQ(digest(data), base);
  std::set<uint64_t> seen{base};
  // 100 bytes: three 32-byte blocks, then 8-byte words, then single bytes; each part counts.
  for (size_t i = 0; i < data.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> flipped = data;
      flipped[i] ^= static_cast<uint8_t>(1u << bit);
      EXPECT_TRUE(seen.insert(digest(flipped)).second) << "byte " << i << " bit " << bit;
    }
}

TEST(Hash64, LengthsAndBoundariesBetweenCallsCount) {
  const std::vector<uint8_t> zeros(64, 0);
  std::set<uint64_t> seen;
  for (size_t n = 0; n <= zeros.size(); ++n) {
    Hash64 h;
    h.bytes(zeros.data(), n);
    EXPECT_TRUE(seen.insert(h.digest()).second) << n << " zero bytes";
  }
  // ("ab", "c") and ("a", "bc"); and an empty call is not nothing.
  const uint8_t abc[] = {'a', 'b', 'c'};
  Hash64 x, y, z, w;
  x.bytes(abc, 2);
  x.bytes(abc + 2, 1);
  y.bytes(abc, 1);
  y.bytes(abc + 1, 2);
  z.bytes(abc, 3);
  w.bytes(abc, 3);
  w.bytes(abc, 0);
  EXPECT_NE(x.digest(), y.digest());
  EXPECT_NE(x.digest(), z.digest());
  EXPECT_NE(z.digest(), w.digest());
  // elements() hashes a vector's bytes: equal vectors, equal digests.
  Hash64 e1, e2;
  e1.elements(std::vector<float>{1.0f, 2.0f});
  e2.elements(std::vector<float>{1.0f, 2.0f});
  EXPECT_EQ(e1.digest(), e2.digest());
}

}  // namespace
}  // namespace relief
