// libFuzzer target, structure-aware: PNG and OpenEXR files whose headers are well formed (correct
// chunk CRCs, attribute sizes, offset tables) but whose fields are drawn from the input: sizes up
// to 2^32 - 1 and zero, bit depths, colour types, interlacing, channel lists (types, sampling,
// counts), compression, data and display windows, line order, tiling flags, chunk offsets, and
// pixel data that is short, long or garbage. The loaders (scene/image_io.h load_texture with each
// option, and read_image) must check sizes from the header before allocating and give a texture
// or a one-line error: never a crash, a hang, an allocation past libFuzzer's -rss_limit_mb, or a
// non-finite texel in a depth map.
#include <fuzzer/FuzzedDataProvider.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "scene/image_io.h"

namespace {

using Bytes = std::vector<uint8_t>;

void put32be(Bytes& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<uint8_t>(v >> s));
}
void put32le(Bytes& b, uint32_t v) {
  for (int s = 0; s < 32; s += 8) b.push_back(static_cast<uint8_t>(v >> s));
}
void put64le(Bytes& b, uint64_t v) {
  for (int s = 0; s < 64; s += 8) b.push_back(static_cast<uint8_t>(v >> s));
}
void put_str(Bytes& b, const char* s) {
  b.insert(b.end(), s, s + std::strlen(s) + 1);
}
void put_bytes(Bytes& b, const std::string& s) {
  b.insert(b.end(), s.begin(), s.end());
}

uint32_t crc32(const uint8_t* p, size_t n) {
  uint32_t c = 0xffffffffu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return ~c;
}

// A zlib stream of stored (uncompressed) deflate blocks holding `raw`, with its Adler-32.
Bytes zlib_stored(const std::string& raw) {
  Bytes z = {0x78, 0x01};
  size_t i = 0;
  do {
    const size_t n = std::min<size_t>(raw.size() - i, 65535);
    z.push_back(i + n == raw.size() ? 1 : 0);
    z.push_back(static_cast<uint8_t>(n));
    z.push_back(static_cast<uint8_t>(n >> 8));
    z.push_back(static_cast<uint8_t>(~n));
    z.push_back(static_cast<uint8_t>(~n >> 8));
    z.insert(z.end(), raw.begin() + i, raw.begin() + i + n);
    i += n;
  } while (i < raw.size());
  uint32_t a = 1, b = 0;
  for (char ch : raw) {
    a = (a + static_cast<uint8_t>(ch)) % 65521;
    b = (b + a) % 65521;
  }
  put32be(z, (b << 16) | a);
  return z;
}

// True about one time in sixteen: the field gets an odd value instead of a valid one.
// (An exhausted provider gives 0, so its fields stay valid.)
bool rare(FuzzedDataProvider& p) {
  return p.ConsumeIntegralInRange<int>(0, 15) == 15;
}

uint32_t side(FuzzedDataProvider& p) {
  static const uint32_t kSides[] = {0,   1,     2,     3,     7,           64,
                                    255, 16384, 16385, 65535, 0x7fffffffu, 0xffffffffu};
  return !rare(p) ? p.ConsumeIntegralInRange<uint32_t>(1, 40)
                  : kSides[p.ConsumeIntegralInRange<size_t>(0, 11)];
}

void png_chunk(Bytes& out, const char* type, const Bytes& body) {
  put32be(out, static_cast<uint32_t>(body.size()));
  const size_t start = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), body.begin(), body.end());
  put32be(out, crc32(out.data() + start, out.size() - start));
}

