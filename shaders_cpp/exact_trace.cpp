// Exact ray / bilinear height-field intersection by max-mip traversal: Tevs, Ihrke and Seidel,
// "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering", I3D 2008.
// Contracts in shaders_cpp/exact_trace.h.
#include "shaders_cpp/exact_trace.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "base/check.h"

namespace relief {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// Boxes grow by this much (cell units) when a ray is clipped to them, so a ray through a shared
// edge or corner is never lost between two nodes.
constexpr double kBoxEps = 1e-9;

// Clips p in [pa, pb] to x0 + dx p in [lo, hi]; false if empty.
inline bool clip_slab(double x0, double dx, double lo, double hi, double& pa, double& pb) {
  lo -= kBoxEps;
  hi += kBoxEps;
  if (dx == 0.0) return x0 >= lo && x0 <= hi;
  double p0 = (lo - x0) / dx, p1 = (hi - x0) / dx;
  if (p0 > p1) std::swap(p0, p1);
  pa = std::max(pa, p0);
  pb = std::min(pb, p1);
  return pa <= pb;
}

// Walks one axis of a line through the periodic or clamped domain: the breakpoints where the
// mapping of the axis changes, and the mapped line between them.
struct AxisWalk {
  bool periodic;
  double x0, dx, extent;
  long k = 0, k_end = 0;  // periodic: current period index and last one
  int region = 0;         // clamp: -1 below 0, 0 inside, 1 above extent

  AxisWalk(bool periodic_axis, double x0_, double dx_, double extent_, double pmax)
      : periodic(periodic_axis), x0(x0_), dx(dx_), extent(extent_) {
    if (periodic) {
      k = static_cast<long>(std::floor(x0 / extent));
      k_end = static_cast<long>(std::floor((x0 + dx * pmax) / extent));
      if (dx == 0.0) k_end = k;
    } else {
      region = region_of(x0, dx);
    }
  }
  int region_of(double x, double d) const {
    if (x < 0.0 || (x == 0.0 && d < 0.0)) return -1;
    if (x > extent || (x == extent && d > 0.0)) return 1;
    return 0;
  }
  // Parameter of the next breakpoint, +inf if none.
  double next() const {
    if (periodic) {
      if (k == k_end) return kInf;
      double b = dx > 0.0 ? static_cast<double>(k + 1) * extent : static_cast<double>(k) * extent;
      return (b - x0) / dx;
    }
    if (dx > 0.0) {
      if (region == -1) return (0.0 - x0) / dx;
      if (region == 0) return (extent - x0) / dx;
    } else if (dx < 0.0) {
      if (region == 1) return (extent - x0) / dx;
      if (region == 0) return (0.0 - x0) / dx;
    }
    return kInf;
  }
  void advance() {
    if (periodic) {
      k += dx > 0.0 ? 1 : -1;
    } else {
      region += dx > 0.0 ? 1 : -1;
    }
  }
  // The mapped line of the current segment.
  void mapped(double& mx0, double& mdx) const {
    if (periodic) {
      mx0 = x0 - static_cast<double>(k) * extent;
      mdx = dx;
    } else if (region == 0) {
      mx0 = x0;
      mdx = dx;
    } else {
      mx0 = region < 0 ? 0.0 : extent;
      mdx = 0.0;
    }
  }
};

}  // namespace

struct HeightField::Query {
  Line line;      // mapped line of the current segment, cell space
  double z0, dz;  // ray depth at parameter p: z0 + dz p
  bool shadow;    // false: first p with D <= z; true: any p with D - z < -bias
  double bias;
  double hit_p;  // result (view)
  int nodes = 0, cells = 0;
};

