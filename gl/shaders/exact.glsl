// Twin of shaders_cpp/exact_trace.h and shaders_cpp/exact_trace.cpp: the first intersection of a texture-space
// ray with the bilinearly reconstructed height field, by top-down traversal of a max-mip (Tevs,
// Ihrke and Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field
// Rendering", I3D 2008) and a closed-form solve of the ray against each candidate bilinear patch.
// Arithmetic is double, as in C++; the C++ recursion (visit_node) is an explicit stack here that
// visits the same nodes in the same order (children sorted by entry parameter, stable), so the
// node and cell counts match the CPU's.
//
// The field arrives in the HeightFieldBuffer storage block, built by gl/height_field.cpp from the
// same texels HeightField::from_texture reads (level 0 of the depth texture, the sampler's wraps):
// the expanded texels (period_u x period_v, row-major) at hf_data[0], then the max-mip levels,
// level 0 holding one minimum per cell. Conventions of shaders_cpp/exact_trace.h: texel (i, j) holds
// depth at its centre; repeat and mirror are periodic (mirror with period 2 * size), clamp
// extends the edge texels; a cell is the square between four texel centres.

layout(std430, binding = kHeightFieldBinding) readonly buffer HeightFieldBuffer {
  int hf_periodic[2];  // per axis: u, v
  int hf_size[2];      // texels per uv unit
  int hf_period[2];    // texels of the expanded field
  int hf_cells[2];     // leaf cells
  int hf_num_levels;
  int hf_level_offset[kMaxFieldLevels];  // first value of each level in hf_data
  int hf_nx[kMaxFieldLevels];
  int hf_ny[kMaxFieldLevels];
  float hf_data[];
};

const double kBoxEps = 1e-9LF;
double exact_inf() { return double(uintBitsToFloat(0x7f800000u)); }

struct Axis {
  bool periodic;
  int size, period, cells;
  double extent;  // cell-space domain: [0, period) periodic, [0, size - 1] clamp
};
Axis field_axis(int a) {
  Axis x;
  x.periodic = hf_periodic[a] != 0;
  x.size = hf_size[a];
  x.period = hf_period[a];
  x.cells = hf_cells[a];
  x.extent = x.periodic ? double(x.period) : double(x.size - 1);
  return x;
}

float field_texel(int i, int j) { return hf_data[j * hf_period[0] + i]; }
float field_node(int level, int i, int j) {
  return hf_data[hf_level_offset[level] + j * hf_nx[level] + i];
}
int field_corner(Axis a, int i) {
  return a.periodic ? (i + 1 == a.period ? 0 : i + 1) : min(i + 1, a.size - 1);
}

// Clips p in [pa, pb] to x0 + dx p in [lo, hi]; false if empty.
bool clip_slab(double x0, double dx, double lo, double hi, inout double pa, inout double pb) {
  lo -= kBoxEps;
  hi += kBoxEps;
  if (dx == 0.0LF) return x0 >= lo && x0 <= hi;
  double p0 = (lo - x0) / dx, p1 = (hi - x0) / dx;
  if (p0 > p1) {
    double s = p0;
    p0 = p1;
    p1 = s;
  }
  pa = max(pa, p0);
  pb = min(pb, p1);
  return pa <= pb;
}

