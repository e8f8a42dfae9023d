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
#include "shaders_cpp/sampling.h"
#include "shaders_cpp/uniforms.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace detail {

// std::clamp's comparisons over the lanes: v < lo ? lo : (hi < v ? hi : v).
template <class F>
inline F std_clamp(const F& v, const F& lo, const F& hi) {
  return select(v < lo, lo, select(hi < v, hi, v));
}
// Row k of glm's mat4 * vec4(x, y, z, w): (m0 x + m1 y) + (m2 z + m3 w), as glm sums it.
template <class F>
inline F mat4_row(const glm::mat4& a, int k, const F& x, const F& y, const F& z, const F& w) {
  return (F(a[0][k]) * x + F(a[1][k]) * y) + (F(a[2][k]) * z + F(a[3][k]) * w);
}
// Row k of glm's mat3(a) * vec3(x, y, z), summed left to right.
template <class F>
inline F mat3_row(const glm::mat4& a, int k, const F& x, const F& y, const F& z) {
  return F(a[0][k]) * x + F(a[1][k]) * y + F(a[2][k]) * z;
}

// shadow_lookup (above) of every lane on face f at once: the same IEEE operations per lane in the
// same order, so the same bits as one lane at a time; the taps' depths are gathered. Lanes
// outside `active` get 1 and fetch nothing, as do the lanes shadow_lookup leaves lit before its
// taps (nearer than the near plane, outside the map).
template <class F>
F shadow_lookup_lanes(const ShadowMapView& m, int f, const V3<F>& p, const V3<F>& n, const V3<F>& l,
                      mask_t<F> active, F& fetches) {
  using I = int_t<F>;
  const F one(1.0f), zero(0.0f), half(0.5f);
  const glm::mat4& v = m.view[f];
  const F qx = mat4_row(v, 0, p.x, p.y, p.z, one), qy = mat4_row(v, 1, p.x, p.y, p.z, one);
  const F qz = mat4_row(v, 2, p.x, p.y, p.z, one), qw = mat4_row(v, 3, p.x, p.y, p.z, one);
  const F dist = -qz;
  const glm::mat4& pr = m.proj[f];
  const F cx = mat4_row(pr, 0, qx, qy, qz, qw), cy = mat4_row(pr, 1, qx, qy, qz, qw);
  const F cw = mat4_row(pr, 3, qx, qy, qz, qw);
  const F size(static_cast<float>(m.size));
  const F px = (cx / cw * half + half) * size, py = (half - cy / cw * half) * size;
  const mask_t<F> in =
      active & (dist > F(m.znear)) & (px >= zero) & (px <= size) & (py >= zero) & (py <= size);
  if (none(in)) return one;
  const F nex = mat3_row(v, 0, n.x, n.y, n.z), ney = mat3_row(v, 1, n.x, n.y, n.z);
  const F nez = mat3_row(v, 2, n.x, n.y, n.z);
  const F cos_t = std_clamp(n.x * l.x + n.y * l.y + n.z * l.z, zero, one);
  const F tan_t = vmin(vsqrt(one - cos_t * cos_t) / vmax(cos_t, F(1e-6f)), F(kMaxShadowSlope));
  const F texel_w = m.orthographic ? F(m.texel) : F(m.texel) * dist;
  const F bias = texel_w * (F(m.settings.depth_bias) + F(m.settings.slope_bias) * tan_t);
  const F plane = nex * qx + ney * qy + nez * qz;
  const int r = m.settings.pcf_radius;
  // lanes left lit read the taps of the first lane in the map (tiles it makes drawn below; a
  // texel of a tile not drawn may be being written by another thread) and do not use them
  int first = 0;
  while (!lane(in, first)) ++first;
  const F bx = select(in, px, F(lane(px, first))) - half;
  const F by = select(in, py, F(lane(py, first))) - half;
  const F x0f = vfloor(bx), y0f = vfloor(by);
  const F fx = bx - x0f, fy = by - y0f;
  const I x0 = trunc_to_int(x0f), y0 = trunc_to_int(y0f);
  if (m.tiles) {
    const int last = m.size - 1;
    for (int k = 0; k < lane_width<F>; ++k)
      if (lane(in, k)) {
        const int x = lane(x0, k), y = lane(y0, k);
        m.tiles->need(f, std::clamp(x - r, 0, last), std::clamp(y - r, 0, last),
                      std::clamp(x + r + 1, 0, last), std::clamp(y + r + 1, 0, last));
      }
  }
  // shadow_distance of the gathered depths
  const float za = m.znear / (m.zfar - m.znear), zb = m.znear * m.zfar / (m.zfar - m.znear);
  const float zspan = m.zfar - m.znear;
  const float* depth = m.depth[f];
  const I last(m.size - 1), row_size(m.size);
  F lit = zero, total = zero;
  for (int j = -r; j <= r + 1; ++j) {
    const F wy = j == -r ? one - fy : (j == r + 1 ? fy : one);
    const I yj = y0 + I(j);
    const I row = vmin(vmax(yj, I(0)), last) * row_size;
    const F ny = one - F(2.0f) * (to_float(yj) + half) / size;
    for (int i = -r; i <= r + 1; ++i) {
      const F wx = i == -r ? one - fx : (i == r + 1 ? fx : one);
      const I xi = x0 + I(i);
      const I tx = vmin(vmax(xi, I(0)), last);
      const F nx = F(2.0f) * (to_float(xi) + half) / size - one;
      F d;
      if (m.orthographic) {
        const F ex = (nx - F(pr[3][0])) / F(pr[0][0]), ey = (ny - F(pr[3][1])) / F(pr[1][1]);
        d = dist + (nex * (ex - qx) + ney * (ey - qy)) / nez;
      } else {
        const F ex = nx / F(pr[0][0]), ey = ny / F(pr[1][1]);
        d = plane / (nex * ex + ney * ey - nez);
      }
      const F reach =
          texel_w * F(kMaxShadowSlope) * F(static_cast<float>(std::abs(i) + std::abs(j) + 1));
      d = select(d == d, std_clamp(d, dist - reach, dist + reach), dist);
      const F w = wx * wy;
      total += w;
      const F texel = gather_f32<F>(depth, row + tx);
      const F stored = m.orthographic ? F(m.zfar) - texel * F(zspan) : F(zb) / (texel + F(za));
      lit = select(d - bias <= stored, lit + w, lit);
    }
  }
  fetches += select(in, F(static_cast<float>((2 * r + 2) * (2 * r + 2))), zero);
  return select(in, lit / total, one);
}

}  // namespace detail

// Shadow-map visibility in [0, 1] per lane of the points p (world), unit normals n and unit
// directions to the light l; lanes outside `active` get 1 and fetch nothing. The taps are added
// to `fetches` per lane. Over lanes, the lanes on one face of the map are looked up together
// (shadow_lookup_lanes); lanes of a cube on several faces, and float, one at a time.
template <class F>
inline F shadow_map_visibility(const ShadowMapView& m, const V3<F>& p, const V3<F>& n,
                               const V3<F>& l, mask_t<F> active, F& fetches) {
  if constexpr (is_lanes_v<F>) {
    int face = 0;
    bool one_face = true;
    if (m.faces == kMaxShadowFaces) {
      face = -1;
      for (int k = 0; k < lane_width<F> && one_face; ++k) {
        if (!lane(active, k)) continue;
        const int fk = relief::detail::cube_face(
            glm::vec3(lane(p.x, k), lane(p.y, k), lane(p.z, k)) - m.position);
        one_face = face < 0 || fk == face;
        face = fk;
      }
    }
    if (face < 0) return F(1.0f);  // no lane active
    if (one_face) return detail::shadow_lookup_lanes(m, face, p, n, l, active, fetches);
  }
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
