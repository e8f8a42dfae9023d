// Cone map bakers. Conservative cones: Dummer 2006, "Cone Step Mapping". Quad-directional and
// relaxed cones: Policarpo & Oliveira 2007, "Relaxed Cone Stepping for Relief Mapping" (GPU Gems 3,
// ch. 18, listings 18-1 and 18-2). Definitions and conventions in bake/cone_map.h.
#include "bake/cone_map.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "base/check.h"
#include "base/thread_pool.h"

namespace relief {

const char* cone_kind_name(ConeKind kind) {
  switch (kind) {
    case ConeKind::kConservative:
      return "conservative";
    case ConeKind::kQuad:
      return "quad";
    case ConeKind::kRelaxed:
      return "relaxed";
  }
  return "?";
}

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// Culling slack: a block or march is skipped only when every value it could give exceeds the
// current ratio by this factor, far above float rounding, so the fast baker's minimum is bit for
// bit the brute force's.
constexpr float kCullSlack = 1.0f + 1e-5f;
constexpr float kMarchSlack = 1.0f + 1.0f / 1024.0f;

struct Field {
  int w = 0, h = 0;
  bool wrap = false;
  std::vector<float> d;  // level 0, row-major, each in [0, 1]
  float deepest = 0.0f;  // max of d

  float at(int x, int y) const { return d[static_cast<size_t>(y) * w + x]; }
  // Depth of the nearest-texel cell (x, y) of the tiled plane (wrap) or clamped to the border.
  float cell(int x, int y) const {
    if (wrap) {
      x %= w;
      y %= h;
      if (x < 0) x += w;
      if (y < 0) y += h;
    } else {
      x = std::clamp(x, 0, w - 1);
      y = std::clamp(y, 0, h - 1);
    }
    return at(x, y);
  }
  // uv distance of a texel offset; monotone in |ox| and |oy| (also in float).
  float dist(int ox, int oy) const {
    const float a = static_cast<float>(ox) / static_cast<float>(w);
    const float b = static_cast<float>(oy) / static_cast<float>(h);
    return std::sqrt(a * a + b * b);
  }
};

// Destinations of a bake: the texels themselves (texel-point cones) or, for cones safe on the
// bilinear surface, the patches between texel centres, each with the minimum of its corners.
// Grid index g stands for destination coordinate g + origin (texel, or the patch's low corner).
struct Destinations {
  bool patches = false;
  int origin = 0;  // 0, or -1 for clamped patches (the half-texel strips at the borders)
  Field grid;      // destination depths; wrap as the source
  // Per source texel (patches only): the apex depth bound A (bilinear maximum over the texel's
  // cell) and the near ratio 1 / L (L: steepest bilinear gradient over the 4 patches around it).
  std::vector<float> apex, near;
};

// Per-axis gap in texels between a source cell [-1/2, 1/2] and the patch [o, o + 1].
inline int gap2(int o) {  // twice the gap, exact in integers
  return std::max({0, 2 * o - 1, -2 * o - 3});
}
inline int range_gap2(int o0, int o1) {
  if (o0 <= 0 && o1 >= -1) return 0;
  return std::min(gap2(o0), gap2(o1));
}

// uv distance between the source and destinations at offsets [ox0, ox1] x [oy0, oy1].
inline float range_dist(const Field& f, const Destinations& d, int ox0, int ox1, int oy0, int oy1) {
  if (!d.patches) return f.dist(std::clamp(0, ox0, ox1), std::clamp(0, oy0, oy1));
  const float a = 0.5f * static_cast<float>(range_gap2(ox0, ox1)) / static_cast<float>(f.w);
  const float b = 0.5f * static_cast<float>(range_gap2(oy0, oy1)) / static_cast<float>(f.h);
  return std::sqrt(a * a + b * b);
}

// The 4 patches around a source texel are "near": bounded by the gradient, not by distance.
inline bool near_patch(const Destinations& d, int ox, int oy) {
  return d.patches ? (ox >= -1 && ox <= 0 && oy >= -1 && oy <= 0) : (ox == 0 && oy == 0);
}

// Quad half-plane membership (+u, -u, +v, -v): closed for texels; for patches, those a ray
// starting anywhere in the source cell can reach.
inline void half_planes(const Destinations& d, int ox, int oy, bool in[4]) {
  const int lo = d.patches ? -1 : 0;
  in[0] = ox >= lo;
  in[1] = ox <= 0;
  in[2] = oy >= lo;
  in[3] = oy <= 0;
}

Destinations make_destinations(const Field& f, bool patches) {
  Destinations d;
  d.patches = patches;
  if (!patches) {
    d.grid = f;
    return d;
  }
  d.origin = f.wrap ? 0 : -1;
  d.grid.wrap = f.wrap;
  d.grid.w = f.wrap ? f.w : f.w + 1;
  d.grid.h = f.wrap ? f.h : f.h + 1;
  d.grid.d.resize(static_cast<size_t>(d.grid.w) * d.grid.h);
  for (int gy = 0; gy < d.grid.h; ++gy)
    for (int gx = 0; gx < d.grid.w; ++gx) {
      const int x = gx + d.origin, y = gy + d.origin;
      d.grid.d[static_cast<size_t>(gy) * d.grid.w + gx] =
          std::min({f.cell(x, y), f.cell(x + 1, y), f.cell(x, y + 1), f.cell(x + 1, y + 1)});
    }
  d.apex.resize(f.d.size());
  d.near.resize(f.d.size());
  const float fw = static_cast<float>(f.w), fh = static_cast<float>(f.h);
  for (int y = 0; y < f.h; ++y)
    for (int x = 0; x < f.w; ++x) {
      // bilinear maximum over the cell: at the corners of its four quarters
      float a = f.at(x, y);
      for (int sy = -1; sy <= 1; sy += 2)
        for (int sx = -1; sx <= 1; sx += 2) {
          const float c = f.at(x, y), ex = f.cell(x + sx, y), ey = f.cell(x, y + sy),
                      exy = f.cell(x + sx, y + sy);
          a = std::max({a, 0.5f * (c + ex), 0.5f * (c + ey), 0.25f * (c + ex + ey + exy)});
        }
      // steepest gradient (depth per uv) of the four patches: at their corners
      float g2 = 0.0f;
      for (int py = y - 1; py <= y; ++py)
        for (int px = x - 1; px <= x; ++px) {
          const float c00 = f.cell(px, py), c10 = f.cell(px + 1, py), c01 = f.cell(px, py + 1),
                      c11 = f.cell(px + 1, py + 1);
          for (float gx : {c10 - c00, c11 - c01})
            for (float gy : {c01 - c00, c11 - c10})
              g2 = std::max(g2, gx * fw * gx * fw + gy * fh * gy * fh);
        }
      const size_t i = static_cast<size_t>(y) * f.w + x;
      // rounded up so the float quotients below never exceed the real bounds
      d.apex[i] = std::nextafter(a, kInf);
      d.near[i] = g2 > 0.0f ? 1.0f / std::nextafter(std::sqrt(g2), kInf) : kInf;
    }
  return d;
}

Field read_field(const Texture& depth, bool wrap) {
  CHECK(!depth.empty());
  Field f;
  f.w = depth.width(0);
  f.h = depth.height(0);
  f.wrap = wrap;
  f.d.resize(static_cast<size_t>(f.w) * f.h);
  // Depth maps hold [0, 1] (loaders clamp files with a warning); a texture made in code that
  // does not is clamped here too (NaN as 0), so every march below ends within the map's depth.
  for (int y = 0; y < f.h; ++y)
    for (int x = 0; x < f.w; ++x) {
      const float v = depth.fetch_r(0, x, y);
      const float c = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;
      f.d[static_cast<size_t>(y) * f.w + x] = c;
      f.deepest = std::max(f.deepest, c);
    }
  return f;
}

// Relaxed pair: the parameter t > 1 at which the ray from (c_i, 0) through S_j first comes out of
// the surface, or 0 if it does not before t_cap. Cells are walked exactly: crossing k along x is
// at t = 1 + (k + 1/2) / |ox|.
float relaxed_exit(const Field& f, int x, int y, int ox, int oy, float dj, float t_cap) {
  // Past t = deepest / dj the ray is below every texel and cannot come out: the same answer (0)
  // without walking there (a bound on the walk whatever t_cap is).
  if (dj > 0.0f) t_cap = std::min(t_cap, f.deepest / dj * kMarchSlack);
  int cx = x + ox, cy = y + oy;
  const int sx = ox > 0 ? 1 : (ox < 0 ? -1 : 0);
  const int sy = oy > 0 ? 1 : (oy < 0 ? -1 : 0);
  const int64_t ax = std::abs(ox), ay = std::abs(oy);
  int64_t kx = 0, ky = 0;
  for (;;) {
    // Compare (kx + 1/2) / ax with (ky + 1/2) / ay exactly.
    const int64_t lhs = ay == 0 ? -1 : (2 * kx + 1) * ay;
    const int64_t rhs = ax == 0 ? -1 : (2 * ky + 1) * ax;
    float t;
    if (ay == 0 || (ax != 0 && lhs < rhs)) {
      t = 1.0f + (static_cast<float>(kx) + 0.5f) / static_cast<float>(ax);
      cx += sx;
      ++kx;
    } else if (ax == 0 || rhs < lhs) {
      t = 1.0f + (static_cast<float>(ky) + 0.5f) / static_cast<float>(ay);
      cy += sy;
      ++ky;
    } else {
      t = 1.0f + (static_cast<float>(kx) + 0.5f) / static_cast<float>(ax);
      cx += sx;
      cy += sy;
      ++kx;
      ++ky;
    }
    if (!(t <= t_cap)) return 0.0f;
    if (f.cell(cx, cy) > t * dj) return t;
  }
}

// r(i, j) for the relaxed cone, or +inf when it is not below `cap_ratio` (the march stops there).
inline float relaxed_pair(const Field& f, int x, int y, int ox, int oy, float di, float dj,
                          float dist, float cap_ratio) {
  const float r = cap_ratio * kMarchSlack;
  const float t_cap = r * di / (dist + r * dj);
  const float t = relaxed_exit(f, x, y, ox, oy, dj, t_cap);
  if (t == 0.0f) return kInf;
  const float ez = t * dj;
  if (!(ez < di)) return kInf;
  return t * dist / (di - ez);
}

// Runs rows(y) for every row over a pool, reporting progress from the calling thread.
void for_rows(int h, int threads, const std::function<void(float)>& progress,
              const std::function<void(int)>& row) {
  ThreadPool pool(threads);
  std::atomic<int> done{0};
  pool.run(h, [&](int y, int worker) {
    row(y);
    const int n = done.fetch_add(1, std::memory_order_relaxed) + 1;
    if (worker == 0 && progress) progress(static_cast<float>(n) / static_cast<float>(h));
  });
  if (progress) progress(1.0f);
}

int channels_of(ConeKind kind) {
  return kind == ConeKind::kQuad ? 4 : 1;
}

void check_options(const ConeBakeOptions& o) {
  CHECK(o.max_ratio > 0.0f);
  CHECK(std::isfinite(o.max_ratio));
}

// Lowers the ratios r[] by destination j at offset (ox, oy) with depth dj and distance D from
// a source of depth di (conservative and quad kinds, and bilinear relaxed cones).
inline void lower(const Destinations& dst, ConeKind kind, int ox, int oy, float di, float dj,
                  float D, float* r) {
  const float v = D / (di - dj);
  if (kind != ConeKind::kQuad) {
    r[0] = std::min(r[0], v);
    return;
  }
  bool in[4];
  half_planes(dst, ox, oy, in);
  for (int c = 0; c < 4; ++c)
    if (in[c]) r[c] = std::min(r[c], v);
}

// A bilinear patch between four texel centres: depth c00 + bx a + by b + e a b at local (a, b) in
// [0, 1]^2 (e: its twist), gradient (bx + e b, by + e a).
struct Patch {
  float c00, bx, by, e;
  Patch(float c00_, float c10, float c01, float c11)
      : c00(c00_), bx(c10 - c00_), by(c01 - c00_), e(c11 - c10 - c01 + c00_) {}
  float at(float a, float b) const { return c00 + bx * a + by * b + e * a * b; }
};

// An axis-aligned box in texel units relative to the source texel's centre.
struct Box {
  float u0, v0, u1, v1;
};

// The radial-descent test of bilinear relaxed cones (see cone_map.h): g(q) . (q - p) > 0 for some
// q in box `qb` of patch P (local origin at (ou, ov)) and p in box `pb`? The expression is linear
// in p and bilinear in q, so its maximum over the two boxes is at a pair of corners.
bool descends_radially(const Patch& P, float ou, float ov, const Box& qb, const Box& pb) {
  for (float qv : {qb.v0, qb.v1})
    for (float qu : {qb.u0, qb.u1}) {
      const float gx = P.bx + P.e * (qv - ov), gy = P.by + P.e * (qu - ou);
      for (float pu : {pb.u0, pb.u1})
        for (float pv : {pb.v0, pb.v1})
          if (gx * (qu - pu) + gy * (qv - pv) > 0.0f) return true;
    }
  return false;
}

// Bilinear relaxed cones: can a ray leaving the axis of source cell (x, y) come out of the surface
// on the patch at offset (ox, oy)? Only where the patch descends radially from an apex in the
// cell: the cell is [-1/2, 1/2]^2 and the patch [ox, ox + 1] x [oy, oy + 1].
bool patch_may_exit(const Field& f, int x, int y, int ox, int oy) {
  const Patch P(f.cell(x + ox, y + oy), f.cell(x + ox + 1, y + oy), f.cell(x + ox, y + oy + 1),
                f.cell(x + ox + 1, y + oy + 1));
  const float u = static_cast<float>(ox), v = static_cast<float>(oy);
  return descends_radially(P, u, v, {u, v, u + 1.0f, v + 1.0f}, {-0.5f, -0.5f, 0.5f, 0.5f});
}

// Does destination (ox, oy) constrain source (x, y)? Always, except for bilinear relaxed cones,
// where only patches a ray can come out of do.
inline bool constrains(const Field& f, const Destinations& dst, ConeKind kind, int x, int y, int ox,
                       int oy) {
  return !(dst.patches && kind == ConeKind::kRelaxed) || patch_may_exit(f, x, y, ox, oy);
}

// Bilinear relaxed cones, the 4 near patches around source texel (x, y) (the 2 x 2 texel square
// [-1, 1]^2 around its centre, which holds its cell). Gaps are zero here, so the patches are cut
// into quarter-texel squares, the cell too, and each pair (apex square Sp, surface square Sq)
// bounds the ratio only if a ray can come out of Sq above an apex of Sp: the minimum depth of Sq
// below the maximum of Sp and the radial-descent test passes. Then: both squares in one patch ->
// along a segment in a patch the depth is quadratic with curvature e dx dy (e: the patch's twist),
// so a ray comes out above its apex only where the depth rose by less than |e dx dy| on the way
// back down: r <= |q - p|_uv / (|e| |dx dy|) >= 2 / (|e| sqrt(w h |dx dy|max)) (a plane: no bound);
// squares apart -> gap / (max - min); touching squares of two patches -> 1 / L (the segment stays
// in the 2 x 2 square, where the depth changes by at most L per uv; 1 / L holds for every pair, so
// each pair's bound is the larger of its own and 1 / L, and the cone is never narrower than the
// conservative one).
float relaxed_near_ratio(const Field& f, const Destinations& dst, int x, int y, float R) {
  const size_t i = static_cast<size_t>(y) * f.w + x;
  float c[3][3];  // texel depths around the source, c[1][1] = the source
  for (int j = -1; j <= 1; ++j)
    for (int k = -1; k <= 1; ++k) c[j + 1][k + 1] = f.cell(x + k, y + j);
  // the 4 near patches; patch (pu, pv) is [pu - 1, pu] x [pv - 1, pv]
  auto patch = [&](int pu, int pv) {
    return Patch(c[pv][pu], c[pv][pu + 1], c[pv + 1][pu], c[pv + 1][pu + 1]);
  };
  const Patch near[2][2] = {{patch(0, 0), patch(1, 0)}, {patch(0, 1), patch(1, 1)}};
  struct Sq {
    Box box;
    float lo, hi;  // depth range over the square (bilinear: at its corners)
    int pu, pv;    // its patch
  };
  auto square = [&](float u0, float v0, float q) {
    Sq sq{{u0, v0, u0 + q, v0 + q}, 2.0f, -1.0f, u0 < 0.0f ? 0 : 1, v0 < 0.0f ? 0 : 1};
    const float ou = static_cast<float>(sq.pu - 1), ov = static_cast<float>(sq.pv - 1);
    for (float u : {sq.box.u0, sq.box.u1})
      for (float v : {sq.box.v0, sq.box.v1}) {
        const float d = near[sq.pv][sq.pu].at(u - ou, v - ov);
        sq.lo = std::min(sq.lo, d);
        sq.hi = std::max(sq.hi, d);
      }
    return sq;
  };
  constexpr float q = 0.25f;
  Sq ps[16], qs[64];
  for (int j = 0; j < 4; ++j)
    for (int k = 0; k < 4; ++k) ps[j * 4 + k] = square(-0.5f + q * k, -0.5f + q * j, q);
  for (int j = 0; j < 8; ++j)
    for (int k = 0; k < 8; ++k) qs[j * 8 + k] = square(-1.0f + q * k, -1.0f + q * j, q);
  const float fw = static_cast<float>(f.w), fh = static_cast<float>(f.h);
  float r = R;
  for (const Sq& b : qs) {
    const Patch& P = near[b.pv][b.pu];
    const float ou = static_cast<float>(b.pu - 1), ov = static_cast<float>(b.pv - 1);
    for (const Sq& a : ps) {
      if (!(b.lo < a.hi) || !descends_radially(P, ou, ov, b.box, a.box)) continue;
      if (a.pu == b.pu && a.pv == b.pv) {
        if (P.e == 0.0f) continue;
        const float dx = std::max(std::abs(b.box.u1 - a.box.u0), std::abs(a.box.u1 - b.box.u0));
        const float dy = std::max(std::abs(b.box.v1 - a.box.v0), std::abs(a.box.v1 - b.box.v0));
        const float twist =
            2.0f / std::nextafter(std::abs(P.e) * std::sqrt(fw * fh * dx * dy), kInf);
        r = std::min(r, std::max(twist, dst.near[i]));
        continue;
      }
      const float gu = std::max({0.0f, b.box.u0 - a.box.u1, a.box.u0 - b.box.u1}),
                  gv = std::max({0.0f, b.box.v0 - a.box.v1, a.box.v0 - b.box.v1});
      if (gu == 0.0f && gv == 0.0f) {
        r = std::min(r, dst.near[i]);
        continue;
      }
      const float gap = std::hypot(gu / fw, gv / fh);
      r = std::min(r, std::max(gap / std::nextafter(a.hi - b.lo, kInf), dst.near[i]));
    }
  }
  return r;
}

// The source's apex depth and initial ratios (the near bound for patches; for bilinear relaxed
// cones relaxed_near_ratio).
inline float start_texel(const Field& f, const Destinations& dst, ConeKind kind, float R, int x,
                         int y, float* r) {
  const size_t i = static_cast<size_t>(y) * f.w + x;
  if (dst.patches && kind == ConeKind::kRelaxed) {
    r[0] = relaxed_near_ratio(f, dst, x, y, R);
    return dst.apex[i];
  }
  const float r0 = dst.patches ? std::min(R, dst.near[i]) : R;
  for (int c = 0; c < 4; ++c) r[c] = r0;
  return dst.patches ? dst.apex[i] : f.at(x, y);
}

// ---- brute force: every pair ----

void brute_texel(const Field& f, const Destinations& dst, const ConeBakeOptions& o, int x, int y,
                 float* out) {
  const float R = o.max_ratio;
  float r[4];
  const float di = start_texel(f, dst, o.kind, R, x, y, r);
  int ox0, ox1, oy0, oy1;
  if (f.wrap) {
    // Offsets with D >= R d_i give ratios >= R: the box |ox| <= R d_i w, |oy| <= R d_i h holds all
    // others (two more for the patches' half-texel gaps).
    const int bx = static_cast<int>(std::ceil(R * di * f.w)) + 3;
    const int by = static_cast<int>(std::ceil(R * di * f.h)) + 3;
    ox0 = -bx, ox1 = bx, oy0 = -by, oy1 = by;
  } else {
    ox0 = dst.origin - x, ox1 = dst.grid.w - 1 + dst.origin - x;
    oy0 = dst.origin - y, oy1 = dst.grid.h - 1 + dst.origin - y;
  }
  for (int oy = oy0; oy <= oy1; ++oy)
    for (int ox = ox0; ox <= ox1; ++ox) {
      if (near_patch(dst, ox, oy)) continue;
      const float dj = dst.grid.cell(x + ox - dst.origin, y + oy - dst.origin);
      if (!(dj < di)) continue;
      if (!constrains(f, dst, o.kind, x, y, ox, oy)) continue;
      const float D = range_dist(f, dst, ox, ox, oy, oy);
      if (o.kind == ConeKind::kRelaxed && !dst.patches)
        r[0] = std::min(r[0], relaxed_pair(f, x, y, ox, oy, di, dj, D, R));
      else
        lower(dst, o.kind, ox, oy, di, dj, D, r);
    }
  for (int c = 0; c < channels_of(o.kind); ++c) out[c] = r[c];
}

// ---- fast: min-depth quadtree, nearest blocks first, culled by the current ratio ----

struct MinTree {
  // levels[L] is ceil(w / 2^L) x ceil(h / 2^L); texel block of node (nx, ny) at level L is
  // [nx 2^L, (nx + 1) 2^L) x [ny 2^L, (ny + 1) 2^L) clipped to the map.
  std::vector<std::vector<float>> levels;
  std::vector<int> lw, lh;
  float at(int L, int nx, int ny) const { return levels[L][static_cast<size_t>(ny) * lw[L] + nx]; }
};

MinTree build_tree(const Field& f) {
  MinTree t;
  t.levels.push_back(f.d);
  t.lw.push_back(f.w);
  t.lh.push_back(f.h);
  while (t.lw.back() > 1 || t.lh.back() > 1) {
    const int pw = t.lw.back(), ph = t.lh.back();
    const int nw = (pw + 1) / 2, nh = (ph + 1) / 2;
    std::vector<float> n(static_cast<size_t>(nw) * nh);
    const std::vector<float>& p = t.levels.back();
    for (int y = 0; y < nh; ++y)
      for (int x = 0; x < nw; ++x) {
        float m = kInf;
        for (int yy = 2 * y; yy < std::min(2 * y + 2, ph); ++yy)
          for (int xx = 2 * x; xx < std::min(2 * x + 2, pw); ++xx)
            m = std::min(m, p[static_cast<size_t>(yy) * pw + xx]);
        n[static_cast<size_t>(y) * nw + x] = m;
      }
    t.levels.push_back(std::move(n));
    t.lw.push_back(nw);
    t.lh.push_back(nh);
  }
  return t;
}

struct Node {
  int level, nx, ny;  // node of the tree
  int bx, by;         // offset of the tree copy (image of the grid) in the tiled plane
  float dmin;         // nearest offset distance from the source texel
};

class FastBaker {
 public:
  FastBaker(const Field& f, const Destinations& dst, const MinTree& t, const ConeBakeOptions& o)
      : f_(f), g_(dst.grid), dst_(dst), t_(t), o_(o) {}