// One axis of a line through the periodic or clamped domain (exact_trace.cpp AxisWalk).
struct AxisWalk {
  bool periodic;
  double x0, dx, extent;
  int k, k_end;  // periodic: current period index and last one
  int region;    // clamp: -1 below 0, 0 inside, 1 above extent
};
int walk_region_of(AxisWalk w, double x, double d) {
  if (x < 0.0LF || (x == 0.0LF && d < 0.0LF)) return -1;
  if (x > w.extent || (x == w.extent && d > 0.0LF)) return 1;
  return 0;
}
AxisWalk axis_walk(bool periodic, double x0, double dx, double extent, double pmax) {
  AxisWalk w = AxisWalk(periodic, x0, dx, extent, 0, 0, 0);
  if (periodic) {
    w.k = int(floor(x0 / extent));
    w.k_end = int(floor((x0 + dx * pmax) / extent));
    if (dx == 0.0LF) w.k_end = w.k;
  } else {
    w.region = walk_region_of(w, x0, dx);
  }
  return w;
}
// Parameter of the next breakpoint, +inf if none.
double walk_next(AxisWalk w) {
  if (w.periodic) {
    if (w.k == w.k_end) return exact_inf();
    double b = w.dx > 0.0LF ? double(w.k + 1) * w.extent : double(w.k) * w.extent;
    return (b - w.x0) / w.dx;
  }
  if (w.dx > 0.0LF) {
    if (w.region == -1) return (0.0LF - w.x0) / w.dx;
    if (w.region == 0) return (w.extent - w.x0) / w.dx;
  } else if (w.dx < 0.0LF) {
    if (w.region == 1) return (w.extent - w.x0) / w.dx;
    if (w.region == 0) return (0.0LF - w.x0) / w.dx;
  }
  return exact_inf();
}
void walk_advance(inout AxisWalk w) {
  if (w.periodic)
    w.k += w.dx > 0.0LF ? 1 : -1;
  else
    w.region += w.dx > 0.0LF ? 1 : -1;
}
// The mapped line of the current segment: (x0, dx).
dvec2 walk_mapped(AxisWalk w) {
  if (w.periodic) return dvec2(w.x0 - double(w.k) * w.extent, w.dx);
  if (w.region == 0) return dvec2(w.x0, w.dx);
  return dvec2(w.region < 0 ? 0.0LF : w.extent, 0.0LF);
}

// The traversal state (exact_trace.cpp Query), one query at a time per fragment.
Axis q_ax, q_ay;
dvec2 q_line_x, q_line_y;  // mapped line of the current segment: (x0, dx), (y0, dy)
double q_z0, q_dz;         // ray depth at parameter p: z0 + dz p
bool q_shadow;             // false: first p with D <= z; true: any p with D - z < -bias
double q_bias;
double q_hit_p;
int q_nodes, q_cells;

bool solve_cell(int i, int j, double pa, double pb) {
  ++q_cells;
  int i1 = field_corner(q_ax, i), j1 = field_corner(q_ay, j);
  double z00 = double(field_texel(i, j)), z10 = double(field_texel(i1, j));
  double z01 = double(field_texel(i, j1)), z11 = double(field_texel(i1, j1));
  double e = z10 - z00, f = z01 - z00, k = z00 - z10 - z01 + z11;
  // local coordinates at pa, and their rates; s = p - pa in [0, len]
  double fx = q_line_x.x + q_line_x.y * pa - double(i), fy = q_line_y.x + q_line_y.y * pa - double(j);
  double bx = q_line_x.y, by = q_line_y.y;
  double len = pb - pa;
  // g(s) = D - z = A s^2 + B s + C
  double A = k * bx * by;
  double B = e * bx + f * by + k * (fx * by + fy * bx) - q_dz;
  double C = z00 + e * fx + f * fy + k * fx * fy - (q_z0 + q_dz * pa);
  if (q_shadow) {
    double gmin = min(C, (A * len + B) * len + C);
    if (A > 0.0LF) {
      double sv = -B / (2.0LF * A);
      if (sv > 0.0LF && sv < len) gmin = min(gmin, C - B * B / (4.0LF * A));
    }
    return gmin < -q_bias;
  }
  if (C <= 0.0LF) {
    q_hit_p = pa;
    return true;
  }
  // smallest root in (0, len]: g > 0 at s = 0, so the first crossing is the smallest root
  double inf = exact_inf();
  double best = inf;
  double roots[2] = double[2](-1.0LF, -1.0LF);
  double scale = abs(B) + abs(A) * len;
  if (abs(A) * len <= 1e-14LF * scale || A == 0.0LF) {
    if (B < 0.0LF) roots[0] = -C / B;
  } else {
    double disc = B * B - 4.0LF * A * C;
    double tol = 1e-12LF * (B * B + abs(4.0LF * A * C));
    if (disc < 0.0LF && disc > -tol) disc = 0.0LF;  // tangency lost to rounding
    if (disc >= 0.0LF) {
      double sq = sqrt(disc);
      double qq = -0.5LF * (B + (B < 0.0LF ? -sq : sq));
      if (qq != 0.0LF) {
        roots[0] = qq / A;
        roots[1] = C / qq;
      } else {
        roots[0] = -B / (2.0LF * A);
      }
    }
  }
  for (int r = 0; r < 2; ++r)
    if (roots[r] >= 0.0LF && roots[r] <= len) best = min(best, roots[r]);
  // rounding may move a crossing at the far end just outside: the far end itself is inside
  if (best == inf && (A * len + B) * len + C <= 0.0LF) best = len;
  if (best == inf) return false;
  q_hit_p = pa + best;
  return true;
}

