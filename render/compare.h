// Image comparison: the metric behind `relief compare`, the CPU-vs-GL tests and `relief bench`.
//
// Both images are compared channel by channel over R, G and B (alpha is ignored), after mapping
// each value into the comparison space: kSrgb (default) clamps to [0, 1] and applies the sRGB
// transfer function, so errors are in the units of an 8-bit display image (8/255 is eight code
// values); kLinear compares the raw linear values as they are (no clamp). Non-finite values count
// as the largest possible error.
//   rmse           sqrt(mean over pixels and channels of (a - b)^2)
//   psnr_db        10 log10(1 / mse) (peak 1); +infinity when the images are equal
//   max_error      largest |a - b| over pixels and channels, at (max_x, max_y)
//   over_fraction  pixels whose largest channel error exceeds `threshold`, over all pixels
#pragma once

#include <cstddef>

#include "rasterizer/image.h"

namespace relief {

enum class DiffSpace { kSrgb, kLinear };

struct ImageDiff {
  int width = 0;
  int height = 0;
  double rmse = 0.0;
  double psnr_db = 0.0;
  double max_error = 0.0;
  int max_x = 0;
  int max_y = 0;
  float threshold = 0.0f;
  size_t over_count = 0;
  double over_fraction = 0.0;
};

// Contract: a and b have the same, non-zero size (CHECKed; callers report mismatches as input
// errors first).
ImageDiff compare_images(const Image& a, const Image& b, float threshold = 8.0f / 255.0f,
                         DiffSpace space = DiffSpace::kSrgb);

// Per-pixel largest channel error as a colour ramp (linear RGB, alpha 1): black at 0, blue below
// half the threshold, green up to the threshold, then yellow to red at 4x the threshold and above.
// Same contract as compare_images.
Image diff_heatmap(const Image& a, const Image& b, float threshold = 8.0f / 255.0f,
                   DiffSpace space = DiffSpace::kSrgb);

}  // namespace relief
