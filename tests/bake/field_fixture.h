// Test helpers for the technique kernels: a tiny float bilinear depth source that needs no
// rasterizer/texture.cpp (GL's LINEAR magnification rule: x = u * w - 0.5, lerp between texel
// centres, repeat or clamp per axis), procedural fields, and random rays.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "bake/cone_map.h"
#include "rasterizer/texture.h"
#include "shaders_cpp/exact_trace.h"

namespace relief::testing {

struct FloatField {
  int w = 0, h = 0;
  std::vector<float> d;  // row-major depth texels
  Wrap wrap_u = Wrap::kRepeat, wrap_v = Wrap::kRepeat;

  float texel(int i, int j) const { return d[static_cast<size_t>(j) * w + i]; }
  static int wrap(long long i, int n, Wrap m) {
    if (m == Wrap::kClamp) return static_cast<int>(i < 0 ? 0 : (i >= n ? n - 1 : i));
    long long r = i % n;
    return static_cast<int>(r < 0 ? r + n : r);
  }
  // The depth-source interface of shaders_cpp/search.h.
  float operator()(int, float u, float v) const {
    float x = u * static_cast<float>(w) - 0.5f, y = v * static_cast<float>(h) - 0.5f;
    float fx0 = std::floor(x), fy0 = std::floor(y);
    float ax = x - fx0, ay = y - fy0;
    // far outside float's integer range a position is meaningless anyway: keep it finite
    if (!(std::fabs(fx0) < 1e15f) || !(std::fabs(fy0) < 1e15f)) return texel(0, 0);
    long long ix = static_cast<long long>(fx0), iy = static_cast<long long>(fy0);
    int i0 = wrap(ix, w, wrap_u), i1 = wrap(ix + 1, w, wrap_u);
    int j0 = wrap(iy, h, wrap_v), j1 = wrap(iy + 1, h, wrap_v);
    float a = texel(i0, j0), b = texel(i1, j0), c = texel(i0, j1), e = texel(i1, j1);
    float top = a + (b - a) * ax, bot = c + (e - c) * ax;
    return top + (bot - top) * ay;
  }
  HeightField exact() const { return HeightField(w, h, d.data(), wrap_u, wrap_v); }
};

// Depth 1 floor with one-texel walls (depth 0) every `period` texels in both directions, plus
// scattered one-texel pillars: thin features a coarse linear search steps over.
inline FloatField thin_walls(int n, int period, uint32_t seed) {
  FloatField f;
  f.w = f.h = n;
  f.d.assign(static_cast<size_t>(n) * n, 1.0f);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      float v = 0.6f + 0.4f * u01(rng);
      if (i % period == 0 || j % period == 0) v = 0.0f;
      if (u01(rng) < 0.03f) v = 0.1f * u01(rng);
      f.d[static_cast<size_t>(j) * n + i] = v;
    }
  return f;
}

// A smooth periodic field of a few sines, in [0, 1].
inline FloatField smooth_bumps(int n) {
  FloatField f;
  f.w = f.h = n;
  f.d.resize(static_cast<size_t>(n) * n);
  const double k = 2.0 * M_PI / n;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      double v = 0.5 + 0.25 * std::sin(2 * k * i) * std::cos(3 * k * j) +
                 0.2 * std::sin(5 * k * (i + j) + 1.0);
      f.d[static_cast<size_t>(j) * n + i] = static_cast<float>(std::clamp(v, 0.0, 1.0));
    }
  return f;
}

// The three cone maps the cone plugins derive from a level-0 depth map (render/derived_maps.h):
// conservative, quad-directional and relaxed cones, all bilinear-safe; tiling.
struct PluginConeMaps {
  Texture cons, quad, relaxed;
};
inline PluginConeMaps bake_plugin_cone_maps(const Texture& depth) {
  PluginConeMaps maps;
  ConeBakeOptions o;
  o.wrap = true;
  o.bilinear = true;
  o.kind = ConeKind::kConservative;
  maps.cons = bake_cone_map(depth, o);
  o.kind = ConeKind::kQuad;
  maps.quad = bake_cone_map(depth, o);
  o.kind = ConeKind::kRelaxed;
  maps.relaxed = bake_cone_map(depth, o);
  return maps;
}

struct RandomRay {
  float u, v, dsx, dsy, vz;
};

// A random view ray: start uv in [0, 1)^2, direction at polar angle in [0, max_deg] from -N,
// depth_scale in [min_scale, max_scale].
inline RandomRay random_ray(std::mt19937& rng, float max_deg, float min_scale, float max_scale) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  float theta = u01(rng) * max_deg * static_cast<float>(M_PI / 180.0);
  float phi = u01(rng) * 2.0f * static_cast<float>(M_PI);
  float scale = min_scale + (max_scale - min_scale) * u01(rng);
  float s = std::sin(theta);
  float vx = s * std::cos(phi), vy = s * std::sin(phi), vz = -std::cos(theta);
  RandomRay r;
  r.u = u01(rng);
  r.v = u01(rng);
  r.dsx = vx * scale / -vz;
  r.dsy = vy * scale / -vz;
  r.vz = vz;
  return r;
}

}  // namespace relief::testing
