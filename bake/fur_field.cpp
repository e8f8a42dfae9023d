// Generated fur and grass depth fields (conventions and parameters in bake/fur_field.h).
#include "bake/fur_field.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "bake/normal_map.h"

namespace relief {
namespace {

// The rounded top: a strand's height at its edge, as a fraction of its height at the centre line.
constexpr float kEdgeHeight = 0.7f;
// A blade is this many root radii long, its tip this fraction of the root's width, and its root
// end this fraction of its tip height.
constexpr float kBladeLength = 6.0f;
constexpr float kBladeTipWidth = 0.2f;
constexpr float kBladeRootHeight = 0.7f;
// The splat's work bound: strands per texel times a strand's footprint in texels.
constexpr double kMaxCoverage = 50.0;

// splitmix64 (Steele, Lea and Flood 2014): a fixed integer sequence for a seed on every machine.
class SplitMix {
 public:
  explicit SplitMix(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1): the top 24 bits, exact in a float.
  float unit() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }

 private:
  uint64_t state_;
};

// The footprint of one strand in texels: the largest distance from its centre (or root) that it
// covers.
float strand_extent(FurKind kind, float radius) {
  return kind == FurKind::kFur ? radius : radius * (kBladeLength + 1.0f);
}

// Height at a texel centre offset (dx, dy) from a strand, or -1 where the strand does not cover
// it. The cross-section is a circular arc from 1 on the centre line to kEdgeHeight at the edge.
float strand_height(FurKind kind, const FurStrand& s, float radius, float dx, float dy) {
  float rr, along = 1.0f;
  if (kind == FurKind::kFur) {
    rr = (dx * dx + dy * dy) / (radius * radius);
  } else {
    // Distance to the blade's spine (root to tip), over the half width where it is closest.
    const float length = kBladeLength * radius;
    const float t = std::clamp((dx * s.dir_x + dy * s.dir_y) / length, 0.0f, 1.0f);
    const float px = dx - t * length * s.dir_x, py = dy - t * length * s.dir_y;
    const float half = radius * (1.0f - (1.0f - kBladeTipWidth) * t);
    rr = (px * px + py * py) / (half * half);
    along = kBladeRootHeight + (1.0f - kBladeRootHeight) * t;
  }
  if (rr >= 1.0f) return -1.0f;
  const float arc = 1.0f - (1.0f - kEdgeHeight) * (1.0f - std::sqrt(1.0f - rr));
  return s.height * along * arc;
}

// One strand's random draws, in a fixed order: position, height, direction (grass), tint.
FurStrand draw_strand(const FurFieldOptions& o, SplitMix& rng) {
  FurStrand s;
  s.x = rng.unit() * static_cast<float>(o.size);
  s.y = rng.unit() * static_cast<float>(o.size);
  s.height = 1.0f - o.jitter * rng.unit();
  if (o.kind == FurKind::kGrass) {
    // A uniform direction by rejection from the square: no sin or cos, whose last bits differ
    // between C libraries.
    float x, y, len2;
    do {
      x = 2.0f * rng.unit() - 1.0f;
      y = 2.0f * rng.unit() - 1.0f;
      len2 = x * x + y * y;
    } while (len2 > 1.0f || len2 < 1e-4f);
    const float inv = 1.0f / std::sqrt(len2);
    s.dir_x = x * inv;
    s.dir_y = y * inv;
  }
  const float a = rng.unit(), b = rng.unit();
  if (o.kind == FurKind::kFur) {
    // brown toward grey, brighter or darker by up to 15 %
    const glm::vec3 brown(0.50f, 0.36f, 0.22f), grey(0.46f, 0.44f, 0.42f);
    s.tip = (brown + (grey - brown) * (0.6f * a)) * (0.85f + 0.3f * b);
  } else {
    // green with the hue pushed toward yellow or toward blue-green
    const float hue = a - 0.5f;
    s.tip = glm::vec3(0.26f + 0.16f * hue, 0.50f + 0.06f * b, 0.10f - 0.06f * hue);
  }
  return s;
}

glm::vec3 root_color(FurKind kind) {
  return kind == FurKind::kFur ? glm::vec3(0.05f, 0.035f, 0.025f) : glm::vec3(0.04f, 0.05f, 0.02f);
}

// Writes strand `index` into the field where it is the highest surface so far.
void splat(const FurFieldOptions& o, const FurStrand& s, int index, std::vector<float>& height,
           std::vector<int>& owner) {
  const float ext = strand_extent(o.kind, o.radius);
  const int n = o.size;
  const int x0 = static_cast<int>(std::floor(s.x - ext)),
            x1 = static_cast<int>(std::ceil(s.x + ext));
  const int y0 = static_cast<int>(std::floor(s.y - ext)),
            y1 = static_cast<int>(std::ceil(s.y + ext));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      // The unwrapped texel centre gives the offset to this periodic image of the strand; the
      // texel written is its wrap into the field.
      const float h = strand_height(o.kind, s, o.radius, x + 0.5f - s.x, y + 0.5f - s.y);
      if (h <= 0.0f) continue;
      const size_t i =
          static_cast<size_t>(((y % n) + n) % n) * n + static_cast<size_t>(((x % n) + n) % n);
      if (h > height[i]) {
        height[i] = h;
        owner[i] = index;
      }
    }
}

}  // namespace