Bytes make_png(FuzzedDataProvider& p) {
  Bytes out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // Valid (colour type, bit depth) pairs of the PNG specification, then odd ones.
  static const uint8_t kPairs[][2] = {{0, 1},  {0, 2}, {0, 4}, {0, 8}, {0, 16}, {2, 8},  {2, 16},
                                      {3, 1},  {3, 2}, {3, 4}, {3, 8}, {4, 8},  {4, 16}, {6, 8},
                                      {6, 16}, {2, 4}, {1, 8}, {7, 8}, {0, 3}};
  Bytes ihdr;
  put32be(ihdr, side(p));
  put32be(ihdr, side(p));
  const auto& pair = kPairs[p.ConsumeIntegralInRange<size_t>(0, rare(p) ? 18 : 14)];
  const uint8_t type = pair[0];
  ihdr.push_back(pair[1]);
  ihdr.push_back(type);
  ihdr.push_back(rare(p) ? p.ConsumeIntegral<uint8_t>() : 0);  // compression
  ihdr.push_back(rare(p) ? p.ConsumeIntegral<uint8_t>() : 0);  // filter method
  ihdr.push_back(rare(p) ? p.ConsumeIntegral<uint8_t>() : p.ConsumeIntegralInRange<uint8_t>(0, 1));
  png_chunk(out, "IHDR", ihdr);
  if (type == 3 || p.ConsumeIntegralInRange<int>(0, 7) == 0) {
    Bytes plte;
    for (int i = 3 * p.ConsumeIntegralInRange<int>(0, 256); i > 0; --i)
      plte.push_back(p.ConsumeIntegral<uint8_t>());
    png_chunk(out, "PLTE", plte);
  }
  if (p.ConsumeIntegralInRange<int>(0, 5) == 0) {
    Bytes trns;
    for (int i = p.ConsumeIntegralInRange<int>(0, 8); i > 0; --i)
      trns.push_back(p.ConsumeIntegral<uint8_t>());
    png_chunk(out, "tRNS", trns);
  }
  if (p.ConsumeIntegralInRange<int>(0, 5) == 0) {  // an iCCP that libpng warns about
    Bytes iccp = {'x', 0, 0};
    put_bytes(iccp, p.ConsumeRandomLengthString(32));
    png_chunk(out, "iCCP", iccp);
  }
  // Rows of filter type 0..4 and pixel bytes (a row's length as the header gives it when it is
  // small); the data's length is the input's, right or wrong.
  static const int kChannels[] = {1, 0, 3, 1, 2, 0, 4};
  const uint64_t w =
      (static_cast<uint64_t>(ihdr[0]) << 24) | (ihdr[1] << 16) | (ihdr[2] << 8) | ihdr[3];
  const uint64_t row = type < 7 && w <= 4096 ? 1 + (w * kChannels[type] * pair[1] + 7) / 8 : 0;
  for (int k = p.ConsumeIntegralInRange<int>(1, 3); k > 0; --k) {
    std::string raw = p.ConsumeRandomLengthString(8192);
    if (!rare(p) && row > 0)
      for (size_t i = 0; i < raw.size(); i += row)
        raw[i] = static_cast<char>(static_cast<uint8_t>(raw[i]) % 5);
    png_chunk(out, "IDAT", zlib_stored(raw));
  }
  if (p.ConsumeBool()) png_chunk(out, "IEND", {});
  return out;
}

void exr_attr(Bytes& b, const char* name, const char* type, const Bytes& value) {
  put_str(b, name);
  put_str(b, type);
  put32le(b, static_cast<uint32_t>(value.size()));
  b.insert(b.end(), value.begin(), value.end());
}

int32_t coord(FuzzedDataProvider& p) {
  static const int32_t kCoords[] = {0,     1,     7,       63,        -1,       -64,
                                    16383, 16384, 1 << 20, INT32_MAX, INT32_MIN};
  return !rare(p) ? p.ConsumeIntegralInRange<int32_t>(0, 40)
                  : kCoords[p.ConsumeIntegralInRange<size_t>(0, 10)];
}

