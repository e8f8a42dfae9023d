// Cone maps for cone step mapping, baked from a depth map.
//   Conservative cones: Dummer 2006, "Cone Step Mapping: An Iterative Ray-Heightfield Intersection
//   Algorithm". Quad-directional cones and relaxed cones: Policarpo & Oliveira 2007, "Relaxed Cone
//   Stepping for Relief Mapping", GPU Gems 3 ch. 18 (listings 18-1 and 18-2).
//
// Coordinates. The depth map (first channel of level 0, values in [0,1], 0 = top reference surface,
// 1 = deepest) spans uv [0,1]^2; texel (x, y) stands for the surface point
// S = (c.u, c.v, d) with c = ((x + 0.5) / w, (y + 0.5) / h) and d its depth. Distances are measured
// in uv (so a non-square map has different texel spacings along u and v), depth in [0,1]; a ratio
// is width / height of a cone in these units. Each ratio is clamped to `max_ratio`.
// Destinations. Every definition below takes the minimum over "other texels" j, given as integer
// texel offsets o = (ox, oy) != 0 from the source texel i: with `wrap` over the whole tiled plane
// (the map repeated; the depth at an offset is that of texel ((x+ox) mod w, (y+oy) mod h)),
// otherwise over the texels of the map. D(o) = sqrt((ox/w)^2 + (oy/h)^2), d_i, d_j the two depths.
// Only destinations with d_j < d_i constrain a cone (a texel at or below the apex never enters it).
//
// Conservative (one ratio):  r_i = min(max_ratio, min_j D(o) / (d_i - d_j)) -- the widest upward
//   cone with apex at S_i that holds no texel surface point S_j strictly inside it.
// Quad-directional (four ratios): the same minimum restricted to the closed half-planes
//   channel 0: ox >= 0 (+u), 1: ox <= 0 (-u), 2: oy >= 0 (+v, increasing rows), 3: oy <= 0 (-v).
//   A ray whose uv direction has du >= 0 and dv >= 0 stays in both closed half-planes +u and +v,
//   so max(r[+u], r[+v]) is a safe ratio for it (and likewise for the other quadrants).
// Relaxed (one ratio), listing 18-2 (the chapter's shader; listing 18-1 is its pseudocode, whose
//   printed ratio expression and test are garbled -- they do not use the exit point's depth
//   against the source's -- so the shader's formula is the one implemented): for each destination
//   j, the ray from src = (c_i, 0) (above texel i on the reference plane) through dst = S_j is
//   followed beyond dst, E(t) = src + t (dst - src), t >= 1, depth t d_j, until it first comes out
//   of the surface: the first t > 1 at which it enters a texel cell whose depth is greater than the
//   ray's depth t d_j (the height field is the nearest-texel one, texel (x, y) covering
//   [x, x+1) x [y, y+1) in texel units; cells beyond a clamped border repeat the border texel; a
//   ray through a cell corner passes straight to the diagonal cell). If that exit point E is above
//   the apex (t d_j < d_i) the cone must leave it outside:
//     r(i, j) = |E.uv - c_i| / (d_i - E.depth) = t D(o) / (d_i - t d_j),
//   otherwise j does not constrain. r_i = min(max_ratio, min_j r(i, j)). So a viewing ray inside
//   the cone that has entered the surface cannot come back out inside the cone (at the sampled
//   destinations), which is what the binary search after relaxed cone stepping needs. The listing
//   searches 128 fixed steps with bilinear depth; here the exit is found exactly (cell by cell).
//   Since t >= 1 and t D / (d_i - t d_j) grows with t, r(i, j) >= D / (d_i - d_j): a relaxed cone
//   is never narrower than the conservative one, and exits with r >= max_ratio need not be found
//   (the march stops at t D / (d_i - t d_j) = max_ratio).
//
// Bilinear-safe conservative and quad cones (`bilinear`). The kernels (shaders_cpp/cone.h) step
//   from a ray point p at the bilinear depth D(p) with the ratio of the texel whose cell (the
//   texel's square, [x, x + 1) x [y, y + 1) in texel units) holds p. For that never to cross the
//   bilinear surface (the field the exact reference intersects), r_i must hold for every apex
//   (p, D(p)) with p in cell i: no bilinear surface point strictly inside. Bound used:
//     r_i = min(max_ratio, 1 / L_i, min over patches P not touching cell i of
//               gap(cell i, P) / (A_i - m_P)),
//   L_i: the steepest gradient (depth per uv) of the 4 patches around texel i (a ray point and a
//   surface point both in them are joined inside them), A_i: the bilinear maximum over cell i,
//   m_P: the minimum corner of patch P (the square between four texel centres), gap: the uv
//   distance between the cell and the patch. Quad channels keep the patches a ray leaving the cell
//   in that direction can reach. These cones are narrower than texel-point ones near features.
// Bilinear-safe relaxed cones (`bilinear` with kRelaxed; issue 22). The chapter's relaxed cones
//   only consider rays that pass the cone's axis at depth 0 and exits on the nearest-texel field;
//   a relaxed step on the bilinear field from a ray point deeper than that can pass a whole
//   one-texel wall (a tent two texels wide on the bilinear field) and come out beyond it: the
//   wrong-layer hits of thin walls. Exact condition: a step runs from the ray's point (p, t) on the
//   cone's axis, outside (t < D(p)), straight to the cone's boundary, in the ray's uv direction
//   dir; it can enter the surface and come out again only if it comes out at a surface point E
//   inside the cone, where the ray's depth grows more slowly than the surface's along dir:
//   dD/d(dir)(E) > (depth per uv of the ray) > 0. Rays of every slope leave the axis (grazing
//   views), so the cone must hold no surface point above the apex where the surface descends
//   radially, g(E) . (E - p) > 0 (g: the bilinear gradient). Then a step that ends outside crossed
//   no surface and a step that ends inside crossed it exactly once: the bracket [last outside,
//   first inside] holds the first hit, for any view, on the field the kernels sample. Bound used:
//   the conservative bilinear bound above restricted to the patches P with
//   max over apexes p in cell i and points q in P of g(q) . (q - p) > 0 (linear in p, bilinear
//   in q, so a test of the 4 x 4 corner pairs), and the near bound 1 / L only when one of the 4
//   near patches passes that test above the deepest apex. Never narrower than bilinear conservative
//   cones; wider where the surface faces the apex (the near side of a bump or wall), equal where
//   the walls are one texel thick (both sides are within a texel).
//
// Two bakers per kind give the same floats: the brute-force one (all pairs, the test oracle) and
// the fast one (a min-depth quadtree bounds whole blocks of destinations: a block whose nearest
// offset D_min and minimum depth m satisfy D_min >= r (d_i - m) cannot lower the current r and is
// skipped; children are visited nearest first; rows are spread over a relief::ThreadPool).
#pragma once

