#include "rasterizer/tone_map.h"

#include <algorithm>

namespace relief {
namespace {

// Finite and non-negative: NaN and v <= 0 read as 0, v above kToneMapMaxInput as that.
float sane(float v) {
  return v > 0.0f ? std::min(v, kToneMapMaxInput) : 0.0f;
}
glm::vec3 sane(glm::vec3 c) {
  return {sane(c.r), sane(c.g), sane(c.b)};
}

// Hill's rational fit of the RRT + ODT, one channel.
float rrt_odt_fit(float v) {
  const float a = v * (v + 0.0245786f) - 0.000090537f;
  const float b = v * (0.983729f * v + 0.4329510f) + 0.238081f;
  return a / b;
}

float clamp01(float v) {
  return std::clamp(v, 0.0f, 1.0f);
}

}  // namespace

bool parse_tone_curve(const std::string& name, ToneCurve& curve) {
  for (ToneCurve c : {ToneCurve::kNone, ToneCurve::kAcesHill, ToneCurve::kPbrNeutral})
    if (name == tone_curve_name(c)) {
      curve = c;
      return true;
    }
  return false;
}

const char* tone_curve_name(ToneCurve curve) {
  switch (curve) {
    case ToneCurve::kAcesHill:
      return "aces";
    case ToneCurve::kPbrNeutral:
      return "pbr-neutral";
    case ToneCurve::kNone:
      break;
  }
  return "none";
}

glm::vec3 tone_map_clamp(glm::vec3 c) {
  c = sane(c);
  return {clamp01(c.r), clamp01(c.g), clamp01(c.b)};
}

glm::vec3 tone_map_aces_hill(glm::vec3 c) {
  c = sane(c);
  // sRGB -> XYZ -> D65 to D60 -> AP1 -> RRT saturation (rows of the viewer's ACESInputMat, a
  // column-major GLSL mat3).
  const float r = 0.59719f * c.r + 0.35458f * c.g + 0.04823f * c.b;
  const float g = 0.07600f * c.r + 0.90834f * c.g + 0.01566f * c.b;
  const float b = 0.02840f * c.r + 0.13383f * c.g + 0.83777f * c.b;
  const float fr = rrt_odt_fit(r), fg = rrt_odt_fit(g), fb = rrt_odt_fit(b);
  // ODT saturation -> XYZ -> D60 to D65 -> sRGB (ACESOutputMat).
  return {clamp01(1.60475f * fr - 0.53108f * fg - 0.07367f * fb),
          clamp01(-0.10208f * fr + 1.10813f * fg - 0.00605f * fb),
          clamp01(-0.00327f * fr - 0.07276f * fg + 1.07602f * fb)};
}

glm::vec3 tone_map_pbr_neutral(glm::vec3 c) {
  c = sane(c);
  constexpr float kStartCompression = 0.8f - 0.04f;
  constexpr float kDesaturation = 0.15f;
  const float x = std::min(c.r, std::min(c.g, c.b));
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  c -= offset;
  const float peak = std::max(c.r, std::max(c.g, c.b));
  if (peak < kStartCompression) return c;
  constexpr float d = 1.0f - kStartCompression;
  const float new_peak = 1.0f - d * d / (peak + d - kStartCompression);
  c *= new_peak / peak;
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - new_peak) + 1.0f);
  // mix(c, new_peak, g) as GLSL defines it: c * (1 - g) + new_peak * g.
  return c * (1.0f - g) + glm::vec3(new_peak * g);
}

glm::vec3 tone_map(ToneCurve curve, glm::vec3 c) {
  switch (curve) {
    case ToneCurve::kAcesHill:
      return tone_map_aces_hill(c);
    case ToneCurve::kPbrNeutral:
      return tone_map_pbr_neutral(c);
    case ToneCurve::kNone:
      break;
  }
  return tone_map_clamp(c);
}

void apply_tone_curve(Image& image, ToneCurve curve) {
  if (curve == ToneCurve::kNone) return;
  for (glm::vec4& p : image.pixels) {
    const glm::vec3 premultiplied(p);
    if (p.a > 0.0f && p.a < 1.0f) {
      p = glm::vec4(tone_map(curve, premultiplied / p.a) * p.a, p.a);
    } else {
      p = glm::vec4(tone_map(curve, premultiplied), p.a);
    }
  }
}

}  // namespace relief
