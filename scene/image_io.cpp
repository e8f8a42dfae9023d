// Image and texture files through OpenImageIO: loading textures in their stored format, reading
// and atomically writing linear float images and planes.
#include "scene/image_io.h"

#include <sys/mman.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rasterizer/output_file.h"

#include "rasterizer/safe_file.h"
#include "rasterizer/srgb_bytes.h"

namespace relief {
namespace {

namespace fs = std::filesystem;

// The first line of an OIIO error, trimmed (errors must stay on one line).
std::string one_line(std::string s) {
  const size_t nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r' || s.back() == '.')) s.pop_back();
  return s.empty() ? std::string("unknown error") : s;
}

Status fail(const std::string& path, const std::string& what) {
  return Status::error(path + ": " + what);
}

double srgb_decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

float finite_or_zero(float v) {
  return std::isfinite(v) ? v : 0.0f;
}

double clamp01(double v) {
  return v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
}

uint8_t to_u8(double v) {
  return static_cast<uint8_t>(std::lround(clamp01(v) * 255.0));
}
uint16_t to_u16(double v) {
  return static_cast<uint16_t>(std::lround(clamp01(v) * 65535.0));
}

enum class Depth { k8, k16, kHalf, kFloat };

// A read-only view of bytes for the readers. OIIO 2.4's IOMemReader reads past the end of its
// buffer when a read starts inside it and ends beyond (fuzz_image_header: an OpenEXR scanline
// chunk whose size runs past the file, heap-buffer-overflow in IOMemReader::pread): here every
// read is clamped to the bytes there are, and one starting at or past the end reads nothing. It
// stays an IOMemReader (proxytype "memreader"): the JPEG reader takes only that and reads its
// buffer() whole, with its size.
class BytesReader final : public OIIO::Filesystem::IOMemReader {
 public:
  explicit BytesReader(const std::string& bytes) : IOMemReader(bytes.data(), bytes.size()) {}
  size_t read(void* buf, size_t size) override {
    const size_t n = pread(buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t pread(void* buf, size_t size, int64_t offset) override {
    if (offset < 0 || static_cast<uint64_t>(offset) >= m_buf.size()) return 0;
    const size_t n = std::min(size, m_buf.size() - static_cast<size_t>(offset));
    std::memcpy(buf, m_buf.data() + offset, n);
    return n;
  }
};

// An opened input whose size has been checked. The reader only ever sees `bytes` (read from a
// checked regular file, or handed over in memory) through `proxy`: it never opens a path.
struct Input {
  std::string bytes;
  std::unique_ptr<BytesReader> proxy;
  std::unique_ptr<OIIO::ImageInput> in;
  int width = 0;
  int height = 0;
  int channels = 0;
  Depth depth = Depth::kFloat;
  ~Input() {
    in.reset();  // before the proxy and the bytes it reads
    proxy.reset();
  }
};

bool starts_with(const std::string& b, const char* magic, size_t n) {
  return b.size() >= n && std::memcmp(b.data(), magic, n) == 0;
}

// The OpenImageIO reader for `bytes`, from their magic number (the file name's extension only
// for TGA, which has none); nullptr when it is none of the formats read from memory.
const char* format_of(const std::string& b, const std::string& name) {
  if (starts_with(b, "\x89PNG\r\n\x1a\n", 8)) return "png";
  if (starts_with(b, "\xff\xd8\xff", 3)) return "jpeg";
  if (starts_with(b, "\x76\x2f\x31\x01", 4)) return "openexr";
  if (starts_with(b, "II*\0", 4) || starts_with(b, "MM\0*", 4) || starts_with(b, "II+\0", 4) ||
      starts_with(b, "MM\0+", 4))
    return "tiff";
  if (starts_with(b, "#?RADIANCE", 10) || starts_with(b, "#?RGBE", 6)) return "hdr";
  if (starts_with(b, "BM", 2)) return "bmp";
  if (starts_with(b, "GIF8", 4)) return "gif";
  if (starts_with(b, "8BPS", 4)) return "psd";
  if (starts_with(b, "DDS ", 4)) return "dds";
  if (b.size() >= 12 && starts_with(b, "RIFF", 4) && std::memcmp(b.data() + 8, "WEBP", 4) == 0)
    return "webp";
  if (b.size() >= 2 && b[0] == 'P' && std::strchr("123456fF", b[1]) != nullptr && b[1] != '\0')
    return "pnm";
  const size_t dot = name.rfind('.');
  if (dot != std::string::npos && name.size() - dot == 4) {
    std::string ext = name.substr(dot);
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext == ".tga") return "targa";
  }
  return nullptr;
}

// First lines that libpng (through OpenImageIO) would print on stderr during a decode are
// caught here, so that nothing but relief's own one line reaches the terminal; the first is
// kept for the error message. Loads are serialised around the capture.
class StderrCapture {
 public:
  StderrCapture() {
    std::fflush(stderr);
    const int fd = ::memfd_create("relief_stderr", MFD_CLOEXEC);
    file_ = fd >= 0 ? ::fdopen(fd, "w+") : nullptr;
    if (fd >= 0 && !file_) ::close(fd);
    saved_ = file_ ? ::dup(2) : -1;
    if (saved_ >= 0) ::dup2(::fileno(file_), 2);
  }
  ~StderrCapture() { release(); }
  // Restores fd 2; the first line written meanwhile (empty if none).
  std::string release() {
    std::string first;
    if (saved_ >= 0) {
      std::fflush(stderr);
      ::dup2(saved_, 2);
      ::close(saved_);
      saved_ = -1;
      std::rewind(file_);
      char line[256];
      if (std::fgets(line, sizeof line, file_)) first = line;
    }
    if (file_) {
      std::fclose(file_);
      file_ = nullptr;
    }
    return first;
  }

