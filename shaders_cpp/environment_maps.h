// An environment light as data (image-based lighting, docs/environment.md): diffuse irradiance
// as spherical harmonics and prefiltered specular radiance with a split-sum BRDF table, made by
// bake/environment_bake.h and read by shaders_cpp/environment.h.
//
// Conventions:
//   Equirectangular input: +Y is up; image row 0 (the top) looks along +Y, the bottom row along
//   -Y; the centre column (u = 0.5) looks along -Z and u grows toward +X (u = 0.75 looks along
//   +X, u = 0 and 1 along +Z). With theta the angle from +Y and phi = 2 pi (u - 0.5):
//   d = (sin theta sin phi, cos theta, -sin theta cos phi), v = theta / pi.
//   Octahedral layout of `specular` (Cigolle et al. 2014, "A Survey of Efficient Representations
//   for Independent Unit Vectors", with +Y as the pole): p = (d.x, d.z) / (|d.x| + |d.y| + |d.z|);
//   for d.y < 0, p = ((1 - |p.y|) sign(p.x), (1 - |p.x|) sign(p.y)) with sign(0) = +1; uv = p / 2
//   + 1/2. The upper hemisphere is the central diamond, u grows toward +X and v toward +Z
//   (texel row 0 is the -Z edge).
//   Specular level k of N holds the GGX-prefiltered radiance (N = V = R) at perceptual roughness
//   k / (N - 1): a shader reads it at lod = roughness * (N - 1), trilinear, clamp to edge.
//   sh: 9 real SH coefficients (bands 0-2, order (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1),
//   (2,0), (2,1), (2,2), basis on (x, y, z) as in shaders_cpp/environment.h) of the radiance,
//   convolved with the clamped cosine (Ramamoorthi & Hanrahan 2001: A0 = pi, A1 = 2 pi / 3,
//   A2 = pi / 4) and divided by pi: their sum at a unit normal n is E(n) / pi, the radiance of a
//   constant environment.
//   brdf_lut: texel (i, j) of the size x size table holds (A, B) in (r, g) at NdotV = (i + 0.5) /
//   size, roughness = (j + 0.5) / size; read bilinearly, clamped, at uv = (NdotV, roughness).
#pragma once

#include <array>
#include <cmath>

#include <glm/vec3.hpp>

#include "rasterizer/texture.h"

namespace relief {

inline constexpr int kEnvShCount = 9;
// The bake refuses an equirectangular environment larger than this (8192 x 4096, the largest
// common HDRI size): it reads every texel, and its source mips add a third to the memory.
// scene/image_io.h's kMaxEnvironmentTexels, for files, is the same (render/derived_maps.cpp
// checks).
inline constexpr long long kMaxEnvironmentBakeTexels = 8192LL * 4096;

struct EnvironmentMaps {
  std::array<glm::vec3, kEnvShCount> sh{};
  Texture specular;  // RGBA16F octahedral, levels of roughness k / (levels - 1)
  Texture brdf_lut;  // RGBA16F, (A, B, 0, 1)
  // The same texels, one R32F texture a channel (specular r, g, b; LUT A, B), for the CPU
  // kernels: R32F is on the lane-parallel sampler (shaders_cpp/sampling.h) and RGBA16F is not.
  // The halves convert to float exactly and filtering is per channel, so a read of the planes
  // gives the bits of a read of the RGBA16F texture. Made by split_channels.
  std::array<Texture, 3> specular_planes;
  std::array<Texture, 2> brdf_planes;
  // What the bake changed: input texels that were NaN, infinite or negative (set to 0), and
  // specular values above the largest half float (65504, stored as 65504).
  long long replaced_texels = 0;
  long long clipped_values = 0;
};

// Fills specular_planes and brdf_planes from specular and brdf_lut (bake_environment calls it).
void split_channels(EnvironmentMaps& maps);

// Where a shader looks the environment up and how bright it is: the environment turned by
// `degrees` about +Y (right-handed: +X toward -Z for positive angles) and scaled by intensity.
struct EnvironmentView {
  float cos_rotation = 1.0f;
  float sin_rotation = 0.0f;
  float intensity = 1.0f;
};
inline EnvironmentView environment_view(float degrees, float intensity) {
  const double r = static_cast<double>(degrees) * (3.14159265358979323846 / 180.0);
  return {static_cast<float>(std::cos(r)), static_cast<float>(std::sin(r)), intensity};
}

}  // namespace relief
