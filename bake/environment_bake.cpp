// The environment bake (bake/environment_bake.h). Sources: Ramamoorthi & Hanrahan 2001, "An
// Efficient Representation for Irradiance Environment Maps"; Karis 2013, "Real Shading in Unreal
// Engine 4"; Colbert & Krivanek 2007, "GPU-Based Importance Sampling" (GPU Gems 3, ch. 20);
// glTF 2.0 specification, appendix B; Cigolle et al. 2014 (octahedral layout).
#include "bake/environment_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "base/thread_pool.h"
#include "shaders_cpp/environment.h"

namespace relief {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr float kHalfMax = 65504.0f;

// One level of the source's mip pyramid: linear RGB, rows top (+Y) to bottom.
struct SourceLevel {
  int w = 0, h = 0;
  std::vector<glm::vec3> px;
  const glm::vec3& at(int x, int y) const { return px[static_cast<size_t>(y) * w + x]; }
};

// Level 0 from the image (invalid texels to 0, counted), then box-filtered levels down to one
// row: each output texel averages the source texels its area covers.
std::vector<SourceLevel> source_pyramid(const Image& img, long long* replaced) {
  std::vector<SourceLevel> levels(1);
  SourceLevel& l0 = levels[0];
  l0.w = img.width;
  l0.h = img.height;
  l0.px.resize(img.pixels.size());
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    glm::vec3 c(img.pixels[i]);
    bool bad = false;
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(c[k]) && c[k] >= 0.0f)) {
        c[k] = 0.0f;
        bad = true;
      }
    *replaced += bad ? 1 : 0;
    l0.px[i] = c;
  }
  while (levels.back().h > 1) {
    const SourceLevel& a = levels.back();
    SourceLevel b;
    b.w = std::max(1, a.w / 2);
    b.h = std::max(1, a.h / 2);
    b.px.resize(static_cast<size_t>(b.w) * b.h);
    for (int y = 0; y < b.h; ++y)
      for (int x = 0; x < b.w; ++x) {
        const int x0 = x * a.w / b.w, x1 = (x + 1) * a.w / b.w;
        const int y0 = y * a.h / b.h, y1 = (y + 1) * a.h / b.h;
        glm::vec3 sum(0.0f);
        for (int j = y0; j < y1; ++j)
          for (int i = x0; i < x1; ++i) sum += a.at(i, j);
        b.px[static_cast<size_t>(y) * b.w + x] = sum / static_cast<float>((x1 - x0) * (y1 - y0));
      }
    levels.push_back(std::move(b));
  }
  return levels;
}

// Bilinear read of a level at equirect uv: u repeats, v clamps.
glm::vec3 bilinear(const SourceLevel& l, glm::vec2 uv) {
  const float x = uv.x * static_cast<float>(l.w) - 0.5f;
  const float y = uv.y * static_cast<float>(l.h) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float a = x - fx, b = y - fy;
  const auto wrap = [&](int i) { return ((i % l.w) + l.w) % l.w; };
  const auto clampy = [&](int j) { return std::clamp(j, 0, l.h - 1); };
  const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
  const int x0 = wrap(ix), x1 = wrap(ix + 1), y0 = clampy(iy), y1 = clampy(iy + 1);
  const glm::vec3 top = l.at(x0, y0) + (l.at(x1, y0) - l.at(x0, y0)) * a;
  const glm::vec3 bottom = l.at(x0, y1) + (l.at(x1, y1) - l.at(x0, y1)) * a;
  return top + (bottom - top) * b;
}

// Trilinear read of the pyramid along direction d at (fractional) level lod.
glm::vec3 trilinear(const std::vector<SourceLevel>& p, glm::vec3 d, float lod) {
  const glm::vec2 uv = equirect_uv(d);
  lod = std::clamp(lod, 0.0f, static_cast<float>(p.size() - 1));
  const int l0 = static_cast<int>(lod);
  const int l1 = std::min(l0 + 1, static_cast<int>(p.size()) - 1);
  const float f = lod - static_cast<float>(l0);
  const glm::vec3 a = bilinear(p[l0], uv);
  return f > 0.0f ? a + (bilinear(p[l1], uv) - a) * f : a;
}

// Point i of n of the Hammersley set: (i / n, radical inverse of i in base 2).
glm::dvec2 hammersley(uint32_t i, uint32_t n) {
  uint32_t b = i;
  b = (b << 16) | (b >> 16);
  b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
  b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
  b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
  b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
  return {static_cast<double>(i) / n, static_cast<double>(b) * (1.0 / 4294967296.0)};
}

// A GGX half vector (alpha^2 = a2) in the frame whose z is the normal: cos theta_h from xi.y.
glm::dvec3 ggx_half_vector(glm::dvec2 xi, double a2) {
  const double cos_t = std::sqrt((1.0 - xi.y) / (1.0 + (a2 - 1.0) * xi.y));
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  const double phi = 2.0 * kPi * xi.x;
  return {sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t};
}