Bytes make_exr(FuzzedDataProvider& p) {
  Bytes out;
  put32le(out, 20000630u);  // magic 76 2f 31 01
  uint32_t version = 2;
  if (p.ConsumeIntegralInRange<int>(0, 3) == 0) version |= 0x200;  // tiled
  if (rare(p)) version |= 0x800;                                   // deep
  if (rare(p)) version |= 0x1000;                                  // multi-part
  put32le(out, version);
  Bytes ch;
  static const char* const kNames[] = {"R", "G", "B", "A", "Y", "Z", "depth.Y"};
  for (int n = p.ConsumeIntegralInRange<int>(0, 5); n > 0; --n) {
    put_str(ch, kNames[p.ConsumeIntegralInRange<size_t>(0, 6)]);
    put32le(ch, !rare(p) ? p.ConsumeIntegralInRange<uint32_t>(0, 2)
                         : p.ConsumeIntegral<uint32_t>());  // UINT, HALF, FLOAT
    ch.push_back(0);
    ch.insert(ch.end(), 3, 0);
    put32le(ch, !rare(p) ? 1u : p.ConsumeIntegralInRange<uint32_t>(0, 3));
    put32le(ch, !rare(p) ? 1u : p.ConsumeIntegralInRange<uint32_t>(0, 3));
  }
  ch.push_back(0);
  exr_attr(out, "channels", "chlist", ch);
  const uint8_t compression =
      rare(p) ? p.ConsumeIntegral<uint8_t>() : p.ConsumeIntegralInRange<uint8_t>(0, 9);
  exr_attr(out, "compression", "compression", {compression});
  Bytes box;
  const int32_t x0 = coord(p), y0 = coord(p);
  // Window corners as a writer of odd files may give them: sums wrap as in the file's int32.
  const auto plus = [](int32_t a, uint32_t b) {
    return static_cast<int32_t>(static_cast<uint32_t>(a) + b);
  };
  const int32_t x1 = !rare(p) ? plus(x0, p.ConsumeIntegralInRange<uint32_t>(0, 40)) : coord(p);
  const int32_t y1 = !rare(p) ? plus(y0, p.ConsumeIntegralInRange<uint32_t>(0, 40)) : coord(p);
  for (int32_t v : {x0, y0, x1, y1}) put32le(box, static_cast<uint32_t>(v));
  exr_attr(out, "dataWindow", "box2i", box);
  if (rare(p)) {
    Bytes disp;
    for (int i = 0; i < 4; ++i) put32le(disp, static_cast<uint32_t>(coord(p)));
    exr_attr(out, "displayWindow", "box2i", disp);
  } else {
    exr_attr(out, "displayWindow", "box2i", box);
  }
  exr_attr(out, "lineOrder", "lineOrder", {p.ConsumeIntegralInRange<uint8_t>(0, rare(p) ? 3 : 1)});
  Bytes f;
  const float ratio = !rare(p) ? 1.0f : p.ConsumeFloatingPoint<float>();
  uint32_t bits;
  std::memcpy(&bits, &ratio, 4);
  put32le(f, bits);
  exr_attr(out, "pixelAspectRatio", "float", f);
  exr_attr(out, "screenWindowCenter", "v2f", Bytes(8, 0));
  exr_attr(out, "screenWindowWidth", "float", {0, 0, 0x80, 0x3f});
  if (version & 0x200) {
    Bytes tiles;
    put32le(tiles, p.ConsumeIntegralInRange<uint32_t>(0, 70000));
    put32le(tiles, p.ConsumeIntegralInRange<uint32_t>(0, 70000));
    tiles.push_back(p.ConsumeIntegralInRange<uint8_t>(0, 3));
    exr_attr(out, "tiles", "tiledesc", tiles);
  }
  out.push_back(0);  // end of header
  // Offset table (a few entries, right or wrong) and scanline chunks.
  // One chunk per scanline block when the window is small (as a writer makes them), else a few.
  const int64_t rows = static_cast<int64_t>(y1) - y0 + 1;
  static const int kLinesPerBlock[] = {1, 1, 16, 32, 32, 16, 256, 256, 32, 256};
  const int per = kLinesPerBlock[compression < 10 ? compression : 0];
  const int chunks = rows >= 1 && rows <= 64 && !rare(p) ? static_cast<int>((rows + per - 1) / per)
                                                         : p.ConsumeIntegralInRange<int>(0, 8);
  const size_t table_end = out.size() + 8 * static_cast<size_t>(chunks);
  std::vector<Bytes> blocks;
  size_t at = table_end;
  for (int i = 0; i < chunks; ++i) {
    Bytes c;
    put32le(c, static_cast<uint32_t>(plus(y0, static_cast<uint32_t>(i * (rare(p) ? 1 : per)))));
    const std::string data = p.ConsumeRandomLengthString(2048);
    put32le(c, !rare(p) ? static_cast<uint32_t>(data.size()) : p.ConsumeIntegral<uint32_t>());
    put_bytes(c, data);
    put64le(out, !rare(p) ? at : p.ConsumeIntegral<uint64_t>());
    at += c.size();
    blocks.push_back(std::move(c));
  }
  for (const Bytes& c : blocks) out.insert(out.end(), c.begin(), c.end());
  return out;
}

std::string temp_path(const char* ext) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("relief_fuzz_hdr_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / (std::string("input") + ext)).string();
}

void one_line(const relief::Status& s) {
  if (s.message().empty() || s.message().find('\n') != std::string::npos) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider p(data, size);
  const bool exr = p.ConsumeBool();
  const uint8_t sel = p.ConsumeIntegral<uint8_t>();
  const Bytes file = exr ? make_exr(p) : make_png(p);
  const std::string path = temp_path(exr ? ".exr" : ".png");
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
  }
  relief::TextureLoadOptions opts;
  opts.first_channel_only = sel & 1;
  opts.unit_range = opts.first_channel_only && (sel & 2);
  opts.height_to_depth = opts.first_channel_only && (sel & 4);
  opts.color_space =
      (sel & 8) && !opts.height_to_depth ? relief::ColorSpace::kSRGB : relief::ColorSpace::kLinear;
  relief::Result<relief::Texture> t = relief::load_texture(path, opts);
  if (!t.ok()) {
    one_line(t.status());
  } else {
    if (opts.unit_range)
      for (int y = 0; y < t->height(0); ++y)
        for (int x = 0; x < t->width(0); ++x) {
          const float v = t->fetch_r(0, x, y);
          if (!(v >= 0.0f && v <= 1.0f)) __builtin_trap();  // a depth map holds [0, 1]
        }
    if (sel & 16) t->generate_mips(relief::MipReduce::kAverage);
  }
  relief::Result<relief::Image> im = relief::read_image(path);
  if (!im.ok()) one_line(im.status());
  std::remove(path.c_str());
  return 0;
}
