// A PNG file holding a header (IHDR) for an image of any size, and no pixels: enough for a
// loader to read the size and, if it does not refuse it, to fail later on the missing data.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>

namespace relief::testing {

inline uint32_t png_crc(const std::string& bytes) {
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

inline std::string png_chunk(const std::string& type, const std::string& data) {
  auto be32 = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  return be32(static_cast<uint32_t>(data.size())) + type + data + be32(png_crc(type + data));
}

// Grey 8-bit, width x height, one IDAT with an empty zlib stream (no pixels).
inline void write_png_header_only(const std::string& path, uint32_t width, uint32_t height) {
  auto be32 = [](uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  const std::string ihdr = be32(width) + be32(height) + std::string{8, 0, 0, 0, 0};
  std::ofstream f(path, std::ios::binary);
  f << std::string("\x89PNG\r\n\x1a\n", 8) << png_chunk("IHDR", ihdr)
    << png_chunk("IDAT", std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8))
    << png_chunk("IEND", "");
}

}  // namespace relief::testing