 private:
  std::FILE* file_ = nullptr;
  int saved_ = -1;
};

std::mutex& decode_mutex() {
  static std::mutex m;
  return m;
}

// OpenEXR allocates a tiled file's tile buffers when it opens the file, before any spec can be
// checked: the tile size (and channel count) is read from the header's "tiles" and "channels"
// attributes here first. Only what the header says is looked at; a malformed header is left to
// the reader's own errors.
Status check_exr_tiles(const std::string& path, const std::string& bytes) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), "\x76\x2f\x31\x01", 4) != 0) return {};
  size_t at = 8;
  const auto cstring = [&](std::string& out) {
    const size_t end = bytes.find('\0', at);
    if (end == std::string::npos) return false;
    out.assign(bytes, at, end - at);
    at = end + 1;
    return true;
  };
  uint32_t tile_w = 0, tile_h = 0;
  long long channels = 0;
  std::string name, type;
  while (at < bytes.size() && bytes[at] != '\0') {
    uint32_t size = 0;
    if (!cstring(name) || !cstring(type) || bytes.size() - at < 4) return {};
    std::memcpy(&size, bytes.data() + at, 4);
    at += 4;
    if (size > bytes.size() - at) return {};
    if (name == "tiles" && type == "tiledesc" && size >= 8) {
      std::memcpy(&tile_w, bytes.data() + at, 4);
      std::memcpy(&tile_h, bytes.data() + at + 4, 4);
    } else if (name == "channels" && type == "chlist") {
      for (size_t c = at; c < at + size && bytes[c] != '\0'; ++channels) {
        const size_t end = bytes.find('\0', c);
        if (end == std::string::npos) break;
        c = end + 1 + 16;  // name, then pixel type, pLinear + reserved, x and y sampling
      }
    }
    at += size;
  }
  if (tile_w > 0 && static_cast<double>(tile_w) * tile_h * std::max(channels, 1LL) >
                        static_cast<double>(kMaxTileValues))
    return fail(path, "tiles of " + std::to_string(tile_w) + "x" + std::to_string(tile_h) +
                          " texels x " + std::to_string(channels) +
                          " channels, more than the limit of " + std::to_string(kMaxTileValues) +
                          " values a tile");
  return {};
}

