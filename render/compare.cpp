#include "render/compare.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

#include "base/check.h"

namespace relief {
namespace {

float to_space(float v, DiffSpace space) {
  if (space == DiffSpace::kLinear) return v;
  if (!std::isfinite(v)) return v;
  v = std::clamp(v, 0.0f, 1.0f);
  return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

// Largest channel error of one pixel; non-finite -> +infinity.
float pixel_error(const glm::vec4& a, const glm::vec4& b, DiffSpace space, double* sq_sum) {
  float worst = 0.0f;
  for (int c = 0; c < 3; ++c) {
    const float x = to_space(a[c], space), y = to_space(b[c], space);
    float e = std::fabs(x - y);
    if (!std::isfinite(e)) e = std::numeric_limits<float>::infinity();
    if (sq_sum) *sq_sum += static_cast<double>(e) * e;
    worst = std::max(worst, e);
  }
  return worst;
}

void check_sizes(const Image& a, const Image& b) {
  CHECK_EQ(a.width, b.width);
  CHECK_EQ(a.height, b.height);
  CHECK(a.width > 0 && a.height > 0);
}

}  // namespace

ImageDiff compare_images(const Image& a, const Image& b, float threshold, DiffSpace space) {
  check_sizes(a, b);
  ImageDiff d;
  d.width = a.width;
  d.height = a.height;
  d.threshold = threshold;
  double sq = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const float e = pixel_error(a.at(x, y), b.at(x, y), space, &sq);
      if (e > d.max_error) {
        d.max_error = e;
        d.max_x = x;
        d.max_y = y;
      }
      if (e > threshold) ++d.over_count;
    }
  const double n = static_cast<double>(a.width) * a.height;
  const double mse = sq / (3.0 * n);
  d.rmse = std::sqrt(mse);
  d.psnr_db = mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : std::numeric_limits<double>::infinity();
  d.over_fraction = static_cast<double>(d.over_count) / n;
  return d;
}

Image diff_heatmap(const Image& a, const Image& b, float threshold, DiffSpace space) {
  check_sizes(a, b);
  Image out(a.width, a.height, glm::vec4(0, 0, 0, 1));
  const float t = threshold > 0.0f ? threshold : 1.0f / 255.0f;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) {
      const float e = pixel_error(a.at(x, y), b.at(x, y), space, nullptr) / t;
      glm::vec3 c;
      if (e <= 0.0f)
        c = glm::vec3(0.0f);
      else if (e < 0.5f)
        c = glm::vec3(0.0f, 0.0f, 0.25f + 1.5f * e);  // dark to full blue
      else if (e <= 1.0f)
        c = glm::vec3(0.0f, 2.0f * (e - 0.5f), 1.0f - 2.0f * (e - 0.5f));  // blue to green
      else
        c = glm::vec3(1.0f, std::clamp(1.0f - (e - 1.0f) / 3.0f, 0.0f, 1.0f),
                      0.0f);  // yellow to red
      out.at(x, y) = glm::vec4(c, 1.0f);
    }
  return out;
}

}  // namespace relief
