// The bake of an environment light (docs/environment.md): from an equirectangular linear RGB
// image to shaders_cpp/environment_maps.h's EnvironmentMaps, whose conventions it follows.
//   - sh: the radiance projected on SH bands 0-2 over every texel, each weighted by its exact
//     solid angle (2 pi / W)(cos theta0 - cos theta1), then convolved with the clamped cosine
//     and divided by pi (Ramamoorthi & Hanrahan 2001).
//   - specular: level k (roughness k / (levels - 1), alpha = roughness^2) is the GGX-weighted
//     average of the radiance with N = V = R (Karis 2013, "Real Shading in Unreal Engine 4"):
//     `specular_samples` Hammersley half vectors, each L weighted by NdotL, read from the
//     source's mips at the level whose texel matches the sample's solid angle 1 / (samples *
//     pdf), pdf = D / 4, plus one (filtered importance sampling, Colbert & Krivanek 2007, GPU
//     Gems 3 ch. 20), and never finer than the output texel. Level 0 (roughness 0, a mirror) is
//     one read along R at the output texel's footprint.
//   - brdf_lut: Karis's split-sum terms with the glTF 2.0 BRDF (appendix B: GGX D, Smith
//     height-correlated V, Schlick F): A = mean of (1 - Fc) w, B = mean of Fc w, Fc = (1 -
//     VdotH)^5, w = 4 V NdotL VdotH / NdotH, over `lut_samples` GGX Hammersley samples.
// Every result is the same bytes for every thread count.
#pragma once

#include <array>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "base/status.h"
#include "rasterizer/image.h"
#include "shaders_cpp/environment_maps.h"

namespace relief {

struct EnvironmentBakeOptions {
  int specular_size = 256;     // level 0 side, a power of two >= 2^(levels - 1)
  int specular_levels = 5;     // 256 .. 16: roughness 0, 0.25, 0.5, 0.75, 1
  int specular_samples = 256;  // GGX samples per texel of levels >= 1
  int lut_size = 64;
  int lut_samples = 1024;
  int threads = 0;  // 0: every core
};

// Bakes the maps of `equirect` (linear RGB; alpha ignored). Texels that are NaN, infinite or
// negative read as 0 (counted in replaced_texels). Error: an empty image, more than
// kMaxEnvironmentBakeTexels texels, or options out of range.
Result<EnvironmentMaps> bake_environment(const Image& equirect,
                                         const EnvironmentBakeOptions& options = {});

// The pieces of the bake, for tests and tools. environment_sh: the sh of an image whose texels
// are all finite and non-negative.
std::array<glm::vec3, kEnvShCount> environment_sh(const Image& equirect, int threads = 0);
// (A, B) at one NdotV and perceptual roughness, from `samples` GGX samples.
glm::vec2 integrate_split_sum(float ndotv, float roughness, int samples);
// The glTF 2.0 height-correlated Smith visibility V at alpha^2 = a2 (appendix B).
double smith_visibility(double ndotl, double ndotv, double a2);

// The unit direction at equirect uv, and the uv of a direction (environment_maps.h).
glm::vec3 equirect_direction(double u, double v);
glm::vec2 equirect_uv(glm::vec3 d);

// A neutral studio environment, linear RGB, width x height (2:1 expected): a grey gradient
// brighter overhead, a darker floor, a large soft key panel (upper front right) and a dimmer fill
// panel (left); R = G = B everywhere, mean radiance over the sphere about 0.8.
Image studio_environment(int width, int height);

}  // namespace relief
