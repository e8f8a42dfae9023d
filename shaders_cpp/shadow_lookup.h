// Shadow-map lookups over the lane type F (float or F8): Williams, "Casting Curved Shadows on
// Curved Surfaces", SIGGRAPH 1978 (depth from the light, then a depth comparison per receiver);
// percentage-closer filtering after Reeves, Salesin and Cook, "Rendering Antialiased Shadows with
// Depth Maps", SIGGRAPH 1987 (filter the comparisons, not the depths), with bilinear tap weights;
// the receiver's depth at each tap follows its tangent plane (receiver-plane depth), plus a
// constant and a slope-scaled bias.
//
// Conventions: a map face is size x size float reversed-Z depths (1 at the light's near plane, 0 at
// its far plane or where nothing was drawn), row 0 at the top (clip y = +1), texel (i, j) centred
// at pixel coordinates (i + 0.5, j + 0.5) as the rasterizer samples. Comparisons are made in linear
// distance from the light along its view axis (world units). A point light's cube has six faces
// in the order +x, -x, +y, -y, +z, -z, each a 90 degree perspective view.

#ifndef RELIEF_SHADERS_CPP_SHADOW_MAP_H_ONCE
#define RELIEF_SHADERS_CPP_SHADOW_MAP_H_ONCE
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include "shaders_cpp/uniforms.h"

namespace relief {

// Filtering and bias, the same for every light of a frame (RenderOptions::shadow).
struct ShadowSettings {
  // Constant bias, in texels: world size of one shadow-map texel at the receiver.
  float depth_bias = 1.0f;
  // Slope-scaled bias, in texels per unit of tan(angle between the normal and the light),
  // tan clamped to kMaxShadowSlope.
  float slope_bias = 1.0f;
  // Percentage-closer filter radius r: (2r + 2)^2 taps with bilinear weights; 0 = one bilinear
  // 2x2 comparison.
  int pcf_radius = 1;
};
inline constexpr float kMaxShadowSlope = 10.0f;
inline constexpr int kMaxShadowFaces = 6;
inline constexpr int kMaxPcfRadius = 4;

// A shadow map drawn on demand (the CPU backend, docs/effects.md "Shadow maps drawn on demand"):
// each face is cut into square tiles, and a tile is drawn the first time a lookup's taps reach
// it. A texel's depth depends only on the casters' fragments at that texel, so every texel read
// holds what a whole map would hold there, and tiles no lookup reaches are never drawn.
struct ShadowTiles {
  int shift = 0;    // a tile is 2^shift texels per side
  int per_row = 0;  // tiles per row and per column of a face
  // Per face, per tile (row by row): 1 once the tile is drawn (release by the drawer).
  const std::atomic<uint8_t>* drawn[kMaxShadowFaces] = {};
  // Draws tile `t` of `face` unless it is drawn, and returns once it is: from any thread, at
  // most once a tile (a second caller waits for the first).
  void (*draw)(const void* owner, int face, int t) = nullptr;
  const void* owner = nullptr;