// Opens `in.bytes` (already filled) for `path` (the name used in messages).
// `max_texels`: kMaxTextureTexels for textures, kMaxImageTexels for read_image.
Status open_bytes(const std::string& path, Input& out, long long max_texels) {
  if (out.bytes.empty()) return fail(path, "cannot read image: the file is empty");
  const char* format = format_of(out.bytes, path);
  if (!format)
    return fail(path,
                "cannot read image: not a PNG, JPEG, EXR, TIFF, HDR, BMP, GIF, PSD, DDS, "
                "WebP, PNM or TGA file");
  RELIEF_RETURN_IF_ERROR(check_exr_tiles(path, out.bytes));
  out.in = OIIO::ImageInput::create(format);
  if (!out.in || !out.in->supports("ioproxy"))
    return fail(path, std::string("cannot read image: no ") + format + " reader");
  out.proxy = std::make_unique<BytesReader>(out.bytes);
  out.in->set_ioproxy(out.proxy.get());
  // Keep alpha unassociated: texture alpha is data (depth, heights), never premultiplied.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  OIIO::ImageSpec spec;
  bool opened = false;
  std::string noise;
  {
    std::lock_guard<std::mutex> lock(decode_mutex());
    StderrCapture capture;
    opened = out.in->open(path, spec, config);
    noise = capture.release();
  }
  if (!opened) {
    std::string why = out.in->geterror();
    if (why.empty()) why = noise;
    out.in.reset();
    return fail(path, "cannot read image: " + printable(one_line(why), 160));
  }
  if (spec.width <= 0 || spec.height <= 0)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", expected at least 1x1");
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", larger than the limit of " + std::to_string(kMaxImageSide) +
                          " on a side");
  if (static_cast<long long>(spec.width) * spec.height > max_texels)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", more than the limit of " + std::to_string(max_texels) + " texels" +
                          (max_texels == kMaxTextureTexels ? " for a texture" : ""));
  if (spec.depth > 1) return fail(path, "volume images are not supported");
  if (spec.nchannels < 1) return fail(path, "image has no channels");
  if (spec.nchannels > 64)
    return fail(path, "image has " + std::to_string(spec.nchannels) + " channels, more than 64");
  if (spec.tile_width > 0 && static_cast<double>(spec.tile_width) * std::max(spec.tile_height, 1) *
                                     std::max(spec.tile_depth, 1) * spec.nchannels >
                                 static_cast<double>(kMaxTileValues))
    return fail(path, "tiles of " + std::to_string(spec.tile_width) + "x" +
                          std::to_string(spec.tile_height) + " texels x " +
                          std::to_string(spec.nchannels) + " channels, more than the limit of " +
                          std::to_string(kMaxTileValues) + " values a tile");
  out.width = spec.width;
  out.height = spec.height;
  out.channels = spec.nchannels;
  switch (spec.format.basetype) {
    case OIIO::TypeDesc::UINT8:
    case OIIO::TypeDesc::INT8:
      out.depth = Depth::k8;
      break;
    case OIIO::TypeDesc::UINT16:
    case OIIO::TypeDesc::INT16:
      out.depth = Depth::k16;
      break;
    case OIIO::TypeDesc::HALF:
      out.depth = Depth::kHalf;
      break;
    default:
      out.depth = Depth::kFloat;
      break;
  }
  return Status();
}

// Reads a regular file (never a FIFO or device, at most kMaxInputFileBytes) and opens it.
Status open_input(const std::string& path, Input& out, long long max_texels) {
  Result<std::string> bytes = read_regular_file(path);
  if (!bytes.ok()) return bytes.status();
  out.bytes = std::move(*bytes);
  return open_bytes(printable(path), out, max_texels);
}