HeightField::HeightField(int width, int height, const float* depth, Wrap wrap_u, Wrap wrap_v) {
  CHECK(width >= 1 && height >= 1);
  w_ = width;
  h_ = height;
  auto make_axis = [](int size, Wrap wrap) {
    Axis a;
    a.size = size;
    a.periodic = wrap != Wrap::kClamp;
    a.period = wrap == Wrap::kMirror ? 2 * size : size;
    a.cells = a.periodic ? a.period : std::max(size - 1, 1);
    a.extent = a.periodic ? a.period : size - 1;
    return a;
  };
  ax_ = make_axis(width, wrap_u);
  ay_ = make_axis(height, wrap_v);
  auto src = [](int i, int size, int period) { return i < size ? i : period - 1 - i; };
  tex_.resize(static_cast<size_t>(ax_.period) * ay_.period);
  for (int j = 0; j < ay_.period; ++j)
    for (int i = 0; i < ax_.period; ++i)
      tex_[static_cast<size_t>(j) * ax_.period + i] =
          depth[static_cast<size_t>(src(j, height, ay_.period)) * width +
                src(i, width, ax_.period)];
  // leaves: min of each cell's four corners
  int nx = ax_.cells, ny = ay_.cells;
  std::vector<float> cells(static_cast<size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int i1 = corner(ax_, i), j1 = corner(ay_, j);
      cells[static_cast<size_t>(j) * nx + i] =
          std::min(std::min(texel(i, j), texel(i1, j)), std::min(texel(i, j1), texel(i1, j1)));
    }
  levels_.push_back(std::move(cells));
  nx_.push_back(nx);
  ny_.push_back(ny);
  while (nx > 1 || ny > 1) {
    int cx = (nx + 1) / 2, cy = (ny + 1) / 2;
    const std::vector<float>& fine = levels_.back();
    std::vector<float> coarse(static_cast<size_t>(cx) * cy);
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i < cx; ++i) {
        float m = fine[static_cast<size_t>(2 * j) * nx + 2 * i];
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di) {
            int fi = 2 * i + di, fj = 2 * j + dj;
            if (fi < nx && fj < ny) m = std::min(m, fine[static_cast<size_t>(fj) * nx + fi]);
          }
        coarse[static_cast<size_t>(j) * cx + i] = m;
      }
    levels_.push_back(std::move(coarse));
    nx = cx;
    ny = cy;
    nx_.push_back(nx);
    ny_.push_back(ny);
  }
}

