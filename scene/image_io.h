// Image and texture files through OpenImageIO (which stays out of rasterizer/ headers).
//
// Row 0 of a file is texel / pixel row 0 (top of the image), matching texture.h and image.h.
// Colour conventions: 8-bit integer files (PNG, JPEG, 8-bit TIFF) hold sRGB-encoded colour and
// linear alpha; 16-bit integer and float files (16-bit PNG/TIFF, EXR) hold linear values.
// Every error is one line that starts with the path and says what was wrong.
#pragma once

#include <string>
#include <vector>

#include "base/status.h"
#include "rasterizer/image.h"
#include "rasterizer/texture.h"

namespace relief {

// Files larger than this on either side, or with more texels in all, are refused when the header
// is read, before any pixel memory is allocated (docs/errors.md, "Limits"). kMaxImageTexels
// holds for read_image (compare: up to an 8192 x 8192 render), kMaxTextureTexels (4096 x 4096)
// for textures: decoding 64 Mi texels takes about 1.5 s, but mips and the maps derived from a
// depth texture then took 19 s and 4 GB for an 8192 x 8192 depth map (3 s for colour); at
// 16 Mi, 5 s and 1.1 GB (1 s for colour).
inline constexpr int kMaxImageSide = 16384;
inline constexpr long long kMaxImageTexels = 64LL * 1024 * 1024;
inline constexpr long long kMaxTextureTexels = 16LL * 1024 * 1024;
// load_environment's limit: 8192 x 4096, the largest common HDRI size (the bake's own limit,
// shaders_cpp/environment_maps.h).
inline constexpr long long kMaxEnvironmentTexels = 8192LL * 4096;
// A tiled file's (EXR, TIFF) tile is decoded into a buffer of its whole size, whatever the image's
// size: at most this many values (tile width x height x channels; a 1024 x 1024 RGBA tile).
// Found by fuzz_image_header: a 20 x 28 EXR with 6560 x 29684 tiles took 3.4 s and 2 GB.
inline constexpr long long kMaxTileValues = 4LL * 1024 * 1024;

struct TextureLoadOptions {
  // kSRGB: colour channels are sRGB-encoded and decode to linear when sampled (8-bit formats keep
  // the bytes and decode through the texture's table; 16-bit and float sources are decoded at
  // load). Must be kLinear with height_to_depth.
  ColorSpace color_space = ColorSpace::kLinear;
  // Keep only channel 0 (R8, R16, R16F or R32F), whatever the file holds.
  bool first_channel_only = false;
  // The file holds a height map (1 = top): store depth d = 1 - h in channel 0 (exact for integer
  // formats: 255 - b, 65535 - v). Other channels are left alone.
  bool height_to_depth = false;
  // Channel 0 is a depth (or height) map, which holds [0, 1]: a float file's values outside it
  // are clamped and non-finite ones read as 0, with one warning line on stderr that says how
  // many texels changed (integer formats cannot leave the range).
  bool unit_range = false;
};

// Loads level 0 of a texture (no mips; call generate_mips). Only a regular file is read
// (rasterizer/safe_file.h: never a FIFO or a device, at most kMaxInputFileBytes), into memory,
// and decoded from there; libpng's own stderr lines are caught (not printed). The format
// follows the file:
//   8-bit:        1 channel R8, 2 RG8, 3 RGBA8 (alpha 1), 4+ RGBA8 (first four)
//   16-bit int:   1 channel R16, otherwise RGBA16F (missing channels 0, alpha 1)
//   half / float: 1 channel R16F (half) or R32F (float or wider), otherwise RGBA16F
// first_channel_only forces the one-channel format of the file's depth.
Result<Texture> load_texture(const std::string& path, const TextureLoadOptions& opts = {});

// load_texture of an image held in memory (an embedded glTF image); `name` starts its messages.
// The decoder reads only `bytes` (at most kMaxInputFileBytes).
Result<Texture> load_texture_from_memory(std::string bytes, const std::string& name,
                                         const TextureLoadOptions& opts = {});

// Reads an image as linear float RGBA (1 channel: grey, alpha 1; 2: grey + alpha; 3: alpha 1).
// 8-bit files are decoded from sRGB (alpha stays linear). Non-finite values read as 0.
Result<Image> read_image(const std::string& path);

// Reads an equirectangular environment (docs/environment.md; shaders_cpp/environment_maps.h has
// its orientation) as linear RGB, alpha 1: a Radiance .hdr (RGBE) or an OpenEXR file (any image
// format read_image reads is accepted; 8-bit files decode from sRGB). Texels that are NaN,
// infinite or negative read as 0, and `replaced` (when not null) says how many there were, for
// the caller to warn about. Errors, one line starting with the path: what read_image refuses
// (missing, not a regular file, not an image, too large a file), more than
// kMaxEnvironmentTexels texels, and an aspect other than exactly 2:1 (width == 2 * height): an
// equirectangular map of another shape would be stretched, which is an error, not a guess.
Result<Image> load_environment(const std::string& path, long long* replaced = nullptr);

// Writes by extension: .png 8-bit sRGB-encoded, .exr float linear, .tif/.tiff 16-bit linear.
// Integer formats clamp to [0, 1]; RGB when every alpha is 1, RGBA otherwise (EXR: always RGBA).
// NaN or Inf pixels are written as 0. The file is encoded in memory and written atomically
// (rasterizer/output_file.h: checked writes, fsync, rename); on failure nothing is left behind
// and a file already at `path` is unchanged.
Status write_image(const std::string& path, const Image& image);
// The bytes write_image / write_plane write to `path` (format by its extension), for callers
// that stage several outputs together (StagedFiles). Errors start with `path`.
Result<std::vector<unsigned char>> encode_image(const std::string& path, const Image& image);
// encode_image with the channel count chosen by the caller, not by content: `channels` 3 (RGB,
// alpha dropped) or 4 (RGBA; `premultiplied` marks an EXR's or TIFF's alpha as associated).
Result<std::vector<unsigned char>> encode_image(const std::string& path, const Image& image,
                                                int channels, bool premultiplied);
// Whether encode_image writes `path` as 8-bit sRGB-encoded colour (.png, any case): the
// display-referred files `relief render --tonemap` maps; .exr, .tif and .tiff stay linear.
bool image_is_8bit(const std::string& path);
Result<std::vector<unsigned char>> encode_plane(const std::string& path, const Plane& plane);
// OK when `path` ends in an extension write_image and write_plane know (.png .exr .tif .tiff,
// any case); else a usage error (exit 2) starting with `path`.
Status check_image_extension(const std::string& path);

// One-channel float plane (depth, steps, ...): .exr and .tif/.tiff as 32-bit float (channel "Y");
// .png as 16-bit grey normalised by the range [min(0, lowest), max(1, highest)], so values in
// [0, 1] are stored as they are. Atomic like write_image; non-finite values are written as 0.
Status write_plane(const std::string& path, const Plane& plane);

}  // namespace relief