  void texel(int x, int y, float* out) {
    const float R = o_.max_ratio;
    float r[4];
    const float di = start_texel(f_, dst_, o_.kind, R, x, y, r);
    const int nc = channels_of(o_.kind);
    const int top = static_cast<int>(t_.levels.size()) - 1;
    stack_.clear();
    if (di > 0.0f) {
      if (f_.wrap) {
        const int ax = static_cast<int>(std::ceil(R)) + 1, ay = ax;
        for (int iy = -ay; iy <= ay; ++iy)
          for (int ix = -ax; ix <= ax; ++ix) push(x, y, top, 0, 0, ix * g_.w, iy * g_.h);
        std::sort(stack_.begin(), stack_.end(),
                  [](const Node& a, const Node& b) { return a.dmin > b.dmin; });
      } else {
        push(x, y, top, 0, 0, 0, 0);
      }
    }
    while (!stack_.empty()) {
      const Node n = stack_.back();
      stack_.pop_back();
      const float m = t_.at(n.level, n.nx, n.ny);
      if (!(m < di)) continue;
      float rmax = r[0];
      for (int c = 1; c < nc; ++c) rmax = std::max(rmax, r[c]);
      if (n.dmin > rmax * (di - m) * kCullSlack) continue;
      const int x0 = n.nx << n.level, y0 = n.ny << n.level;
      if (n.level <= 2) {
        // Small block: every destination.
        const int x1 = std::min(x0 + (1 << n.level), g_.w),
                  y1 = std::min(y0 + (1 << n.level), g_.h);
        for (int ty = y0; ty < y1; ++ty)
          for (int tx = x0; tx < x1; ++tx) {
            const int ox = tx + dst_.origin + n.bx - x, oy = ty + dst_.origin + n.by - y;
            if (near_patch(dst_, ox, oy)) continue;
            const float dj = g_.at(tx, ty);
            if (!(dj < di)) continue;
            const float D = range_dist(f_, dst_, ox, ox, oy, oy);
            if (o_.kind != ConeKind::kQuad && D > r[0] * (di - dj) * kCullSlack) continue;
            if (!constrains(f_, dst_, o_.kind, x, y, ox, oy)) continue;
            if (o_.kind == ConeKind::kRelaxed && !dst_.patches)
              r[0] = std::min(r[0], relaxed_pair(f_, x, y, ox, oy, di, dj, D, r[0]));
            else
              lower(dst_, o_.kind, ox, oy, di, dj, D, r);
          }
        continue;
      }
      // Children, nearest popped first.
      const size_t base = stack_.size();
      const int L = n.level - 1;
      for (int cy = 2 * n.ny; cy < std::min(2 * n.ny + 2, t_.lh[L]); ++cy)
        for (int cx = 2 * n.nx; cx < std::min(2 * n.nx + 2, t_.lw[L]); ++cx)
          push(x, y, L, cx, cy, n.bx, n.by);
      std::sort(stack_.begin() + base, stack_.end(),
                [](const Node& a, const Node& b) { return a.dmin > b.dmin; });
    }
    for (int c = 0; c < nc; ++c) out[c] = r[c];
  }

