// Tone curves: the display transform of `relief render --tonemap` (docs/effects.md, "Output
// transform"), applied to linear colour after --exposure and before the 8-bit sRGB encoding.
// Float outputs (EXR) stay linear and never see a curve.
//
// Every curve is a scalar function of one pixel in float arithmetic (the build contracts no
// multiply-adds, -ffp-contract=off), so an image maps to the same bits whatever the thread count.
// Inputs are first made finite and non-negative: NaN and negative channels read as 0, channels
// above kToneMapMaxInput as kToneMapMaxInput (the curves' quadratics stay finite).
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "rasterizer/image.h"

namespace relief {

enum class ToneCurve {
  kNone,        // clamp to [0, 1]: the look of relief before tone curves
  kAcesHill,    // "ACES Filmic Tone Mapping (Hill)" of the Khronos glTF Sample Viewer
  kPbrNeutral,  // the Khronos PBR Neutral tone mapper
};

inline constexpr float kToneMapMaxInput = 65504.0f;  // the largest half float

// "none" | "aces" | "pbr-neutral": the curve; false for anything else.
bool parse_tone_curve(const std::string& name, ToneCurve& curve);
// The name parse_tone_curve reads.
const char* tone_curve_name(ToneCurve curve);

// kNone: each channel clamped to [0, 1].
glm::vec3 tone_map_clamp(glm::vec3 c);
// Stephen Hill's fit of the ACES sRGB RRT + ODT (github.com/TheRealMJP/BakingLab, ACES.hlsl) as
// the glTF Sample Viewer's toneMapACES_Hill (source/Renderer/shaders/tonemapping.glsl): the
// input matrix (sRGB -> AP1 with the RRT's saturation), the rational fit per channel
//   f(v) = (v (v + 0.0245786) - 0.000090537) / (v (0.983729 v + 0.4329510) + 0.238081),
// the output matrix (ODT saturation -> sRGB), clamped to [0, 1]. Both matrices keep grey grey;
// f rises to 1 / 0.983729 = 1.0165 and passes 1 at v = 25.67, so grey above that clips to 1.
// The viewer's "Hill - Exposure Boost" variant divides by 0.6 first: --exposure 0.737 (log2 of
// 1 / 0.6) in front of this curve.
glm::vec3 tone_map_aces_hill(glm::vec3 c);
// The Khronos PBR Neutral tone mapper (github.com/KhronosGroup/ToneMapping, PBR_Neutral): with
// x = min(r, g, b), subtract x - 6.25 x^2 when x < 0.08, else 0.04 (a toe that meets the constant
// at x = 0.08); a colour whose peak p = max(r, g, b) is then below startCompression = 0.76 is
// done. Above it, the colour is scaled to the new peak 1 - d^2 / (p + d - 0.76), d = 0.24, and
// mixed towards grey of that peak by 1 - 1 / (0.15 (p - new peak) + 1) (desaturation 0.15).
// Hue (HSV) is kept exactly; output is in [0, 1).
glm::vec3 tone_map_pbr_neutral(glm::vec3 c);
// The curve's scalar function (kNone: tone_map_clamp).
glm::vec3 tone_map(ToneCurve curve, glm::vec3 c);

// Maps an image of linear premultiplied colour: the colour of a pixel with 0 < alpha < 1 is
// divided by alpha, mapped and multiplied by alpha again (coverage scales the displayed colour,
// it is not a darker colour); a pixel with alpha 0 (light with no coverage) or >= 1 maps as it is.
// kNone leaves the image untouched: the 8-bit encoder clamps the premultiplied colour, as it
// always did.
void apply_tone_curve(Image& image, ToneCurve curve);

}  // namespace relief