// Depth-first traversal from the root over [pa, pb] of the current segment: exact_trace.cpp visit_node
// with its recursion unrolled onto a stack (at most 3 pending siblings per level).
const int kTraversalStack = 3 * kMaxFieldLevels;
bool visit_tree(double root_pa, double root_pb) {
  int st_level[kTraversalStack], st_i[kTraversalStack], st_j[kTraversalStack];
  double st_pa[kTraversalStack], st_pb[kTraversalStack];
  int sp = 1;
  st_level[0] = hf_num_levels - 1;
  st_i[0] = 0;
  st_j[0] = 0;
  st_pa[0] = root_pa;
  st_pb[0] = root_pb;
  while (sp > 0) {
    --sp;
    int level = st_level[sp], i = st_i[sp], j = st_j[sp];
    double pa = st_pa[sp], pb = st_pb[sp];
    ++q_nodes;
    double zmin = double(field_node(level, i, j));
    double za = q_z0 + q_dz * pa, zb = q_z0 + q_dz * pb;
    if (!q_shadow) {
      // the ray is above the whole node until its depth reaches the node's minimum
      if (zmin > zb) continue;
      if (zmin > za) pa = max(pa, (zmin - q_z0) / q_dz);
      if (pa > pb) continue;
    } else if (zmin - max(za, zb) >= -q_bias) {
      continue;
    }
    if (level == 0) {
      if (solve_cell(i, j, pa, pb)) return true;
      continue;
    }
    // children in the order the ray enters them (a stable insertion sort, as std::sort does on
    // four elements)
    int kid_i[4], kid_j[4];
    double kid_pa[4], kid_pb[4];
    int n = 0;
    int span = 1 << (level - 1);
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) {
        int ci = 2 * i + di, cj = 2 * j + dj;
        if (ci >= hf_nx[level - 1] || cj >= hf_ny[level - 1]) continue;
        double x0 = double(ci) * double(span), y0 = double(cj) * double(span);
        double x1 = min(x0 + double(span), double(q_ax.cells));
        double y1 = min(y0 + double(span), double(q_ay.cells));
        double ca = pa, cb = pb;
        if (!clip_slab(q_line_x.x, q_line_x.y, x0, x1, ca, cb)) continue;
        if (!clip_slab(q_line_y.x, q_line_y.y, y0, y1, ca, cb)) continue;
        int k = n;
        for (; k > 0 && kid_pa[k - 1] > ca; --k) {
          kid_i[k] = kid_i[k - 1];
          kid_j[k] = kid_j[k - 1];
          kid_pa[k] = kid_pa[k - 1];
          kid_pb[k] = kid_pb[k - 1];
        }
        kid_i[k] = ci;
        kid_j[k] = cj;
        kid_pa[k] = ca;
        kid_pb[k] = cb;
        ++n;
      }
    // pushed last to first, so the first child is visited next
    for (int k = n - 1; k >= 0 && sp < kTraversalStack; --k) {
      st_level[sp] = level - 1;
      st_i[sp] = kid_i[k];
      st_j[sp] = kid_j[k];
      st_pa[sp] = kid_pa[k];
      st_pb[sp] = kid_pb[k];
      ++sp;
    }
  }
  return false;
}

// A bound on the segments of one ray that no valid input reaches (a ray crosses at most a few
// thousand periods), so that bad input cannot hang the device.
const int kMaxSegments = 1 << 20;

