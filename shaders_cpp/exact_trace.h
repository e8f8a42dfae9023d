// The exact reference: first intersection of a texture-space ray with the bilinearly reconstructed
// height field, by top-down traversal of a max-mip (Tevs, Ihrke and Seidel, "Maximum Mipmaps for
// Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008) and a closed-form solve
// of the ray against each candidate bilinear patch. It is the ground truth the approximate
// searches of shaders_cpp/search.h are measured against.
//
// Field: texel (i, j) of a depth map holds depth in [0, 1] (0 = reference surface, 1 deepest) at
// its centre ((i + 0.5) / w, (j + 0.5) / h); between four texel centres the depth is their
// bilinear interpolation, exactly what a bilinear texture fetch at LOD 0 returns, with the same
// wrap rule per axis (repeat and mirror are periodic, clamp extends the edge texels forever).
// A "cell" is the square between four texel centres; the hierarchy's leaves are cells holding the
// minimum depth (= maximum height) of their four corners, which bounds the bilinear patch since
// the patch never leaves the range of its corners. Each level above keeps the minimum of 2x2 nodes.
//
// Ray (shaders_cpp/ray.h): (u, v) + t * (dsx, dsy) at depth t in [0, 1]; the hit is the smallest t
// with D(u + t dsx, v + t dsy) <= t. Arithmetic is double throughout, so the reference is far more
// accurate than any float kernel it is compared with, even at grazing angles where the ray
// crosses the texture many times.

#ifndef RELIEF_SHADERS_CPP_EXACT_H_ONCE
#define RELIEF_SHADERS_CPP_EXACT_H_ONCE
#include <vector>
#include "rasterizer/texture.h"

namespace relief {

struct ExactHit {
  double u = 0.0, v = 0.0;  // hit texture coordinates (not wrapped)
  double t = 1.0;           // ray depth at the hit
  int nodes = 0;            // hierarchy nodes visited
  int cells = 0;            // leaf patches solved
};

class HeightField {
 public:
  HeightField() = default;
  // `depth` holds width * height texels row-major (row 0 first), values in [0, 1]. Mirror wrap is
  // periodic with period 2 * size; repeat with period size.
  HeightField(int width, int height, const float* depth, Wrap wrap_u, Wrap wrap_v);
  // The first channel of `level` of a depth texture, with the sampler's wrap modes.
  static HeightField from_texture(const Texture& texture, const SamplerState& sampler,
                                  int level = 0);

  int width() const { return w_; }
  int height() const { return h_; }
  bool empty() const { return w_ == 0; }

  // Bilinear depth at (u, v), as a bilinear fetch at LOD 0 computes it (in double).
  double depth_at(double u, double v) const;

  // First hit of the ray (u, v) + t (dsx, dsy), depth t in [0, 1]. Depths never exceed 1, so a
  // hit always exists (at t = 1 at the latest).
  ExactHit intersect(double u, double v, double dsx, double dsy) const;

  // Whether the shadow ray from the point (u, v) at depth t toward the light, (u, v) + s (dlx,
  // dly) at depth t - s for s in [0, t] (shaders_cpp/ray.h light_step), passes under the surface
  // by more than `bias` anywhere: min_s D - (t - s) < -bias. Optional counters.
  bool shadowed(double u, double v, double t, double dlx, double dly, double bias,
                int* nodes = nullptr, int* cells = nullptr) const;

  // Read-only layout, for packing the same field elsewhere (gl/height_field.cpp). Axis 0 is u.
  // The expanded texels are period(0) x period(1), row-major; level l has level_width(l) x
  // level_height(l) nodes, level 0 one per leaf cell (min of its four corners), each level above
  // the min of 2x2 nodes, the last 1 x 1.
  bool periodic(int axis) const { return axis_(axis).periodic; }
  int size(int axis) const { return axis_(axis).size; }
  int period(int axis) const { return axis_(axis).period; }
  int cells(int axis) const { return axis_(axis).cells; }
  const std::vector<float>& texels() const { return tex_; }
  int num_levels() const { return static_cast<int>(levels_.size()); }
  const std::vector<float>& level(int l) const { return levels_[l]; }
  int level_width(int l) const { return nx_[l]; }
  int level_height(int l) const { return ny_[l]; }