#include <functional>
#include <vector>

#include "rasterizer/texture.h"

namespace relief {

enum class ConeKind { kConservative, kQuad, kRelaxed };
const char* cone_kind_name(ConeKind kind);

struct ConeBakeOptions {
  ConeKind kind = ConeKind::kRelaxed;
  float max_ratio = 1.0f;  // > 0; the chapter clamps at 1 to store ratios in 8 bits
  bool wrap = false;       // tiling map (repeat) vs clamp at the borders
  // Cones safe for the bilinear surface (see above) instead of the texel points (conservative,
  // quad) or the chapter's nearest-texel exits (relaxed).
  bool bilinear = false;
  int threads = 0;  // <= 0: hardware concurrency (fast baker only)
  // Called on the calling thread with non-decreasing fractions in [0, 1], ending with 1.
  std::function<void(float fraction)> progress;
};

// Raw ratios, row-major, `channels` per texel (1, or 4 for kQuad in the order +u, -u, +v, -v).
struct ConeRatios {
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<float> values;
  float at(int x, int y, int c = 0) const {
    return values[(static_cast<size_t>(y) * width + x) * channels + c];
  }
};

// Precondition: depth not empty, options.max_ratio > 0 and finite.
ConeRatios bake_cone_ratios(const Texture& depth, const ConeBakeOptions& options);
ConeRatios bake_cone_ratios_brute_force(const Texture& depth, const ConeBakeOptions& options);

// One relaxed pair value r(i, j) as defined above (for the tests): source texel (x, y), offset
// (ox, oy); returns +infinity when j does not constrain (or only with r >= max_ratio).
float relaxed_pair_ratio(const Texture& depth, int x, int y, int ox, int oy, float max_ratio,
                         bool wrap);

// The texture: R32F (one channel) or RGBA16F (quad), each value rounded down to the format so the
// stored cone is never wider than the baked one; with `min_mips`, a mip chain where each texel is
// the minimum of its 2x2 block (Texture::generate_mips(MipReduce::kMin)).
Texture cone_ratios_to_texture(const ConeRatios& ratios, bool min_mips = true);

// bake_cone_ratios + cone_ratios_to_texture.
Texture bake_cone_map(const Texture& depth, const ConeBakeOptions& options, bool min_mips = true);

}  // namespace relief
