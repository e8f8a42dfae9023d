// Image and texture files through OpenImageIO: loading textures in their stored format, reading
// and atomically writing linear float images and planes.
#include "scene/image_io.h"

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

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
double srgb_encode(double c) {
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
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

// An opened input whose size has been checked.
struct Input {
  std::unique_ptr<OIIO::ImageInput> in;
  int width = 0;
  int height = 0;
  int channels = 0;
  Depth depth = Depth::kFloat;
};

Status open_input(const std::string& path, Input& out) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return fail(path, "no such file");
  if (fs::is_directory(path, ec)) return fail(path, "is a directory, not an image");
  // Keep alpha unassociated: texture alpha is data (depth, heights), never premultiplied.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  out.in = OIIO::ImageInput::open(path, &config);
  if (!out.in) return fail(path, "cannot read image: " + one_line(OIIO::geterror()));
  const OIIO::ImageSpec& spec = out.in->spec();
  if (spec.width <= 0 || spec.height <= 0)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", expected at least 1x1");
  if (spec.width > kMaxImageSide || spec.height > kMaxImageSide)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", larger than the limit of " + std::to_string(kMaxImageSide) +
                          " on a side");
  if (static_cast<long long>(spec.width) * spec.height > kMaxImageTexels)
    return fail(path, "image is " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                          ", more than the limit of " + std::to_string(kMaxImageTexels) +
                          " texels");
  if (spec.depth > 1) return fail(path, "volume images are not supported");
  if (spec.nchannels < 1) return fail(path, "image has no channels");
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

// Reads channels [0, nch) of subimage 0, level 0 as `type`.
Status read_pixels(const std::string& path, Input& in, int nch, OIIO::TypeDesc type, void* data) {
  if (!in.in->read_image(0, 0, 0, nch, type, data))
    return fail(path, "cannot decode image: " + one_line(in.in->geterror()));
  return Status();
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// Writes `pixels` (type, channels, channel names) to a temporary next to `path`, then renames it.
Status write_atomic(const std::string& path, const char* oiio_format, OIIO::ImageSpec spec,
                    const void* pixels) {
  static std::atomic<unsigned> counter{0};
  std::error_code ec;
  const fs::path target(path);
  if (target.filename().empty()) return fail(path, "not a file name");
  fs::path dir = target.parent_path();
  if (dir.empty()) dir = ".";
  if (!fs::is_directory(dir, ec)) return fail(path, "directory does not exist");
  const fs::path tmp =
      dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
             std::to_string(counter.fetch_add(1)) + target.extension().string());
  auto cleanup = [&tmp] {
    std::error_code ignored;
    fs::remove(tmp, ignored);
  };
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(oiio_format);
  if (!out)
    return fail(path, std::string("no ") + oiio_format + " writer: " + one_line(OIIO::geterror()));
  if (!out->open(tmp.string(), spec)) {
    const std::string err = one_line(out->geterror());
    out.reset();
    cleanup();
    return fail(path, "cannot write: " + err);
  }
  if (!out->write_image(spec.format, pixels)) {
    const std::string err = one_line(out->geterror());
    out->close();
    out.reset();
    cleanup();
    return fail(path, "cannot write: " + err);
  }
  if (!out->close()) {
    const std::string err = one_line(out->geterror());
    out.reset();
    cleanup();
    return fail(path, "cannot write: " + err);
  }
  out.reset();
  fs::rename(tmp, target, ec);
  if (ec) {
    cleanup();
    return fail(path, "cannot write: " + ec.message());
  }
  return Status();
}

bool image_shape_ok(int w, int h, size_t n) {
  return w >= 1 && h >= 1 && n == static_cast<size_t>(w) * static_cast<size_t>(h);
}

}  // namespace