// Reads channels [0, nch) of subimage 0, level 0 as `type`.
Status read_pixels(const std::string& path, Input& in, int nch, OIIO::TypeDesc type, void* data) {
  bool ok = false;
  std::string noise;
  {
    std::lock_guard<std::mutex> lock(decode_mutex());
    StderrCapture capture;
    ok = in.in->read_image(0, 0, 0, nch, type, data);
    noise = capture.release();
  }
  if (!ok) {
    std::string why = in.in->geterror();
    if (why.empty()) why = noise;
    return fail(path, "cannot decode image: " + printable(one_line(why), 160));
  }
  return Status();
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Encodes `pixels` (type, channels, channel names) as `oiio_format` in memory: OpenImageIO never
// touches the disk, so every byte of the file is written (and checked) by output_file.h.
Result<std::vector<unsigned char>> encode_pixels(const std::string& path, const char* oiio_format,
                                                 const OIIO::ImageSpec& spec, const void* pixels) {
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(oiio_format);
  if (!out)
    return fail(path, std::string("no ") + oiio_format + " writer: " + one_line(OIIO::geterror()));
  if (!out->supports("ioproxy") || !out->set_ioproxy(&proxy))
    return fail(path, std::string("the ") + oiio_format + " writer cannot encode to memory");
  bool ok = out->open(path, spec) && out->write_image(spec.format, pixels);
  ok = out->close() && ok;
  if (!ok) return fail(path, "cannot encode image: " + one_line(out->geterror()));
  if (bytes.empty()) return fail(path, "cannot encode image: the encoder wrote nothing");
  return bytes;
}

std::string_view as_text(const std::vector<unsigned char>& bytes) {
  return std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

Status unknown_extension(const std::string& path, const std::string& ext) {
  if (ext.empty())
    return Status::usage(path + ": no image extension, expected .png, .exr, .tif or .tiff");
  return Status::usage(path + ": unknown image extension '" + printable(ext, 16) +
                       "', expected .png, .exr, .tif or .tiff");
}

bool image_shape_ok(int w, int h, size_t n) {
  return w >= 1 && h >= 1 && n == static_cast<size_t>(w) * static_cast<size_t>(h);
}

}  // namespace

namespace {

// The texture in an opened input (see load_texture); `path` is the name for messages.
Result<Texture> texture_from(const std::string& path, Input& in, const TextureLoadOptions& opts) {
  const int src_ch = opts.first_channel_only ? 1 : std::min(in.channels, 4);
  const size_t n = static_cast<size_t>(in.width) * in.height;
  const bool srgb = opts.color_space == ColorSpace::kSRGB;

  if (in.depth == Depth::k8) {
    std::vector<uint8_t> src(n * src_ch);
    RELIEF_RETURN_IF_ERROR(read_pixels(path, in, src_ch, OIIO::TypeDesc::UINT8, src.data()));
    const TexFormat f =
        src_ch == 1 ? TexFormat::kR8 : (src_ch == 2 ? TexFormat::kRG8 : TexFormat::kRGBA8);
    const int dst_ch = format_channels(f);
    std::vector<uint8_t> texels(n * dst_ch, 255);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < src_ch; ++c) texels[i * dst_ch + c] = src[i * src_ch + c];
    if (opts.height_to_depth)
      for (size_t i = 0; i < n; ++i)
        texels[i * dst_ch] = static_cast<uint8_t>(255 - texels[i * dst_ch]);
    return Texture(f, in.width, in.height, texels.data(), opts.color_space);
  }

  if (in.depth == Depth::k16 && src_ch == 1) {
    std::vector<uint16_t> src(n);
    RELIEF_RETURN_IF_ERROR(read_pixels(path, in, 1, OIIO::TypeDesc::UINT16, src.data()));
    for (uint16_t& v : src) {
      if (srgb) v = to_u16(srgb_decode(v / 65535.0));
      if (opts.height_to_depth) v = static_cast<uint16_t>(65535 - v);
    }
    return Texture(TexFormat::kR16, in.width, in.height, src.data());
  }

  // Half, float and multi-channel 16-bit: through float (OIIO normalises integers to [0, 1]).
  std::vector<float> src(n * src_ch);
  RELIEF_RETURN_IF_ERROR(read_pixels(path, in, src_ch, OIIO::TypeDesc::FLOAT, src.data()));
  TexFormat f = TexFormat::kRGBA16F;
  if (src_ch == 1) f = in.depth == Depth::kFloat ? TexFormat::kR32F : TexFormat::kR16F;
  const int dst_ch = format_channels(f);
  std::vector<float> values(n * dst_ch, 0.0f);
  size_t clamped = 0;
  for (size_t i = 0; i < n; ++i) {
    float* d = &values[i * dst_ch];
    if (dst_ch == 4) d[3] = 1.0f;
    for (int c = 0; c < src_ch; ++c) {
      float v = finite_or_zero(src[i * src_ch + c]);
      if (srgb && c < 3) v = static_cast<float>(srgb_decode(v));
      d[c] = v;
    }
    if (opts.height_to_depth) d[0] = 1.0f - d[0];
    if (opts.unit_range) {
      const float raw = src[i * src_ch];
      const float v = static_cast<float>(clamp01(d[0]));
      clamped += v != d[0] || !std::isfinite(raw);
      d[0] = v;
    }
  }
  if (clamped > 0)
    std::fprintf(stderr,
                 "relief: warning: %s: %zu of %zu depth texels lie outside [0, 1] or are not "
                 "finite; clamped\n",
                 path.c_str(), clamped, n);
  return Texture::from_floats(f, in.width, in.height, values.data());
}

}  // namespace