double ggx_d(double ndoth, double a2) {
  const double t = ndoth * ndoth * (a2 - 1.0) + 1.0;
  return a2 / (kPi * t * t);
}

// One prefiltered texel along n at roughness `rough` (> 0) from the precomputed samples.
struct LobeSample {
  glm::dvec3 h;  // half vector in the normal's frame
  float lod;     // source level of its read
};
glm::vec3 prefilter(const std::vector<SourceLevel>& src, glm::vec3 n,
                    const std::vector<LobeSample>& samples) {
  const glm::dvec3 nz(n);
  const glm::dvec3 up = std::abs(nz.y) < 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  const glm::dvec3 tx = glm::normalize(glm::cross(up, nz));
  const glm::dvec3 ty = glm::cross(nz, tx);
  glm::dvec3 sum(0.0);
  double weight = 0.0;
  for (const LobeSample& s : samples) {
    const glm::dvec3 h = tx * s.h.x + ty * s.h.y + nz * s.h.z;
    const double ndoth = s.h.z;
    const glm::dvec3 l = h * (2.0 * ndoth) - nz;  // reflect(-N, H) with V = N
    const double ndotl = 2.0 * ndoth * ndoth - 1.0;
    if (ndotl <= 0.0) continue;
    sum += glm::dvec3(trilinear(src, glm::vec3(l), s.lod)) * ndotl;
    weight += ndotl;
  }
  return weight > 0.0 ? glm::vec3(sum / weight) : glm::vec3(0.0f);
}

// The samples of level `k` of `levels`: half vectors and their source LODs.
std::vector<LobeSample> lobe_samples(int k, int levels, int count, double texel_lod,
                                     double source_texel_sr) {
  const double rough = static_cast<double>(k) / (levels - 1);
  const double a2 = rough * rough * rough * rough;
  std::vector<LobeSample> out;
  for (int i = 0; i < count; ++i) {
    const glm::dvec3 h = ggx_half_vector(hammersley(i, count), a2);
    const double pdf = ggx_d(h.z, a2) / 4.0;  // of L, with V = N
    const double sample_sr = 1.0 / (count * pdf + 1e-30);
    const double lod = 0.5 * std::log2(std::max(sample_sr / source_texel_sr, 1e-30)) + 1.0;
    out.push_back({h, static_cast<float>(std::max(lod, texel_lod))});
  }
  return out;
}

// Floats to an RGBA16F level (values above the largest half counted).
MipLevel half_level(int w, int h, std::vector<float>& rgba, long long* clipped) {
  for (float& v : rgba)
    if (v > kHalfMax) {
      v = kHalfMax;
      ++*clipped;
    }
  Texture t = Texture::from_floats(TexFormat::kRGBA16F, w, h, rgba.data());
  return t.level(0);
}

Texture specular_chain(const std::vector<SourceLevel>& src, const EnvironmentBakeOptions& o,
                       ThreadPool& pool, long long* clipped) {
  const double source_texel_sr = (kPi / src[0].h) * (kPi / src[0].h);
  std::vector<MipLevel> levels;
  for (int k = 0; k < o.specular_levels; ++k) {
    const int n = std::max(1, o.specular_size >> k);
    const double texel_sr = 4.0 * kPi / (static_cast<double>(n) * n);
    const double texel_lod = std::max(0.0, 0.5 * std::log2(texel_sr / source_texel_sr));
    const std::vector<LobeSample> samples =
        k == 0 ? std::vector<LobeSample>{}
               : lobe_samples(k, o.specular_levels, o.specular_samples, texel_lod, source_texel_sr);
    std::vector<float> rgba(static_cast<size_t>(n) * n * 4, 1.0f);
    pool.run(n, [&](int y, int) {
      for (int x = 0; x < n; ++x) {
        const HWY_NAMESPACE::V2<float> uv((x + 0.5f) / n, (y + 0.5f) / n);
        const HWY_NAMESPACE::V3<float> d = HWY_NAMESPACE::octahedral_direction(uv);
        const glm::vec3 dir(d.x, d.y, d.z);
        const glm::vec3 c = k == 0 ? trilinear(src, dir, static_cast<float>(texel_lod))
                                   : prefilter(src, dir, samples);
        float* out = &rgba[(static_cast<size_t>(y) * n + x) * 4];
        out[0] = c.x;
        out[1] = c.y;
        out[2] = c.z;
      }
    });
    levels.push_back(half_level(n, n, rgba, clipped));
  }
  return Texture::from_levels(TexFormat::kRGBA16F, std::move(levels));
}

