// Textures and sampling for the CPU backend.
//
// Conventions: texel (0, 0) is the first texel in memory and the top-left of the source image;
// texture coordinate (u, v) = (0, 0) is that texel's outer corner, (1, 1) the opposite corner, and
// texel (i, j) has its centre at ((i + 0.5) / w, (j + 0.5) / h). The GL backend uploads the same
// bytes row 0 first, so texture(uv) addresses the same texel in both backends.
//
// Storage keeps the source format (R8 ... R32F) per mip level; fetches decode to linear float
// (sRGB-encoded 8-bit colour is decoded through a table). LOD follows the OpenGL 4.5 specification
// (section 8.14): rho = max(|d(uv*size)/dx|, |d(uv*size)/dy|), lod = log2(rho), clamped to
// [0, levels-1]. Anisotropic filtering takes up to max_aniso trilinear probes along the major axis
// of the footprint (the EXT_texture_filter_anisotropic model).
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace relief {

enum class TexFormat : uint8_t { kR8, kRG8, kRGBA8, kR16, kR16F, kRGBA16F, kR32F };
int format_channels(TexFormat f);
int format_bytes_per_texel(TexFormat f);
const char* format_name(TexFormat f);

enum class ColorSpace : uint8_t { kLinear, kSRGB };  // sRGB applies to 8-bit RGB(A) colour only
enum class Filter : uint8_t { kNearest, kBilinear, kTrilinear, kAnisotropic };
enum class Wrap : uint8_t { kRepeat, kClamp, kMirror };
// How a mip level is made from the one above: average (colour, normals), or the minimum or
// maximum of each 2x2 block (cone maps; max-mips for empty-space skipping).
enum class MipReduce : uint8_t { kAverage, kMin, kMax };

struct SamplerState {
  Filter filter = Filter::kTrilinear;
  Wrap wrap_u = Wrap::kRepeat;
  Wrap wrap_v = Wrap::kRepeat;
  int max_aniso = 16;  // 1..16, used by kAnisotropic
};

struct MipLevel {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> data;  // tightly packed rows, format_bytes_per_texel each
};

class Texture {
 public:
  Texture() = default;
  // Level 0 from tightly packed texels (copied). Width and height >= 1.
  Texture(TexFormat format, int width, int height, const void* texels,
          ColorSpace color_space = ColorSpace::kLinear);
  // Level 0 from float channels (count = width*height*format_channels), encoded into `format`.
  static Texture from_floats(TexFormat format, int width, int height, const float* values,
                             ColorSpace color_space = ColorSpace::kLinear);
  // A texture of explicit levels (a prefiltered chain: bake/environment_bake.h), moved in: level
  // k must be max(1, w >> k) x max(1, h >> k) of level 0's w x h (the sizes generate_mips makes,
  // which the samplers assume) and hold that many texels of `format`; fewer levels than a full
  // chain are allowed (sampling clamps the LOD to levels() - 1, as GL does with
  // GL_TEXTURE_MAX_LEVEL = levels() - 1). Float texels are sanitised like the constructor's.
  // CHECK-fails on a size mismatch or no levels.
  static Texture from_levels(TexFormat format, std::vector<MipLevel> levels,
                             ColorSpace color_space = ColorSpace::kLinear);

  // Replaces levels 1.. with a full chain down to 1x1 (non-power-of-two: floor halving, each
  // output texel reduces the 2x2 (or 2x1, 1x2) block that covers it).
  void generate_mips(MipReduce reduce = MipReduce::kAverage);
  // Replaces every texel of levels 1.. by the minimum (kMin) or maximum (kMax) of itself and its
  // eight neighbours (wrapped by wrap_u, wrap_v). After generate_mips(kMin) a bilinear read of
  // level k >= 1 anywhere in the square between four texel centres is then no more than any
  // level-0 texel under those four texels' blocks, so the level-0 bilinear surface within half a
  // level-k texel (less half a level-0 texel) of the read point never lies below it: a
  // conservative min over the read's footprint, for every filter and LOD (derived_maps.h
  // "depth_max_mip"). kAverage leaves the levels as they are.
  void dilate_mips(MipReduce reduce, Wrap wrap_u, Wrap wrap_v);

  TexFormat format() const { return format_; }
  ColorSpace color_space() const { return color_space_; }
  int width(int level = 0) const { return levels_[level].width; }
  int height(int level = 0) const { return levels_[level].height; }
  int levels() const { return static_cast<int>(levels_.size()); }
  const MipLevel& level(int i) const { return levels_[i]; }
  bool empty() const { return levels_.empty(); }

  // Texel at integer coordinates (already wrapped, inside the level), decoded to linear float;
  // missing channels read as (0, 0, 0, 1) like GL.
  glm::vec4 fetch(int level, int x, int y) const;
  // First channel only: the fast path for depth and cone maps.
  float fetch_r(int level, int x, int y) const;

  // The bilinear footprints of an R8 level, for the lane-parallel reads (shaders_cpp/sampling.h
  // bilinear_at: one 4-byte gather a read instead of two texel-pair gathers). Word
  // row * width + column holds the four texels a bilinear read with integer corner (ix, iy)
  // blends: (x0, y0), (x1, y0), (x0, y1), (x1, y1) in bytes 0 to 3, where x0 = wrap(ix) and
  // x1 = wrap(ix + 1) by wrap_u, y0 and y1 likewise by wrap_v. The column is footprint_cell(ix):
  // x0 for repeat (width = the level's width), min(max(ix, -1), w - 1) + 1 for clamp (width = w +
  // 1: ix = -1 reads texel 0 twice). Rows likewise. Built on the first call for that level and
  // those wraps, once, from any thread, and kept with the texture (copies share them until one
  // is changed). Empty (null words) for other formats, mirror wraps and levels over 16 M
  // footprints.
  struct Footprints {
    const uint32_t* words = nullptr;
    int width = 0;  // words a row
  };
  Footprints r8_footprints(int level, Wrap wrap_u, Wrap wrap_v) const;

 private:
  struct FootprintCache;
  void reset_footprints();  // after the levels change

  TexFormat format_ = TexFormat::kRGBA8;
  ColorSpace color_space_ = ColorSpace::kLinear;
  std::vector<MipLevel> levels_;
  std::shared_ptr<FootprintCache> footprints_;  // null until levels exist (R8 only)
};

using TexturePtr = std::shared_ptr<const Texture>;

// The 8-bit sRGB byte of linear value v: lround(255 * srgb(v)), srgb the IEC 61966-2-1 curve in
// double; 0 for v <= 0 and NaN, 255 for v >= 1 (what an sRGB texture stores, and .png output).
uint8_t encode_srgb8(float v);

// Decode tables of 8-bit channels: unorm (i / 255) and sRGB (to linear), 256 floats each.
const float* unorm8_table();
const float* srgb8_table();

// GL wrap of an integer texel coordinate (OpenGL 4.5, table 8.20): the result is in [0, size).
inline int wrap_texel(int i, int size, Wrap w) {
  if (static_cast<unsigned>(i) < static_cast<unsigned>(size)) return i;
  switch (w) {
    case Wrap::kRepeat: {
      const int m = i % size;
      return m < 0 ? m + size : m;
    }
    case Wrap::kClamp:
      return i < 0 ? 0 : size - 1;
    case Wrap::kMirror: {
      int m = i % (2 * size);
      if (m < 0) m += 2 * size;
      const int a = m - size;
      const int mirrored = a >= 0 ? a : -(1 + a);
      return (size - 1) - mirrored;
    }
  }
  return 0;
}

// The footprint column (row) of integer texel coordinate i at a level `size` texels wide (high)
// under wrap w (repeat or clamp; Texture::r8_footprints).
inline int footprint_cell(int i, int size, Wrap w) {
  if (w == Wrap::kClamp) return std::min(std::max(i, -1), size - 1) + 1;
  return wrap_texel(i, size, w);
}

// LOD (before clamping) from screen-space derivatives of uv, as GL computes it.
float compute_lod(const Texture& t, glm::vec2 duv_dx, glm::vec2 duv_dy);

// textureLod: explicit LOD. The filters are GL's minification modes: kNearest is
// NEAREST_MIPMAP_NEAREST, kBilinear LINEAR_MIPMAP_NEAREST (level nearest to lod), kTrilinear
// LINEAR_MIPMAP_LINEAR (blends the two levels around lod). lod <= 0 magnifies level 0 (nearest
// for kNearest, bilinear otherwise). A texture with one level behaves as one without mipmaps.
glm::vec4 sample_lod(const Texture& t, const SamplerState& s, glm::vec2 uv, float lod);
// textureGrad / texture: LOD (and anisotropy) from derivatives.
glm::vec4 sample_grad(const Texture& t, const SamplerState& s, glm::vec2 uv, glm::vec2 duv_dx,
                      glm::vec2 duv_dy);
// First-channel variant of sample_lod with bilinear (or trilinear when lod is fractional and the
// filter asks for it) filtering: the inner-loop sampler of the relief searches.
float sample_r_lod(const Texture& t, const SamplerState& s, glm::vec2 uv, float lod);

}  // namespace relief
