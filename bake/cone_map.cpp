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

#include "rasterizer/check.h"
#include "rasterizer/thread_pool.h"

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
  std::vector<float> d;  // level 0, row-major

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

Field read_field(const Texture& depth, bool wrap) {
  CHECK(!depth.empty());
  Field f;
  f.w = depth.width(0);
  f.h = depth.height(0);
  f.wrap = wrap;
  f.d.resize(static_cast<size_t>(f.w) * f.h);
  for (int y = 0; y < f.h; ++y)
    for (int x = 0; x < f.w; ++x) f.d[static_cast<size_t>(y) * f.w + x] = depth.fetch_r(0, x, y);
  return f;
}

// Relaxed pair: the parameter t > 1 at which the ray from (c_i, 0) through S_j first comes out of
// the surface, or 0 if it does not before t_cap. Cells are walked exactly: crossing k along x is
// at t = 1 + (k + 1/2) / |ox|.
float relaxed_exit(const Field& f, int x, int y, int ox, int oy, float dj, float t_cap) {
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

// ---- brute force: every pair ----

void brute_texel(const Field& f, const ConeBakeOptions& o, int x, int y, float* out) {
  const float di = f.at(x, y);
  const float R = o.max_ratio;
  float r[4] = {R, R, R, R};
  int ox0, ox1, oy0, oy1;
  if (f.wrap) {
    // Offsets with D >= R d_i give ratios >= R: the box |ox| <= R d_i w, |oy| <= R d_i h holds all
    // others.
    const int bx = static_cast<int>(std::ceil(R * di * f.w)) + 1;
    const int by = static_cast<int>(std::ceil(R * di * f.h)) + 1;
    ox0 = -bx, ox1 = bx, oy0 = -by, oy1 = by;
  } else {
    ox0 = -x, ox1 = f.w - 1 - x, oy0 = -y, oy1 = f.h - 1 - y;
  }
  for (int oy = oy0; oy <= oy1; ++oy)
    for (int ox = ox0; ox <= ox1; ++ox) {
      if (ox == 0 && oy == 0) continue;
      const float dj = f.cell(x + ox, y + oy);
      if (!(dj < di)) continue;
      const float D = f.dist(ox, oy);
      switch (o.kind) {
        case ConeKind::kConservative:
          r[0] = std::min(r[0], D / (di - dj));
          break;
        case ConeKind::kQuad: {
          const float v = D / (di - dj);
          if (ox >= 0) r[0] = std::min(r[0], v);
          if (ox <= 0) r[1] = std::min(r[1], v);
          if (oy >= 0) r[2] = std::min(r[2], v);
          if (oy <= 0) r[3] = std::min(r[3], v);
          break;
        }
        case ConeKind::kRelaxed:
          r[0] = std::min(r[0], relaxed_pair(f, x, y, ox, oy, di, dj, D, R));
          break;
      }
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
  int bx, by;         // texel offset of the tree copy (image of the map) in the tiled plane
  float dmin;         // nearest offset distance from the source texel
};

class FastBaker {
 public:
  FastBaker(const Field& f, const MinTree& t, const ConeBakeOptions& o) : f_(f), t_(t), o_(o) {}

  void texel(int x, int y, float* out) {
    const float di = f_.at(x, y);
    const float R = o_.max_ratio;
    float r[4] = {R, R, R, R};
    const int nc = channels_of(o_.kind);
    const int top = static_cast<int>(t_.levels.size()) - 1;
    stack_.clear();
    if (di > 0.0f) {
      if (f_.wrap) {
        const int ax = static_cast<int>(std::ceil(R)) + 1, ay = ax;
        for (int iy = -ay; iy <= ay; ++iy)
          for (int ix = -ax; ix <= ax; ++ix) push(x, y, top, 0, 0, ix * f_.w, iy * f_.h);
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
        // Small block: every texel.
        const int x1 = std::min(x0 + (1 << n.level), f_.w),
                  y1 = std::min(y0 + (1 << n.level), f_.h);
        for (int ty = y0; ty < y1; ++ty)
          for (int tx = x0; tx < x1; ++tx) {
            const int ox = tx + n.bx - x, oy = ty + n.by - y;
            if (ox == 0 && oy == 0) continue;
            const float dj = f_.at(tx, ty);
            if (!(dj < di)) continue;
            const float D = f_.dist(ox, oy);
            switch (o_.kind) {
              case ConeKind::kConservative:
                if (D > r[0] * (di - dj) * kCullSlack) break;
                r[0] = std::min(r[0], D / (di - dj));
                break;
              case ConeKind::kQuad: {
                const float v = D / (di - dj);
                if (ox >= 0) r[0] = std::min(r[0], v);
                if (ox <= 0) r[1] = std::min(r[1], v);
                if (oy >= 0) r[2] = std::min(r[2], v);
                if (oy <= 0) r[3] = std::min(r[3], v);
                break;
              }
              case ConeKind::kRelaxed:
                if (D > r[0] * (di - dj) * kCullSlack) break;
                r[0] = std::min(r[0], relaxed_pair(f_, x, y, ox, oy, di, dj, D, r[0]));
                break;
            }
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
    const int x0 = (nx << L) + bx - x, x1 = std::min((nx + 1) << L, f_.w) - 1 + bx - x;
    const int y0 = (ny << L) + by - y, y1 = std::min((ny + 1) << L, f_.h) - 1 + by - y;
    const int ox = std::clamp(0, x0, x1), oy = std::clamp(0, y0, y1);
    stack_.push_back(Node{L, nx, ny, bx, by, f_.dist(ox, oy)});
  }

  const Field& f_;
  const MinTree& t_;
  const ConeBakeOptions& o_;
  std::vector<Node> stack_;
};

}  // namespace

ConeRatios bake_cone_ratios_brute_force(const Texture& depth, const ConeBakeOptions& options) {
  check_options(options);
  const Field f = read_field(depth, options.wrap);
  ConeRatios out;
  out.width = f.w;
  out.height = f.h;
  out.channels = channels_of(options.kind);
  out.values.resize(static_cast<size_t>(f.w) * f.h * out.channels);
  for_rows(f.h, options.threads, options.progress, [&](int y) {
    for (int x = 0; x < f.w; ++x)
      brute_texel(f, options, x, y, &out.values[(static_cast<size_t>(y) * f.w + x) * out.channels]);
  });
  return out;
}

ConeRatios bake_cone_ratios(const Texture& depth, const ConeBakeOptions& options) {
  check_options(options);
  const Field f = read_field(depth, options.wrap);
  const MinTree tree = build_tree(f);
  ConeRatios out;
  out.width = f.w;
  out.height = f.h;
  out.channels = channels_of(options.kind);
  out.values.resize(static_cast<size_t>(f.w) * f.h * out.channels);
  for_rows(f.h, options.threads, options.progress, [&](int y) {
    FastBaker baker(f, tree, options);
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