Texture split_sum_table(int size, int samples, ThreadPool& pool) {
  std::vector<float> rgba(static_cast<size_t>(size) * size * 4, 1.0f);
  pool.run(size, [&](int j, int) {
    for (int i = 0; i < size; ++i) {
      const glm::vec2 ab = integrate_split_sum((i + 0.5f) / size, (j + 0.5f) / size, samples);
      float* out = &rgba[(static_cast<size_t>(j) * size + i) * 4];
      out[0] = ab.x;
      out[1] = ab.y;
      out[2] = 0.0f;
    }
  });
  return Texture::from_floats(TexFormat::kRGBA16F, size, size, rgba.data());
}

std::array<glm::vec3, kEnvShCount> sh_of(const SourceLevel& l, ThreadPool& pool) {
  std::vector<std::array<glm::dvec3, kEnvShCount>> rows(l.h);
  pool.run(l.h, [&](int y, int) {
    const double t0 = kPi * y / l.h, t1 = kPi * (y + 1) / l.h;
    const double sr = (2.0 * kPi / l.w) * (std::cos(t0) - std::cos(t1));
    std::array<glm::dvec3, kEnvShCount> acc{};
    for (int x = 0; x < l.w; ++x) {
      const glm::vec3 d = equirect_direction((x + 0.5) / l.w, (y + 0.5) / l.h);
      float basis[kEnvShCount];
      HWY_NAMESPACE::sh_basis(HWY_NAMESPACE::V3<float>(d.x, d.y, d.z), basis);
      const glm::dvec3 c(l.at(x, y));
      for (int i = 0; i < kEnvShCount; ++i) acc[i] += c * (static_cast<double>(basis[i]) * sr);
    }
    rows[y] = acc;
  });
  std::array<glm::dvec3, kEnvShCount> total{};
  for (const auto& r : rows)  // in row order: the same sum for every thread count
    for (int i = 0; i < kEnvShCount; ++i) total[i] += r[i];
  constexpr double kBand[kEnvShCount] = {1.0,  2.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0, 0.25,
                                         0.25, 0.25,      0.25,      0.25};  // A_l / pi
  std::array<glm::vec3, kEnvShCount> sh{};
  for (int i = 0; i < kEnvShCount; ++i) sh[i] = glm::vec3(total[i] * kBand[i]);
  return sh;
}

Status check_options(const Image& img, const EnvironmentBakeOptions& o) {
  if (img.width < 1 || img.height < 1 || img.pixels.size() != size_t(img.width) * img.height)
    return Status::error("environment image is empty");
  if (static_cast<long long>(img.width) * img.height > kMaxEnvironmentBakeTexels)
    return Status::error("environment image is " + std::to_string(img.width) + "x" +
                         std::to_string(img.height) + ", more than the limit of " +
                         std::to_string(kMaxEnvironmentBakeTexels) + " texels");
  const bool pow2 = o.specular_size > 0 && (o.specular_size & (o.specular_size - 1)) == 0;
  if (!pow2 || o.specular_size > 4096 || o.specular_levels < 2 || o.specular_levels > 12 ||
      (o.specular_size >> (o.specular_levels - 1)) < 1 || o.specular_samples < 1 ||
      o.specular_samples > 65536 || o.lut_size < 2 || o.lut_size > 1024 || o.lut_samples < 1 ||
      o.lut_samples > 65536)
    return Status::error("environment bake options out of range");
  return Status();
}

}  // namespace

glm::vec3 equirect_direction(double u, double v) {
  const double theta = kPi * v, phi = 2.0 * kPi * (u - 0.5);
  return glm::vec3(static_cast<float>(std::sin(theta) * std::sin(phi)),
                   static_cast<float>(std::cos(theta)),
                   static_cast<float>(-std::sin(theta) * std::cos(phi)));
}

glm::vec2 equirect_uv(glm::vec3 d) {
  const double len = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
  if (!(len > 0.0)) return {0.5f, 0.0f};
  const double theta = std::acos(std::clamp(d.y / len, -1.0, 1.0));
  const double phi = std::atan2(double(d.x), -double(d.z));
  return {static_cast<float>(phi / (2.0 * kPi) + 0.5), static_cast<float>(theta / kPi)};
}

double smith_visibility(double ndotl, double ndotv, double a2) {
  const double gv = ndotl * std::sqrt(ndotv * ndotv * (1.0 - a2) + a2);
  const double gl = ndotv * std::sqrt(ndotl * ndotl * (1.0 - a2) + a2);
  const double sum = gv + gl;
  return sum > 0.0 ? 0.5 / sum : 0.0;
}