Result<Texture> load_texture(const std::string& path, const TextureLoadOptions& opts) {
  if (opts.height_to_depth && opts.color_space != ColorSpace::kLinear)
    return Status::usage(path + ": height_to_depth needs a linear colour space, not sRGB");
  Input in;
  RELIEF_RETURN_IF_ERROR(open_input(path, in));
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
  for (size_t i = 0; i < n; ++i) {
    float* d = &values[i * dst_ch];
    if (dst_ch == 4) d[3] = 1.0f;
    for (int c = 0; c < src_ch; ++c) {
      float v = finite_or_zero(src[i * src_ch + c]);
      if (srgb && c < 3) v = static_cast<float>(srgb_decode(v));
      d[c] = v;
    }
    if (opts.height_to_depth) d[0] = 1.0f - d[0];
  }
  return Texture::from_floats(f, in.width, in.height, values.data());
}

Result<Image> read_image(const std::string& path) {
  Input in;
  RELIEF_RETURN_IF_ERROR(open_input(path, in));
  const int ch = std::min(in.channels, 4);
  const size_t n = static_cast<size_t>(in.width) * in.height;
  std::vector<float> src(n * ch);
  RELIEF_RETURN_IF_ERROR(read_pixels(path, in, ch, OIIO::TypeDesc::FLOAT, src.data()));
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

Status write_image(const std::string& path, const Image& image) {
  if (!image_shape_ok(image.width, image.height, image.pixels.size()))
    return fail(path, "cannot write an empty or malformed image (" + std::to_string(image.width) +
                          "x" + std::to_string(image.height) + ")");
  const std::string ext = lower_extension(path);
  const size_t n = image.pixels.size();
  bool opaque = true;
  for (const glm::vec4& p : image.pixels) opaque = opaque && p.a == 1.0f;
  if (ext == ".png" || ext == ".tif" || ext == ".tiff") {
    const bool png = ext == ".png";
    const int ch = opaque ? 3 : 4;
    OIIO::ImageSpec spec(image.width, image.height, ch,
                         png ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::UINT16);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (png) {
      spec.attribute("oiio:ColorSpace", "sRGB");
      std::vector<uint8_t> px(n * ch);
      for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < ch; ++c) {
          const double v = finite_or_zero(image.pixels[i][c]);
          px[i * ch + c] = to_u8(c < 3 ? srgb_encode(clamp01(v)) : v);
        }
      return write_atomic(path, "png", spec, px.data());
    }
    spec.attribute("oiio:ColorSpace", "Linear");
    spec.attribute("compression", "zip");
    std::vector<uint16_t> px(n * ch);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < ch; ++c) px[i * ch + c] = to_u16(finite_or_zero(image.pixels[i][c]));
    return write_atomic(path, "tiff", spec, px.data());
  }
  if (ext == ".exr") {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    std::vector<float> px(n * 4);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 4; ++c) px[i * 4 + c] = finite_or_zero(image.pixels[i][c]);
    return write_atomic(path, "openexr", spec, px.data());
  }
  return Status::usage(path + ": unknown image extension '" + ext +
                       "', expected .png, .exr, .tif or .tiff");
}

Status write_plane(const std::string& path, const Plane& plane) {
  if (!image_shape_ok(plane.width, plane.height, plane.values.size()))
    return fail(path, "cannot write an empty or malformed plane (" + std::to_string(plane.width) +
                          "x" + std::to_string(plane.height) + ")");
  const std::string ext = lower_extension(path);
  const size_t n = plane.values.size();
  if (ext == ".exr" || ext == ".tif" || ext == ".tiff") {
    OIIO::ImageSpec spec(plane.width, plane.height, 1, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Y"};
    std::vector<float> px(n);
    for (size_t i = 0; i < n; ++i) px[i] = finite_or_zero(plane.values[i]);
    return write_atomic(path, ext == ".exr" ? "openexr" : "tiff", spec, px.data());
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
    return write_atomic(path, "png", spec, px.data());
  }
  return Status::usage(path + ": unknown image extension '" + ext +
                       "', expected .png, .exr, .tif or .tiff");
}

}  // namespace relief