 private:
  void push(int x, int y, int L, int nx, int ny, int bx, int by) {
    const int sx = bx + dst_.origin - x, sy = by + dst_.origin - y;
    const int x0 = (nx << L) + sx, x1 = std::min((nx + 1) << L, g_.w) - 1 + sx;
    const int y0 = (ny << L) + sy, y1 = std::min((ny + 1) << L, g_.h) - 1 + sy;
    stack_.push_back(Node{L, nx, ny, bx, by, range_dist(f_, dst_, x0, x1, y0, y1)});
  }

  const Field& f_;
  const Field& g_;
  const Destinations& dst_;
  const MinTree& t_;
  const ConeBakeOptions& o_;
  std::vector<Node> stack_;
};

// The output of a bake of `kind` over field f, zeroed.
ConeRatios make_ratios(const Field& f, ConeKind kind) {
  ConeRatios out;
  out.width = f.w;
  out.height = f.h;
  out.channels = channels_of(kind);
  out.values.resize(static_cast<size_t>(f.w) * f.h * out.channels);
  return out;
}

}  // namespace

ConeRatios bake_cone_ratios_brute_force(const Texture& depth, const ConeBakeOptions& options) {
  check_options(options);
  const Field f = read_field(depth, options.wrap);
  const Destinations dst = make_destinations(f, options.bilinear);
  ConeRatios out = make_ratios(f, options.kind);
  for_rows(f.h, options.threads, options.progress, [&](int y) {
    for (int x = 0; x < f.w; ++x)
      brute_texel(f, dst, options, x, y,
                  &out.values[(static_cast<size_t>(y) * f.w + x) * out.channels]);
  });
  return out;
}