HeightField HeightField::from_texture(const Texture& texture, const SamplerState& sampler,
                                      int level) {
  int w = texture.width(level), h = texture.height(level);
  std::vector<float> d(static_cast<size_t>(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) d[static_cast<size_t>(j) * w + i] = texture.fetch_r(level, i, j);
  return HeightField(w, h, d.data(), sampler.wrap_u, sampler.wrap_v);
}

int HeightField::corner(const Axis& a, int i) const {
  return a.periodic ? (i + 1 == a.period ? 0 : i + 1) : std::min(i + 1, a.size - 1);
}

double HeightField::depth_at(double u, double v) const {
  auto locate = [](const Axis& a, double uv, int& i, double& f) {
    double x = uv * a.size - 0.5;
    if (a.periodic) {
      x -= std::floor(x / a.period) * a.period;
      i = std::min(static_cast<int>(std::floor(x)), a.period - 1);
    } else {
      x = std::clamp(x, 0.0, a.extent);
      i = std::min(static_cast<int>(std::floor(x)), a.cells - 1);
    }
    f = x - i;
  };
  int i, j;
  double fx, fy;
  locate(ax_, u, i, fx);
  locate(ay_, v, j, fy);
  int i1 = corner(ax_, i), j1 = corner(ay_, j);
  double a = texel(i, j), b = texel(i1, j), c = texel(i, j1), d = texel(i1, j1);
  return (a + (b - a) * fx) * (1.0 - fy) + (c + (d - c) * fx) * fy;
}

// Splits p in [0, pmax] where either axis's mapping changes and calls visit(pa, pb, line) on each
// piece in order until it returns true.
template <class Visit>
bool HeightField::for_segments(double x0, double dx, double y0, double dy, double pmax,
                               Visit&& visit) const {
  AxisWalk wx(ax_.periodic, x0, dx, ax_.extent, pmax);
  AxisWalk wy(ay_.periodic, y0, dy, ay_.extent, pmax);
  double pa = 0.0;
  for (;;) {
    double nx = wx.next(), ny = wy.next();
    double pb = std::min(std::min(nx, ny), pmax);
    pb = std::max(pb, pa);
    Line line;
    wx.mapped(line.x0, line.dx);
    wy.mapped(line.y0, line.dy);
    if (visit(pa, pb, line)) return true;
    if (pb >= pmax) return false;
    if (nx <= pb) wx.advance();
    if (ny <= pb) wy.advance();
    pa = pb;
  }
}

bool HeightField::visit_node(Query& q, int level, int i, int j, double pa, double pb) const {
  ++q.nodes;
  double zmin = node(level, i, j);
  double za = q.z0 + q.dz * pa, zb = q.z0 + q.dz * pb;
  if (!q.shadow) {
    // the ray is above the whole node until its depth reaches the node's minimum
    if (zmin > zb) return false;
    if (zmin > za) pa = std::max(pa, (zmin - q.z0) / q.dz);
    if (pa > pb) return false;
  } else if (zmin - std::max(za, zb) >= -q.bias) {
    return false;
  }
  if (level == 0) return solve_cell(q, i, j, pa, pb);
  // children in the order the ray enters them
  struct Child {
    int i, j;
    double pa, pb;
  } kids[4];
  int n = 0;
  int span = 1 << (level - 1);
  for (int dj = 0; dj < 2; ++dj)
    for (int di = 0; di < 2; ++di) {
      int ci = 2 * i + di, cj = 2 * j + dj;
      if (ci >= nx_[level - 1] || cj >= ny_[level - 1]) continue;
      double x0 = static_cast<double>(ci) * span, y0 = static_cast<double>(cj) * span;
      double x1 = std::min(x0 + span, static_cast<double>(ax_.cells));
      double y1 = std::min(y0 + span, static_cast<double>(ay_.cells));
      double ca = pa, cb = pb;
      if (!clip_slab(q.line.x0, q.line.dx, x0, x1, ca, cb)) continue;
      if (!clip_slab(q.line.y0, q.line.dy, y0, y1, ca, cb)) continue;
      kids[n++] = {ci, cj, ca, cb};
    }
  // By entry parameter: an insertion sort (at most four children; ties keep their order, as
  // std::sort's insertion sort of so few did), which GCC 12's -Warray-bounds reads right.
  for (int a = 1; a < n; ++a)
    for (int b = a; b > 0 && kids[b].pa < kids[b - 1].pa; --b) std::swap(kids[b], kids[b - 1]);
  for (int k = 0; k < n; ++k)
    if (visit_node(q, level - 1, kids[k].i, kids[k].j, kids[k].pa, kids[k].pb)) return true;
  return false;
}

bool HeightField::solve_cell(Query& q, int i, int j, double pa, double pb) const {
  ++q.cells;
  int i1 = corner(ax_, i), j1 = corner(ay_, j);
  double z00 = texel(i, j), z10 = texel(i1, j), z01 = texel(i, j1), z11 = texel(i1, j1);
  double e = z10 - z00, f = z01 - z00, k = z00 - z10 - z01 + z11;
  // local coordinates at pa, and their rates; s = p - pa in [0, len]
  double fx = q.line.x0 + q.line.dx * pa - i, fy = q.line.y0 + q.line.dy * pa - j;
  double bx = q.line.dx, by = q.line.dy;
  double len = pb - pa;
  // g(s) = D - z = A s^2 + B s + C
  double A = k * bx * by;
  double B = e * bx + f * by + k * (fx * by + fy * bx) - q.dz;
  double C = z00 + e * fx + f * fy + k * fx * fy - (q.z0 + q.dz * pa);
  if (q.shadow) {
    double gmin = std::min(C, (A * len + B) * len + C);
    if (A > 0.0) {
      double sv = -B / (2.0 * A);
      if (sv > 0.0 && sv < len) gmin = std::min(gmin, C - B * B / (4.0 * A));
    }
    return gmin < -q.bias;
  }
  if (C <= 0.0) {
    q.hit_p = pa;
    return true;
  }
  // smallest root in (0, len]: g > 0 at s = 0, so the first crossing is the smallest root
  double best = kInf;
  auto consider = [&](double s) {
    if (s >= 0.0 && s <= len) best = std::min(best, s);
  };
  double scale = std::abs(B) + std::abs(A) * len;
  if (std::abs(A) * len <= 1e-14 * scale || A == 0.0) {
    if (B < 0.0) consider(-C / B);
  } else {
    double disc = B * B - 4.0 * A * C;
    double tol = 1e-12 * (B * B + std::abs(4.0 * A * C));
    if (disc < 0.0 && disc > -tol) disc = 0.0;  // tangency lost to rounding
    if (disc >= 0.0) {
      double sq = std::sqrt(disc);
      double qq = -0.5 * (B + (B < 0.0 ? -sq : sq));
      if (qq != 0.0) {
        consider(qq / A);
        consider(C / qq);
      } else {
        consider(-B / (2.0 * A));
      }
    }
  }
  // rounding may move a crossing at the far end just outside: the far end itself is inside
  if (best == kInf && (A * len + B) * len + C <= 0.0) best = len;
  if (best == kInf) return false;
  q.hit_p = pa + best;
  return true;
}

ExactHit HeightField::intersect(double u, double v, double dsx, double dsy) const {
  ExactHit r;
  CHECK(!empty());
  if (!(std::isfinite(u) && std::isfinite(v) && std::isfinite(dsx) && std::isfinite(dsy))) {
    r.u = u;
    r.v = v;
    r.t = 1.0;
    return r;
  }
  Query q;
  q.z0 = 0.0;
  q.dz = 1.0;
  q.shadow = false;
  q.bias = 0.0;
  q.hit_p = 1.0;
  int top = static_cast<int>(levels_.size()) - 1;
  double x0 = u * ax_.size - 0.5, y0 = v * ay_.size - 0.5;
  double dx = dsx * ax_.size, dy = dsy * ay_.size;
  bool hit = for_segments(x0, dx, y0, dy, 1.0, [&](double pa, double pb, const Line& line) {
    q.line = line;
    double ca = pa, cb = pb;
    if (!clip_slab(line.x0, line.dx, 0.0, ax_.cells, ca, cb)) return false;
    if (!clip_slab(line.y0, line.dy, 0.0, ay_.cells, ca, cb)) return false;
    return visit_node(q, top, 0, 0, ca, cb);
  });
  r.t = hit ? std::clamp(q.hit_p, 0.0, 1.0) : 1.0;
  r.u = u + r.t * dsx;
  r.v = v + r.t * dsy;
  r.nodes = q.nodes;
  r.cells = q.cells;
  return r;
}

bool HeightField::shadowed(double u, double v, double t, double dlx, double dly, double bias,
                           int* nodes, int* cells) const {
  CHECK(!empty());
  if (!(std::isfinite(u) && std::isfinite(v) && std::isfinite(t) && std::isfinite(dlx) &&
        std::isfinite(dly)))
    return false;
  Query q;
  q.z0 = t;
  q.dz = -1.0;
  q.shadow = true;
  q.bias = bias;
  q.hit_p = 0.0;
  int top = static_cast<int>(levels_.size()) - 1;
  double x0 = u * ax_.size - 0.5, y0 = v * ay_.size - 0.5;
  double dx = dlx * ax_.size, dy = dly * ay_.size;
  bool hit = false;
  if (t > 0.0)
    hit = for_segments(x0, dx, y0, dy, t, [&](double pa, double pb, const Line& line) {
      q.line = line;
      double ca = pa, cb = pb;
      if (!clip_slab(line.x0, line.dx, 0.0, ax_.cells, ca, cb)) return false;
      if (!clip_slab(line.y0, line.dy, 0.0, ay_.cells, ca, cb)) return false;
      return visit_node(q, top, 0, 0, ca, cb);
    });
  if (nodes) *nodes = q.nodes;
  if (cells) *cells = q.cells;
  return hit;
}

}  // namespace relief