const char* fur_kind_name(FurKind kind) {
  return kind == FurKind::kFur ? "fur" : "grass";
}

FurFieldOptions fur_field_defaults(FurKind kind) {
  FurFieldOptions o;
  o.kind = kind;
  if (kind == FurKind::kGrass) {
    o.density = 90.0f;
    o.radius = 2.0f;
    o.jitter = 0.4f;
  }
  return o;
}

Status check_fur_field_options(const FurFieldOptions& o) {
  if (o.size < 1 || o.size > 4096) return Status::usage("fur field: --size must be in 1..4096");
  if (!std::isfinite(o.density) || o.density < 0.0f || o.density > 10000.0f)
    return Status::usage("fur field: --density must be in [0, 10000] strands per 100x100 texels");
  if (!std::isfinite(o.radius) || o.radius < 0.5f || o.radius > 32.0f)
    return Status::usage("fur field: --radius must be in [0.5, 32] texels");
  if (!std::isfinite(o.jitter) || o.jitter < 0.0f || o.jitter > 1.0f)
    return Status::usage("fur field: --jitter must be in [0, 1]");
  const double ext = strand_extent(o.kind, o.radius);
  if (o.density / 1e4 * (2.0 * ext + 1.0) * (2.0 * ext + 1.0) > kMaxCoverage)
    return Status::usage("fur field: --density times the strand's footprint exceeds " +
                         std::to_string(static_cast<int>(kMaxCoverage)) +
                         " strands per texel; lower --density or --radius");
  return Status();
}

Result<FurField> make_fur_field(const FurFieldOptions& o) {
  if (Status s = check_fur_field_options(o); !s.ok()) return s;
  FurField f;
  f.size = o.size;
  const size_t texels = static_cast<size_t>(o.size) * o.size;
  const long count = std::lround(o.density * static_cast<double>(texels) / 1e4);
  SplitMix rng(o.seed);
  std::vector<float> height(texels, 0.0f);
  std::vector<int> owner(texels, -1);
  f.strands.reserve(static_cast<size_t>(count));
  for (long k = 0; k < count; ++k) {
    f.strands.push_back(draw_strand(o, rng));
    splat(o, f.strands.back(), static_cast<int>(k), height, owner);
  }
  f.depth.resize(texels);
  f.color.resize(texels);
  const glm::vec3 root = root_color(o.kind);
  for (size_t i = 0; i < texels; ++i) {
    const float h = std::clamp(height[i], 0.0f, 1.0f);
    f.depth[i] = 1.0f - h;
    const glm::vec3 tip = owner[i] >= 0 ? f.strands[static_cast<size_t>(owner[i])].tip : root;
    // Light gathers toward the tip: the gradient is quadratic in height.
    f.color[i] = root + (tip - root) * (h * h);
  }
  return f;
}

Texture fur_depth_texture(const FurField& f) {
  Texture t = Texture::from_floats(TexFormat::kR16, f.size, f.size, f.depth.data());
  t.generate_mips(MipReduce::kAverage);
  return t;
}

Texture fur_color_texture(const FurField& f) {
  std::vector<float> rgba(f.color.size() * 4);
  for (size_t i = 0; i < f.color.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = std::clamp(f.color[i][c], 0.0f, 1.0f);
    rgba[i * 4 + 3] = 1.0f;
  }
  Texture t =
      Texture::from_floats(TexFormat::kRGBA8, f.size, f.size, rgba.data(), ColorSpace::kSRGB);
  t.generate_mips(MipReduce::kAverage);
  return t;
}

Texture fur_normal_texture(const Texture& depth, float depth_scale) {
  return normal_map_from_depth(depth, depth_scale, true);
}

}  // namespace relief