Result<Texture> load_texture(const std::string& path, const TextureLoadOptions& opts) {
  if (opts.height_to_depth && opts.color_space != ColorSpace::kLinear)
    return Status::usage(printable(path) +
                         ": height_to_depth needs a linear colour space, not sRGB");
  Input in;
  RELIEF_RETURN_IF_ERROR(open_input(path, in, kMaxTextureTexels));
  return texture_from(printable(path), in, opts);
}

Result<Texture> load_texture_from_memory(std::string bytes, const std::string& name,
                                         const TextureLoadOptions& opts) {
  if (opts.height_to_depth && opts.color_space != ColorSpace::kLinear)
    return Status::usage(name + ": height_to_depth needs a linear colour space, not sRGB");
  if (bytes.size() > kMaxInputFileBytes)
    return Status::error(name + ": image is " + std::to_string(bytes.size()) +
                         " bytes, more than the limit of " + std::to_string(kMaxInputFileBytes));
  Input in;
  in.bytes = std::move(bytes);
  RELIEF_RETURN_IF_ERROR(open_bytes(name, in, kMaxTextureTexels));
  return texture_from(name, in, opts);
}

Result<Image> read_image(const std::string& path) {
  Input in;
  RELIEF_RETURN_IF_ERROR(open_input(path, in, kMaxImageTexels));
  const int ch = std::min(in.channels, 4);
  const size_t n = static_cast<size_t>(in.width) * in.height;
  std::vector<float> src(n * ch);
  RELIEF_RETURN_IF_ERROR(read_pixels(printable(path), in, ch, OIIO::TypeDesc::FLOAT, src.data()));
  const bool srgb = in.depth == Depth::k8;
  const int colour = ch >= 3 ? 3 : 1;  // colour channels; 1 or 2 channels are grey (+ alpha)
  Image img(in.width, in.height);
  for (size_t i = 0; i < n; ++i) {
    const float* s = &src[i * ch];
    float rgb[3];
    for (int c = 0; c < colour; ++c) {
      const float v = finite_or_zero(s[c]);
      rgb[c] = srgb ? static_cast<float>(srgb_decode(v)) : v;
    }
    if (colour == 1) rgb[1] = rgb[2] = rgb[0];
    const float a = (ch == 2 || ch == 4) ? finite_or_zero(s[ch - 1]) : 1.0f;
    img.pixels[i] = glm::vec4(rgb[0], rgb[1], rgb[2], a);
  }
  return img;
}

Result<Image> load_environment(const std::string& path, long long* replaced) {
  Input in;
  RELIEF_RETURN_IF_ERROR(open_input(path, in, kMaxEnvironmentTexels));
  if (in.width != 2 * in.height)
    return fail(printable(path), "environment is " + std::to_string(in.width) + "x" +
                                     std::to_string(in.height) +
                                     ", expected an equirectangular map twice as wide as high");
  const int ch = std::min(in.channels, 3);
  const size_t n = static_cast<size_t>(in.width) * in.height;
  std::vector<float> src(n * ch);
  RELIEF_RETURN_IF_ERROR(read_pixels(printable(path), in, ch, OIIO::TypeDesc::FLOAT, src.data()));
  const bool srgb = in.depth == Depth::k8;
  long long bad = 0;
  Image img(in.width, in.height);
  for (size_t i = 0; i < n; ++i) {
    float rgb[3];
    bool replaced_one = false;
    for (int c = 0; c < 3; ++c) {
      float v = src[i * ch + (ch == 3 ? c : 0)];  // 1 or 2 channels: grey
      if (!(std::isfinite(v) && v >= 0.0f)) {
        v = 0.0f;
        replaced_one = true;
      }
      rgb[c] = srgb ? static_cast<float>(srgb_decode(v)) : v;
    }
    bad += replaced_one ? 1 : 0;
    img.pixels[i] = glm::vec4(rgb[0], rgb[1], rgb[2], 1.0f);
  }
  if (replaced) *replaced = bad;
  return img;
}

bool image_is_8bit(const std::string& path) {
  return lower_extension(path) == ".png";
}

