// Twin of shaders_cpp/search.h: the height-field ray searches, one fragment at a time.
//   linear + binary search: Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary
//     Polygonal Surfaces", I3D 2005 (section 3; appendix ray_intersect_rm);
//   steep parallax: McGuire and McGuire, "Steep Parallax Mapping", I3D 2005 poster;
//   secant refinement: Tatarchuk, "Dynamic Parallax Occlusion Mapping with Approximate Soft
//     Shadows", I3D 2006;
//   parallax: Kaneko et al. 2001; offset limiting: Welsh 2004.
// Also compute_lod of rasterizer/texture.cpp, which the CPU's TextureDepth is built with.
//
// Conventions: see ray.glsl. A sample at depth t is inside when D(uv + ds * t) <= t. Every search
// returns the hit and the steps and fetches it made (one depth sample = one fetch), as the C++
// does per lane. Where the C++ masks lanes, a fragment here simply runs its own loop.

// kDepthSlot, the depth map's texture slot (plugins/relief_shell.h ReliefSlot), is defined by the
// twin from the generated prelude (kSlot_<technique>_depth) before it includes this file.

// rasterizer/texture.cpp: the isotropic LOD of a footprint (the larger of the two axes).
float footprint(vec2 size, vec2 d) {
  float x = d.x * size.x;
  float y = d.y * size.y;
  return sqrt(x * x + y * y);
}
float compute_lod(vec2 size, vec2 duv_dx, vec2 duv_dy) {
  float rho = max(footprint(size, duv_dx), footprint(size, duv_dy));
  if (isnan(rho)) return 0.0;
  if (rho <= 0.0) return -64.0;
  float lod = log2(rho);
  return isnan(lod) ? 0.0 : clamp(lod, -64.0, 64.0);
}

// The depth texture at a fixed LOD (computed once per quad, outside the loops): the material's
// depth map, or for lod=max-mip the derived chain in slot RELIEF_MAX_MIP_SLOT (defined by the
// twins that have a `lod` parameter). The slot is chosen by constant indices, not by indexing
// the sampler array with a variable: Mesa 22's llvmpipe crashes compiling that inside the loops.
struct TextureDepth {
  float lod;
  bool max_mip;
};
float sample_depth(TextureDepth depth, vec2 uv) {
#ifdef RELIEF_MAX_MIP_SLOT
  if (depth.max_mip) return textureLod(textures[RELIEF_MAX_MIP_SLOT], uv, depth.lod).r;
#endif
  return textureLod(textures[kDepthSlot], uv, depth.lod).r;
}

// plugins/relief_shell.h material_depth: the depth map at the per-quad LOD; a twin with a `lod`
// parameter passes its mode (SearchLod: 0 quad, 1 zero = level 0, 2 max-mip = the chain at the
// per-quad LOD; the chain has the depth map's size), others pass 0.
TextureDepth material_depth(FragIn in_, int mode) {
  TextureDepth d = TextureDepth(0.0, false);
  if (mode == 1) return d;
#ifdef RELIEF_MAX_MIP_SLOT
  d.max_mip = mode == 2 && has_texture[RELIEF_MAX_MIP_SLOT];
#endif
  d.lod = compute_lod(vec2(textureSize(textures[kDepthSlot], 0)), in_.duv_dx, in_.duv_dy);
  return d;
}

struct SearchHit {
  vec2 uv;        // hit texture coordinates (not wrapped)
  float depth;    // ray depth at the hit, [0, 1]
  float steps;    // search iterations
  float fetches;  // depth samples
};

// The last sample outside (t_out, g_out = D - t > 0; 0, 0 if none) and the first inside.
struct Bracket {
  float t_out, g_out, t_in, g_in;
};

// A bound no valid step count reaches (the schemas cap steps at 256): a NaN count cannot hang.
const int kMaxLinearSteps = 4096;

// Linear search: samples t_i = i / n for i = 0..n, stops at the first inside; t = 1 is inside.
SearchHit linear_search(TextureDepth depth, vec2 uv, vec2 ds, float n, out Bracket bracket) {
  float inv_n = 1.0 / n;
  float t_out = 0.0, g_out = 0.0, t_in = 0.0, g_in = 0.0;
  float steps = 0.0, fetches = 0.0;
  for (int i = 0; i <= kMaxLinearSteps; ++i) {
    float fi = float(i);
    bool last = fi >= n || i == kMaxLinearSteps;
    float t = last ? 1.0 : fi * inv_n;
    float d = sample_depth(depth, uv + ds * t);
    float g = last ? min(d - t, 0.0) : d - t;
    bool inside = last || g <= 0.0;
    steps += 1.0;
    fetches += 1.0;
    if (inside) {
      t_in = t;
      g_in = g;
      break;
    }
    t_out = t;
    g_out = g;
  }
  bracket = Bracket(t_out, g_out, t_in, g_in);
  return SearchHit(uv + ds * t_in, t_in, steps, fetches);
}

// Binary search (m halvings) of the bracket; returns the inside end. Adds to hit's counters.
SearchHit binary_search(TextureDepth depth, vec2 uv, vec2 ds, Bracket b, int m, SearchHit hit) {
  float lo = b.t_out, hi = b.t_in;
  bool refine = hi > lo;
  for (int i = 0; i < m && refine; ++i) {
    float mid = (lo + hi) * 0.5;
    float d = sample_depth(depth, uv + ds * mid);
    bool inside = d <= mid;
    if (inside)
      hi = mid;
    else
      lo = mid;
    hit.steps += 1.0;
    hit.fetches += 1.0;
  }
  hit.depth = hi;
  hit.uv = uv + ds * hi;
  return hit;
}

// Secant refinement (POM): the root of the line through the bracket's samples. No fetch.
SearchHit secant_refine(vec2 uv, vec2 ds, Bracket b, SearchHit hit) {
  float den = b.g_out - b.g_in;
  bool ok = den > 0.0;
  float w = b.g_out / (ok ? den : 1.0);
  float t = clamp(b.t_out + (b.t_in - b.t_out) * w, b.t_out, b.t_in);
  t = ok ? t : hit.depth;
  hit.depth = t;
  hit.uv = uv + ds * t;
  return hit;
}

// Relief mapping: linear search (n steps) then binary search (m steps).
SearchHit relief_search(TextureDepth depth, vec2 uv, vec2 ds, float n, int m) {
  Bracket b;
  SearchHit hit = linear_search(depth, uv, ds, n, b);
  return binary_search(depth, uv, ds, b, m, hit);
}

// Parallax occlusion mapping: linear search (n steps) then secant refinement.
SearchHit pom_search(TextureDepth depth, vec2 uv, vec2 ds, float n) {
  Bracket b;
  SearchHit hit = linear_search(depth, uv, ds, n, b);
  return secant_refine(uv, ds, b, hit);
}

// Steep parallax: n depth planes, the first plane sample inside, no refinement.
SearchHit steep_parallax_search(TextureDepth depth, vec2 uv, vec2 ds, float n) {
  Bracket b;
  return linear_search(depth, uv, ds, n, b);
}

// Parallax mapping: one sample d = D(uv), hit at uv + ds * d; offset limiting drops 1 / -V.z.
SearchHit parallax_offset(TextureDepth depth, vec2 uv, vec2 ds, float vz, bool offset_limiting) {
  float d = clamp(sample_depth(depth, uv), 0.0, 1.0);
  vec2 step_ = offset_limiting ? ds * clamp(-vz, 0.0, 1.0) : ds;
  return SearchHit(uv + step_ * d, d, 1.0, 1.0);
}