  // Makes the texels [x0, x1] x [y0, y1] of `face` (inside the map) drawn.
  void need(int face, int x0, int y0, int x1, int y1) const {
    const std::atomic<uint8_t>* d = drawn[face];
    const int tx0 = x0 >> shift, tx1 = x1 >> shift, ty1 = y1 >> shift;
    for (int ty = y0 >> shift; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        const int t = ty * per_row + tx;
        if (d[t].load(std::memory_order_acquire) != 1) draw(owner, face, t);
      }
  }
};

// One light's depth map as the receivers see it (LightUniform::shadow).
struct ShadowMapView {
  int size = 0;                     // texels per side
  int faces = 0;                    // 1, or 6 for a point light's cube
  bool orthographic = false;        // directional lights
  glm::vec3 position{0.0f};         // the light (perspective faces)
  glm::mat4 view[kMaxShadowFaces];  // world -> light eye space (looking down -z)
  glm::mat4 proj[kMaxShadowFaces];  // eye -> clip, reversed-Z
  const float* depth[kMaxShadowFaces] = {};
  float znear = 0.0f, zfar = 0.0f;
  // World size of one texel: orthographic, everywhere; perspective, at distance 1 from the light.
  float texel = 0.0f;
  ShadowSettings settings;
  // Null when every texel is drawn; else lookups make the tiles their taps reach drawn first.
  const ShadowTiles* tiles = nullptr;
};

namespace detail {

inline int cube_face(glm::vec3 d) {
  const glm::vec3 a(std::fabs(d.x), std::fabs(d.y), std::fabs(d.z));
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0f ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0f ? 2 : 3;
  return d.z >= 0.0f ? 4 : 5;
}

// Distance from the light along its axis of a stored reversed-Z depth.
inline float shadow_distance(const ShadowMapView& m, float depth) {
  if (m.orthographic) return m.zfar - depth * (m.zfar - m.znear);
  const float a = m.znear / (m.zfar - m.znear), b = m.znear * m.zfar / (m.zfar - m.znear);
  return b / (depth + a);
}

// Fraction of the light reaching world point p with unit normal n, l the unit direction to the
// light; adds the taps to `fetches`. Points outside the map or nearer than its near plane are lit.
inline float shadow_lookup(const ShadowMapView& m, glm::vec3 p, glm::vec3 n, glm::vec3 l,
                           float& fetches) {
  const int f = m.faces == kMaxShadowFaces ? cube_face(p - m.position) : 0;
  const glm::vec4 q = m.view[f] * glm::vec4(p, 1.0f);
  const float dist = -q.z;
  if (!(dist > m.znear)) return 1.0f;
  const glm::mat4& pr = m.proj[f];
  const glm::vec4 c = pr * q;
  const float size = static_cast<float>(m.size);
  const float px = (c.x / c.w * 0.5f + 0.5f) * size, py = (0.5f - c.y / c.w * 0.5f) * size;
  if (!(px >= 0.0f && px <= size && py >= 0.0f && py <= size)) return 1.0f;
  const glm::vec3 ne = glm::mat3(m.view[f]) * n;
  const float cos_t = std::clamp(n.x * l.x + n.y * l.y + n.z * l.z, 0.0f, 1.0f);
  const float tan_t =
      std::min(std::sqrt(1.0f - cos_t * cos_t) / std::max(cos_t, 1e-6f), kMaxShadowSlope);
  const float texel_w = m.orthographic ? m.texel : m.texel * dist;
  const float bias = texel_w * (m.settings.depth_bias + m.settings.slope_bias * tan_t);
  const float plane = ne.x * q.x + ne.y * q.y + ne.z * q.z;  // perspective: n . q
  const int r = m.settings.pcf_radius;
  const float bx = px - 0.5f, by = py - 0.5f;
  const float x0f = std::floor(bx), y0f = std::floor(by);
  const float fx = bx - x0f, fy = by - y0f;
  const int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
  if (m.tiles) {
    const int last = m.size - 1;
    m.tiles->need(f, std::clamp(x0 - r, 0, last), std::clamp(y0 - r, 0, last),
                  std::clamp(x0 + r + 1, 0, last), std::clamp(y0 + r + 1, 0, last));
  }
  const float* depth = m.depth[f];
  float lit = 0.0f, total = 0.0f;
  for (int j = -r; j <= r + 1; ++j) {
    const float wy = j == -r ? 1.0f - fy : (j == r + 1 ? fy : 1.0f);
    const int ty = std::clamp(y0 + j, 0, m.size - 1);
    const float ny = 1.0f - 2.0f * (static_cast<float>(y0 + j) + 0.5f) / size;
    for (int i = -r; i <= r + 1; ++i) {
      const float wx = i == -r ? 1.0f - fx : (i == r + 1 ? fx : 1.0f);
      const int tx = std::clamp(x0 + i, 0, m.size - 1);
      const float nx = 2.0f * (static_cast<float>(x0 + i) + 0.5f) / size - 1.0f;
      // the receiver's tangent plane under the tap's texel centre
      float d;
      if (m.orthographic) {
        const float ex = (nx - pr[3][0]) / pr[0][0], ey = (ny - pr[3][1]) / pr[1][1];
        d = dist + (ne.x * (ex - q.x) + ne.y * (ey - q.y)) / ne.z;
      } else {
        const float ex = nx / pr[0][0], ey = ny / pr[1][1];
        d = plane / (ne.x * ex + ne.y * ey - ne.z);
      }
      const float reach =
          texel_w * kMaxShadowSlope * static_cast<float>(std::abs(i) + std::abs(j) + 1);
      d = d == d ? std::clamp(d, dist - reach, dist + reach) : dist;
      const float w = wx * wy;
      total += w;
      if (d - bias <= shadow_distance(m, depth[static_cast<size_t>(ty) * m.size + tx])) lit += w;
    }
  }
  fetches += static_cast<float>((2 * r + 2) * (2 * r + 2));
  return lit / total;
}

}  // namespace detail

}  // namespace relief
#endif  // RELIEF_SHADERS_CPP_SHADOW_MAP_H_ONCE

#if defined(RELIEF_SHADERS_CPP_SHADOW_MAP_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_SHADOW_MAP_H_
#undef RELIEF_SHADERS_CPP_SHADOW_MAP_H_
#else
#define RELIEF_SHADERS_CPP_SHADOW_MAP_H_
#endif

#include <algorithm>
#include <cmath>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "shaders_cpp/lanes.h"
#include "shaders_cpp/uniforms.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
// Shadow-map visibility in [0, 1] per lane of the points p (world), unit normals n and unit
// directions to the light l; lanes outside `active` get 1 and fetch nothing. The taps are added
// to `fetches` per lane.
template <class F>
inline F shadow_map_visibility(const ShadowMapView& m, const V3<F>& p, const V3<F>& n,
                               const V3<F>& l, mask_t<F> active, F& fetches) {
  F taps(0.0f);
  const F vis = per_lane(F(0.0f), [&](int i) {
    if (!lane(active, i)) return 1.0f;
    float t = 0.0f;
    const float v =
        relief::detail::shadow_lookup(m, glm::vec3(lane(p.x, i), lane(p.y, i), lane(p.z, i)),
                                      glm::vec3(lane(n.x, i), lane(n.y, i), lane(n.z, i)),
                                      glm::vec3(lane(l.x, i), lane(l.y, i), lane(l.z, i)), t);
    set_lane(taps, i, t);
    return v;
  });
  fetches += taps;
  return vis;
}

// The visibility callback of blinn_phong (shaders_cpp/lighting.h) for kernels whose only
// visibility is the shadow maps: light i's map, if it has one, at point p with normal n (the
// geometric normal for surfaces that do not move the point); taps are added to `fetches`.
template <class F>
struct ShadowMapReceiver {
  const FrameUniforms& frame;
  V3<F> p, n;
  F& fetches;
  F operator()(int i, V3<F> l, mask_t<F> lit) const {
    const ShadowMapView* sm = frame.lights[i].shadow;
    return sm ? shadow_map_visibility(*sm, p, n, l, lit, fetches) : F(1.0f);
  }
};

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_SHADOW_MAP_H_