 private:
  struct Axis {
    bool periodic = true;
    int size = 0;         // texels per uv unit
    int period = 0;       // texels of the (expanded) field along this axis
    int cells = 0;        // leaf cells along this axis
    double extent = 0.0;  // cell-space domain: [0, period) periodic, [0, size - 1] clamp
  };
  struct Line {
    double x0, dx, y0, dy;  // cell-space position at parameter p: (x0 + dx p, y0 + dy p)
  };
  struct Query;  // traversal state (exact_trace.cpp)

  const Axis& axis_(int axis) const { return axis == 0 ? ax_ : ay_; }
  float texel(int i, int j) const { return tex_[static_cast<size_t>(j) * ax_.period + i]; }
  int corner(const Axis& a, int i) const;
  float node(int level, int i, int j) const {
    return levels_[level][static_cast<size_t>(j) * nx_[level] + i];
  }
  template <class Visit>
  bool for_segments(double x0, double dx, double y0, double dy, double pmax, Visit&& visit) const;
  bool visit_node(Query& q, int level, int i, int j, double pa, double pb) const;
  bool solve_cell(Query& q, int i, int j, double pa, double pb) const;

  int w_ = 0, h_ = 0;
  Axis ax_, ay_;
  std::vector<float> tex_;                  // ax_.period x ay_.period texels
  std::vector<std::vector<float>> levels_;  // levels_[0]: cells; last: 1 x 1
  std::vector<int> nx_, ny_;
};

}  // namespace relief
#endif  // RELIEF_SHADERS_CPP_EXACT_H_ONCE

#if defined(RELIEF_SHADERS_CPP_EXACT_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_EXACT_H_
#undef RELIEF_SHADERS_CPP_EXACT_H_
#else
#define RELIEF_SHADERS_CPP_EXACT_H_
#endif

#include <vector>

#include "rasterizer/texture.h"
#include "shaders_cpp/lanes.h"
#include "shaders_cpp/search.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
// Per-lane bridge for plugins and tests: the exact hit of each active lane's ray, rounded to
// float. steps = nodes visited, fetches = nodes visited + 4 per patch solved (the reads the
// reference makes; it samples no texture). Inactive lanes return their start uv at depth 0.
template <class F>
inline SearchHit<F> exact_search(const HeightField& field, V2<F> uv, V2<F> ds, mask_t<F> active) {
  SearchHit<F> r{uv, F(0.0f), F(0.0f), F(0.0f)};
  for (int i = 0; i < lane_width<F>; ++i) {
    if (!lane(active, i)) continue;
    ExactHit h = field.intersect(lane(uv.x, i), lane(uv.y, i), lane(ds.x, i), lane(ds.y, i));
    set_lane(r.uv.x, i, static_cast<float>(h.u));
    set_lane(r.uv.y, i, static_cast<float>(h.v));
    set_lane(r.depth, i, static_cast<float>(h.t));
    set_lane(r.steps, i, static_cast<float>(h.nodes));
    set_lane(r.fetches, i, static_cast<float>(h.nodes + 4 * h.cells));
  }
  return r;
}

// Exact hard self-shadow per lane (same contract as shaders_cpp/shadow.h self_shadow): visibility
// 1 lit, 0 shadowed; L.z <= 0 is shadowed; inactive lanes are lit.
template <class F>
inline F exact_shadow(const HeightField& field, V2<F> uv, F t, V2<F> dl, F lz, float bias,
                      mask_t<F> active, F* steps = nullptr) {
  F vis(1.0f), st(0.0f);
  for (int i = 0; i < lane_width<F>; ++i) {
    if (!lane(active, i)) continue;
    if (!(lane(lz, i) > 0.0f)) {
      set_lane(vis, i, 0.0f);
      continue;
    }
    int nodes = 0, cells = 0;
    bool sh = field.shadowed(lane(uv.x, i), lane(uv.y, i), lane(t, i), lane(dl.x, i), lane(dl.y, i),
                             bias, &nodes, &cells);
    set_lane(vis, i, sh ? 0.0f : 1.0f);
    set_lane(st, i, static_cast<float>(nodes));
  }
  if (steps) *steps = st;
  return vis;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_EXACT_H_