glm::vec2 integrate_split_sum(float ndotv, float roughness, int samples) {
  const double nv = std::clamp(static_cast<double>(ndotv), 1e-4, 1.0);
  const double r = std::clamp(static_cast<double>(roughness), 0.0, 1.0);
  const double a2 = r * r * r * r;
  const glm::dvec3 v(std::sqrt(1.0 - nv * nv), 0.0, nv);
  double a = 0.0, b = 0.0;
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 h = ggx_half_vector(hammersley(i, samples), a2);
    const double vdoth = glm::dot(v, h);
    const glm::dvec3 l = h * (2.0 * vdoth) - v;
    const double ndotl = l.z, ndoth = h.z;
    if (ndotl <= 0.0 || vdoth <= 0.0) continue;
    const double w = 4.0 * smith_visibility(ndotl, nv, a2) * ndotl * vdoth / ndoth;
    const double fc = std::pow(1.0 - vdoth, 5.0);
    a += (1.0 - fc) * w;
    b += fc * w;
  }
  return {static_cast<float>(a / samples), static_cast<float>(b / samples)};
}

std::array<glm::vec3, kEnvShCount> environment_sh(const Image& equirect, int threads) {
  long long replaced = 0;
  ThreadPool pool(threads);
  return sh_of(source_pyramid(equirect, &replaced)[0], pool);
}

Result<EnvironmentMaps> bake_environment(const Image& equirect,
                                         const EnvironmentBakeOptions& options) {
  RELIEF_RETURN_IF_ERROR(check_options(equirect, options));
  EnvironmentMaps maps;
  const std::vector<SourceLevel> src = source_pyramid(equirect, &maps.replaced_texels);
  ThreadPool pool(options.threads);
  maps.sh = sh_of(src[0], pool);
  maps.specular = specular_chain(src, options, pool, &maps.clipped_values);
  maps.brdf_lut = split_sum_table(options.lut_size, options.lut_samples, pool);
  split_channels(maps);
  return maps;
}

namespace {
// Channel c of every level of t as an R32F texture (the texel values exactly).
Texture channel_plane(const Texture& t, int c) {
  std::vector<MipLevel> levels;
  for (int k = 0; k < t.levels(); ++k) {
    const MipLevel& src = t.level(k);
    MipLevel l{src.width, src.height, std::vector<uint8_t>(size_t(src.width) * src.height * 4)};
    for (int y = 0; y < src.height; ++y)
      for (int x = 0; x < src.width; ++x) {
        const float v = t.fetch(k, x, y)[c];
        std::memcpy(l.data.data() + (size_t(y) * src.width + x) * 4, &v, 4);
      }
    levels.push_back(std::move(l));
  }
  return Texture::from_levels(TexFormat::kR32F, std::move(levels));
}
}  // namespace

void split_channels(EnvironmentMaps& maps) {
  if (!maps.specular.empty())
    for (int c = 0; c < 3; ++c) maps.specular_planes[c] = channel_plane(maps.specular, c);
  if (!maps.brdf_lut.empty())
    for (int c = 0; c < 2; ++c) maps.brdf_planes[c] = channel_plane(maps.brdf_lut, c);
}

namespace {
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
// A soft rectangular panel facing direction c (gnomonic half extents sx, sy, soft edge `soft`).
double panel(glm::dvec3 d, glm::dvec3 c, double sx, double sy, double soft) {
  const double dc = glm::dot(d, c);
  if (dc <= 0.0) return 0.0;
  const glm::dvec3 right = glm::normalize(glm::cross(c, glm::dvec3(0, 1, 0)));
  const glm::dvec3 up = glm::cross(right, c);
  const double s = std::abs(glm::dot(d, right) / dc), t = std::abs(glm::dot(d, up) / dc);
  return (1.0 - smoothstep(sx - soft, sx + soft, s)) * (1.0 - smoothstep(sy - soft, sy + soft, t));
}
}  // namespace

Image studio_environment(int width, int height) {
  Image img(std::max(width, 1), std::max(height, 1), glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
  const glm::dvec3 key = glm::normalize(glm::dvec3(0.6, 0.55, 0.6));   // upper front right
  const glm::dvec3 fill = glm::normalize(glm::dvec3(-0.8, 0.2, 0.3));  // left, lower
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec3 d(equirect_direction((x + 0.5) / img.width, (y + 0.5) / img.height));
      const double sky = 0.45 + 0.35 * std::max(d.y, 0.0);  // brighter overhead
      const double floor = 0.18 + 0.04 * (1.0 + d.y);       // darker below
      double l = floor + (sky - floor) * smoothstep(-0.08, 0.08, d.y);
      l += 6.0 * panel(d, key, 0.5, 0.35, 0.12) + 1.5 * panel(d, fill, 0.45, 0.45, 0.15);
      const float v = static_cast<float>(l);
      img.at(x, y) = glm::vec4(v, v, v, 1.0f);
    }
  return img;
}

}  // namespace relief