// Splits p in [0, pmax] where either axis's mapping changes (exact_trace.cpp for_segments) and traverses
// each piece, clipped to the domain, until one hits.
bool traverse_segments(double x0, double dx, double y0, double dy, double pmax) {
  AxisWalk wx = axis_walk(q_ax.periodic, x0, dx, q_ax.extent, pmax);
  AxisWalk wy = axis_walk(q_ay.periodic, y0, dy, q_ay.extent, pmax);
  double pa = 0.0LF;
  for (int s = 0; s < kMaxSegments; ++s) {
    double nx = walk_next(wx), ny = walk_next(wy);
    double pb = min(min(nx, ny), pmax);
    pb = max(pb, pa);
    q_line_x = walk_mapped(wx);
    q_line_y = walk_mapped(wy);
    double ca = pa, cb = pb;
    if (clip_slab(q_line_x.x, q_line_x.y, 0.0LF, double(q_ax.cells), ca, cb) &&
        clip_slab(q_line_y.x, q_line_y.y, 0.0LF, double(q_ay.cells), ca, cb) && visit_tree(ca, cb))
      return true;
    if (pb >= pmax) return false;
    if (nx <= pb) walk_advance(wx);
    if (ny <= pb) walk_advance(wy);
    pa = pb;
  }
  return false;
}

bool finite_d(double x) { return !isnan(x) && !isinf(x); }

void start_query(double z0, double dz, bool shadow_ray, double bias) {
  q_ax = field_axis(0);
  q_ay = field_axis(1);
  q_z0 = z0;
  q_dz = dz;
  q_shadow = shadow_ray;
  q_bias = bias;
  q_hit_p = shadow_ray ? 0.0LF : 1.0LF;
  q_nodes = 0;
  q_cells = 0;
}

// HeightField::intersect: first hit of (u, v) + t (dsx, dsy), t in [0, 1]; returns (u, v, t).
dvec3 field_intersect(double u, double v, double dsx, double dsy) {
  start_query(0.0LF, 1.0LF, false, 0.0LF);
  if (!(finite_d(u) && finite_d(v) && finite_d(dsx) && finite_d(dsy))) return dvec3(u, v, 1.0LF);
  double x0 = u * double(q_ax.size) - 0.5LF, y0 = v * double(q_ay.size) - 0.5LF;
  double dx = dsx * double(q_ax.size), dy = dsy * double(q_ay.size);
  bool hit = traverse_segments(x0, dx, y0, dy, 1.0LF);
  double t = hit ? clamp(q_hit_p, 0.0LF, 1.0LF) : 1.0LF;
  return dvec3(u + t * dsx, v + t * dsy, t);
}

// HeightField::shadowed: whether the shadow ray from (u, v) at depth t passes under the surface by
// more than bias.
bool field_shadowed(double u, double v, double t, double dlx, double dly, double bias) {
  start_query(t, -1.0LF, true, bias);
  if (!(finite_d(u) && finite_d(v) && finite_d(t) && finite_d(dlx) && finite_d(dly))) return false;
  double x0 = u * double(q_ax.size) - 0.5LF, y0 = v * double(q_ay.size) - 0.5LF;
  double dx = dlx * double(q_ax.size), dy = dly * double(q_ay.size);
  bool hit = false;
  if (t > 0.0LF) hit = traverse_segments(x0, dx, y0, dy, t);
  return hit;
}

// exact_search: the exact hit rounded to float; steps = nodes visited, fetches = nodes + 4 per
// patch solved.
SearchHit exact_search(vec2 uv, vec2 ds) {
  dvec3 h = field_intersect(double(uv.x), double(uv.y), double(ds.x), double(ds.y));
  return SearchHit(vec2(float(h.x), float(h.y)), float(h.z), float(q_nodes),
                   float(q_nodes + 4 * q_cells));
}

// exact_shadow: hard visibility (1 lit, 0 shadowed); L.z <= 0 is shadowed. steps = nodes visited.
float exact_shadow(vec2 uv, float t, vec2 dl, float lz, float bias, out float steps) {
  steps = 0.0;
  if (!(lz > 0.0)) return 0.0;
  bool sh = field_shadowed(double(uv.x), double(uv.y), double(t), double(dl.x), double(dl.y),
                           double(bias));
  steps = float(q_nodes);
  return sh ? 0.0 : 1.0;
}