ConeRatios bake_cone_ratios(const Texture& depth, const ConeBakeOptions& options) {
  check_options(options);
  const Field f = read_field(depth, options.wrap);
  const Destinations dst = make_destinations(f, options.bilinear);
  const MinTree tree = build_tree(dst.grid);
  ConeRatios out = make_ratios(f, options.kind);
  for_rows(f.h, options.threads, options.progress, [&](int y) {
    FastBaker baker(f, dst, tree, options);
    for (int x = 0; x < f.w; ++x)
      baker.texel(x, y, &out.values[(static_cast<size_t>(y) * f.w + x) * out.channels]);
  });
  return out;
}

float relaxed_pair_ratio(const Texture& depth, int x, int y, int ox, int oy, float max_ratio,
                         bool wrap) {
  const Field f = read_field(depth, wrap);
  const float di = f.at(x, y), dj = f.cell(x + ox, y + oy);
  if ((ox == 0 && oy == 0) || !(dj < di)) return kInf;
  return relaxed_pair(f, x, y, ox, oy, di, dj, f.dist(ox, oy), max_ratio);
}

namespace {
// Largest IEEE half value <= x (x >= 0, finite, below 65504).
float round_down_to_half(float x) {
  if (!(x > 0.0f)) return 0.0f;
  if (x < 6.103515625e-05f) return std::floor(x * 16777216.0f) / 16777216.0f;  // subnormal halves
  uint32_t b;
  std::memcpy(&b, &x, 4);
  b &= ~((1u << 13) - 1u);  // keep 10 mantissa bits
  float r;
  std::memcpy(&r, &b, 4);
  return r;
}
}  // namespace

Texture cone_ratios_to_texture(const ConeRatios& ratios, bool min_mips) {
  CHECK(ratios.channels == 1 || ratios.channels == 4);
  Texture t;
  if (ratios.channels == 1) {
    t = Texture::from_floats(TexFormat::kR32F, ratios.width, ratios.height, ratios.values.data());
  } else {
    std::vector<float> v(ratios.values.size());
    for (size_t i = 0; i < v.size(); ++i)
      v[i] = round_down_to_half(std::min(ratios.values[i], 65504.0f));
    t = Texture::from_floats(TexFormat::kRGBA16F, ratios.width, ratios.height, v.data());
  }
  if (min_mips) t.generate_mips(MipReduce::kMin);
  return t;
}

Texture bake_cone_map(const Texture& depth, const ConeBakeOptions& options, bool min_mips) {
  return cone_ratios_to_texture(bake_cone_ratios(depth, options), min_mips);
}

}  // namespace relief