Result<std::vector<unsigned char>> encode_image(const std::string& path, const Image& image) {
  bool opaque = true;
  for (const glm::vec4& p : image.pixels) opaque = opaque && p.a == 1.0f;
  return encode_image(path, image, lower_extension(path) == ".exr" ? 4 : (opaque ? 3 : 4), false);
}

Result<std::vector<unsigned char>> encode_image(const std::string& path, const Image& image,
                                                int channels, bool premultiplied) {
  const std::string name = printable(path);  // in messages
  if (!image_shape_ok(image.width, image.height, image.pixels.size()))
    return fail(name, "cannot write an empty or malformed image (" + std::to_string(image.width) +
                          "x" + std::to_string(image.height) + ")");
  const std::string ext = lower_extension(path);
  const size_t n = image.pixels.size();
  const int ch = channels == 3 ? 3 : 4;
  if (ext == ".png" || ext == ".tif" || ext == ".tiff") {
    const bool png = image_is_8bit(path);
    OIIO::ImageSpec spec(image.width, image.height, ch,
                         png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
    spec.attribute("oiio:UnassociatedAlpha", premultiplied && !png ? 0 : 1);
    if (png) {
      spec.attribute("oiio:ColorSpace", "sRGB");
      std::vector<uint8_t> px(n * ch);
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < ch; ++c) {
          const float v = finite_or_zero(image.pixels[i][c]);
          px[i * ch + c] = c < 3 ? srgb_byte(v) : to_u8(v);
        }
      return encode_pixels(name, "png", spec, px.data());
    }
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("compression", "zip");
    std::vector<uint16_t> px(n * ch);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < ch; ++c) px[i * ch + c] = to_u16(finite_or_zero(image.pixels[i][c]));
    return encode_pixels(name, "tiff", spec, px.data());
  }
  if (ext == ".exr") {
    OIIO::ImageSpec spec(image.width, image.height, ch, OIIO::TypeDesc::FLOAT);
    spec.attribute("oiio:UnassociatedAlpha", premultiplied ? 0 : 1);
    std::vector<float> px(n * ch);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < ch; ++c) px[i * ch + c] = finite_or_zero(image.pixels[i][c]);
    return encode_pixels(name, "openexr", spec, px.data());
  }
  return unknown_extension(name, ext);
}

Result<std::vector<unsigned char>> encode_plane(const std::string& path, const Plane& plane) {
  const std::string name = printable(path);  // in messages
  if (!image_shape_ok(plane.width, plane.height, plane.values.size()))
    return fail(name, "cannot write an empty or malformed plane (" + std::to_string(plane.width) +
                          "x" + std::to_string(plane.height) + ")");
  const std::string ext = lower_extension(path);
  const size_t n = plane.values.size();
  if (ext == ".exr" || ext == ".tif" || ext == ".tiff") {
    OIIO::ImageSpec spec(plane.width, plane.height, 1, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Y"};
    std::vector<float> px(n);
    for (size_t i = 0; i < n; ++i) px[i] = finite_or_zero(plane.values[i]);
    return encode_pixels(name, ext == ".exr" ? "openexr" : "tiff", spec, px.data());
  }
  if (ext == ".png") {
    double lo = 0.0, hi = 1.0;
    for (float v : plane.values)
      if (std::isfinite(v)) {
        lo = std::min(lo, static_cast<double>(v));
        hi = std::max(hi, static_cast<double>(v));
      }
    OIIO::ImageSpec spec(plane.width, plane.height, 1, OIIO::TypeDesc::UINT16);
    std::vector<uint16_t> px(n);
    for (size_t i = 0; i < n; ++i)
      px[i] = to_u16((finite_or_zero(plane.values[i]) - lo) / (hi - lo));
    return encode_pixels(name, "png", spec, px.data());
  }
  return unknown_extension(name, ext);
}

Status check_image_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".png" || ext == ".exr" || ext == ".tif" || ext == ".tiff") return {};
  return unknown_extension(printable(path), ext);
}

Status write_image(const std::string& path, const Image& image) {
  Result<std::vector<unsigned char>> bytes = encode_image(path, image);
  if (!bytes.ok()) return bytes.status();
  return write_file_atomic(path, as_text(*bytes));
}

Status write_plane(const std::string& path, const Plane& plane) {
  Result<std::vector<unsigned char>> bytes = encode_plane(path, plane);
  if (!bytes.ok()) return bytes.status();
  return write_file_atomic(path, as_text(*bytes));
}

}  // namespace relief
