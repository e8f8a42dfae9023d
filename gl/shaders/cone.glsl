// Twin of shaders_cpp/cone.h and plugins/cone_shell.h: cone stepping through the height field.
//   conservative cone stepping: Dummer, "Cone Step Mapping: An Iterative Ray-Heightfield
//     Intersection Algorithm", 2006;
//   quad-directional cones and relaxed cone stepping + binary search: Policarpo and Oliveira,
//     "Relaxed Cone Stepping for Relief Mapping", GPU Gems 3, ch. 18, 2007 (section 18.4.2,
//     equations 1-4, listing 18-3 and figure 18-10).
// Each function keeps its C++ name and follows it operation by operation; change both together.
//
// The cone map is texture slot kConeSlot (the twin defines it from the generated prelude's
// kSlot_<technique>_<cone slot> before including this file); gl/gl_backend.cpp uploads it as
// 32-bit float of the values Texture::fetch decodes (RGBA16F and R32F maps lose nothing), and the
// depth slot as R32F. Cone maps and the relaxed march's depth are read with the CPU's nearest-texel rule
// exactly (rasterizer/texture.cpp: level by GL's MIPMAP_NEAREST choice, floor(u * size), the
// sampler's wrap) through texelFetch, so no driver rounding of nearest coordinates enters. The
// march's filtered depth is the CPU's sample_r_lod too, re-done on texelFetch (sample_r_lod_cpu):
// a cone step stops where h = D - t <= 0, and on a light ray entering above a flat top (D = 0)
// llvmpipe's filter weights (a few 1e-7 off the CPU's) decided that test the other way on 3% of
// the pixels of `plane`.
// texture_sampler[slot] holds the slot's (filter, wrap_u, wrap_v) as rasterizer/texture.h's
// Filter and Wrap values (kFilter*, kWrap*: the generated prelude).

uniform ivec3 texture_sampler[kMaxTextureSlots];

// Depth units an occluder must rise above the shadow ray (plugins/cone_shell.h).
const float kConeShadowBias = 0.001;

#include "wrap.glsl"

// rasterizer/texture.cpp: sanitize_lod, nearest_level, scaled_coord.
float sanitize_lod(float lod) { return isnan(lod) ? 0.0 : clamp(lod, -64.0, 64.0); }
int nearest_level(float lod, int q) {
  if (q == 0 || lod <= 0.5) return 0;
  if (lod > float(q) + 0.5) return q;
  return min(int(ceil(lod + 0.5)) - 1, q);
}
float scaled_coord(float u, int size, float offset) {
  if (isnan(u)) u = 0.0;
  precise float x = u * float(size) - offset;
  return clamp(x, -67108864.0, 67108864.0);
}

// The size of a mip level. Not textureSize(t, level): llvmpipe answers it with the first lane's
// level for every lane (measured: 40 of 47k plane pixels, where the lanes of one SIMD group sit
// on both sides of an integer LOD, read the wrong level). GL's chain: max(1, size >> level).
ivec2 level_size(int slot, int level) { return max(textureSize(textures[slot], 0) >> level, 1); }

// sample_nearest of one level: the texel under uv.
vec4 sample_nearest_level(int slot, vec2 uv, int level) {
  ivec2 size = level_size(slot, level);
  ivec3 s = texture_sampler[slot];
  int x = wrap_texel(int(floor(scaled_coord(uv.x, size.x, 0.0))), size.x, s.y);
  int y = wrap_texel(int(floor(scaled_coord(uv.y, size.y, 0.0))), size.y, s.z);
  return texelFetch(textures[slot], ivec2(x, y), level);
}

// sample_lod with Filter::kNearest: the texel under uv on the level nearest lod.
vec4 sample_nearest(int slot, vec2 uv, float lod) {
  int level = nearest_level(sanitize_lod(lod), textureQueryLevels(textures[slot]) - 1);
  return sample_nearest_level(slot, uv, level);
}

// sample_bilinear, first channel, in the CPU's lerp form (constant regions stay exact).
float sample_bilinear_r(int slot, vec2 uv, int level) {
  ivec2 size = level_size(slot, level);
  ivec3 s = texture_sampler[slot];
  float xf = scaled_coord(uv.x, size.x, 0.5);
  float yf = scaled_coord(uv.y, size.y, 0.5);
  float fx = floor(xf), fy = floor(yf);
  precise float a = xf - fx;
  precise float b = yf - fy;
  int ix = int(fx), iy = int(fy);
  ivec2 xs = wrap_pair(ix, size.x, s.y), ys = wrap_pair(iy, size.y, s.z);
  int x0 = xs.x, x1 = xs.y, y0 = ys.x, y1 = ys.y;
  float t00 = texelFetch(textures[slot], ivec2(x0, y0), level).r;
  float t10 = texelFetch(textures[slot], ivec2(x1, y0), level).r;
  float t01 = texelFetch(textures[slot], ivec2(x0, y1), level).r;
  float t11 = texelFetch(textures[slot], ivec2(x1, y1), level).r;
  precise float top = t00 + a * (t10 - t00);
  precise float bottom = t01 + a * (t11 - t01);
  precise float r = top + b * (bottom - top);
  return r;
}

// rasterizer/texture.cpp sample_r_lod: the slot's filter (anisotropic as trilinear) at lod.
// The level (or the two levels and the weight of the second) is chosen first and the levels are
// read in a loop that stops after the first where no lane blends: llvmpipe runs every read of a
// function on every lane, masked, but leaves a loop once no lane is in it, and compiles a loop's
// body once. With a read per case this function was half of the cone twins' time there.
float sample_r_lod_cpu(int slot, vec2 uv, float lod) {
  lod = sanitize_lod(lod);
  int q = textureQueryLevels(textures[slot]) - 1;
  int filter_ = texture_sampler[slot].x;
  bool nearest = filter_ == kFilterNearest;
  int level = 0;
  bool blend = false;
  precise float f = 0.0;
  if (q == 0 || lod <= 0.0) {
    level = 0;
  } else if (nearest || filter_ == kFilterBilinear) {
    level = nearest_level(lod, q);
  } else if (lod >= float(q)) {
    level = q;
  } else {
    float fl = floor(lod);
    level = int(fl);
    f = lod - fl;
    blend = f != 0.0;
  }
  if (nearest) return sample_nearest_level(slot, uv, level).r;
  float t1 = 0.0, t2 = 0.0;
  for (int k = 0; k < 2; ++k) {
    float t = sample_bilinear_r(slot, uv, level + k);
    if (k == 0)
      t1 = t;
    else
      t2 = t;
    if (!blend) break;
  }
  if (!blend) return t1;
  precise float r = t1 + f * (t2 - t1);
  return r;
}

// A cone source (TextureCone, or QuadTextureCone when quad) at the depth map's LOD; cu, cv are
// QuadTextureCone::aim's channels (0: +u, 1: -u; 2: +v, 3: -v).
struct ConeSource {
  float lod;
  bool quad;
  int cu, cv;
};

ConeSource make_cone_source(TextureDepth depth, bool quad) { return ConeSource(depth.lod, quad, 0, 2); }

ConeSource aim(ConeSource c, vec2 ds) {
  c.cu = ds.x >= 0.0 ? 0 : 1;
  c.cv = ds.y >= 0.0 ? 2 : 3;
  return c;
}

float cone_ratio(ConeSource c, vec2 p) {
  vec4 r = sample_nearest(kConeSlot, p, c.lod);
  if (!c.quad) return r.x;
  float a = r[c.cu], b = r[c.cv];
  return a < b ? b : a;
}

// The march's depth: the material's filtering, or (nearest) NearestTextureDepth's texel.
float march_depth(TextureDepth depth, bool nearest, vec2 p) {
  return nearest ? sample_nearest(kDepthSlot, p, depth.lod).r
                 : sample_r_lod_cpu(kDepthSlot, p, depth.lod);
}

// What a cone step reads at p: the depth and the cone ratio; one step and two fetches.
struct ConeTexel {
  float depth;
  float ratio;
};
ConeTexel cone_texel(TextureDepth depth, bool nearest, ConeSource cone, vec2 p, inout float steps,
                     inout float fetches) {
  steps += 1.0;
  fetches += 2.0;
  return ConeTexel(march_depth(depth, nearest, p), cone_ratio(cone, p));
}

// cone_march_state: n cone steps from depth 0, capped at t_max; two fetches per step. Returns
// where it stopped (t), the last sample outside (t_out) and whether the sample at t was inside.
struct ConeMarch {
  float t, t_out;
  bool inside;
  float steps, fetches;
};
ConeMarch cone_march_state(TextureDepth depth, bool nearest, ConeSource cone, vec2 uv, vec2 ds,
                           int n, float t_max) {
  float ray_ratio = sqrt(ds.x * ds.x + ds.y * ds.y);
  ConeMarch m = ConeMarch(0.0, 0.0, false, 0.0, 0.0);
  bool marching = m.t < t_max;
  for (int i = 0; i < n && marching; ++i) {
    ConeTexel c = cone_texel(depth, nearest, cone, uv + ds * m.t, m.steps, m.fetches);
    float r = c.ratio;
    float h = c.depth - m.t;
    m.inside = !(h > 0.0);
    marching = h > 0.0;
    if (marching) m.t_out = m.t;
    // distance to the cone's surface along the ray (equation 3)
    float den = ray_ratio + r;
    bool moves = marching && den > 0.0;
    float step_ = r * h / (moves ? den : 1.0);
    m.t = moves ? min(m.t + step_, t_max) : m.t;
    marching = marching && m.t < t_max;
  }
  return m;
}

SearchHit cone_march(TextureDepth depth, bool nearest, ConeSource cone, vec2 uv, vec2 ds, int n,
                     float t_max) {
  ConeMarch m = cone_march_state(depth, nearest, cone, uv, ds, n, t_max);
  return SearchHit(uv + ds * m.t, m.t, m.steps, m.fetches);
}

// half_texel_along: half a texel of the depth map along a ray of uv step ds, in units of t.
float half_texel_along(vec2 ds) {
  ivec2 size = textureSize(textures[kDepthSlot], 0);
  float len = sqrt(ds.x * ds.x + ds.y * ds.y) * float(max(size.x, size.y));
  return 0.5 / max(len, 1e-6);
}

// cone_finish: the bracket-safe end of a march on the material's depth (sample_r_lod_cpu, the
// field the march read): a lane left outside takes k more cone steps of at least
// (t_max - t) / k (on a view ray at most view_floor, the first fallback_ramp(k) ramped up from
// 1/2^16 of that); a view ray they leave short of t_max then
// takes k even samples over the rest), then t_max (inside on a view ray: bottom); m halvings of [last outside, first inside]; returns the inside end, or t_max with
// found false.
// shaders_cpp/cone.h fallback_ramp and ramped_floor: fallback step j < ramp = min(16, k / 2) of a
// view ray takes at least min(floor, view_floor / 2^(ramp - j)) (ldexp: exact powers of two).
const int kFallbackRamp = 16;
int fallback_ramp(int k) { return min(k / 2, kFallbackRamp); }
float ramped_floor(int j, int ramp, float floor_, float view_floor) {
  return j < ramp ? min(floor_, view_floor * ldexp(1.0, j - ramp)) : floor_;
}

SearchHit cone_finish(TextureDepth depth, ConeSource cone, vec2 uv, vec2 ds, ConeMarch mr, int k,
                      int m, float t_max, bool bottom, float view_floor, out bool found) {
  float ray_ratio = sqrt(ds.x * ds.x + ds.y * ds.y);
  float lo = mr.t_out, hi = mr.t;
  float steps = mr.steps, fetches = mr.fetches;
  found = mr.inside;
  bool searching = !mr.inside && mr.t < t_max;
  float floor_ = (t_max - mr.t) * (1.0 / float(k));
  if (bottom) floor_ = min(floor_, view_floor);
  int ramp = fallback_ramp(k);
  float s = mr.t;
  for (int j = 0; j < k && searching; ++j) {
    ConeTexel c = cone_texel(depth, false, cone, uv + ds * s, steps, fetches);
    float h = c.depth - s;
    if (!(h > 0.0)) {
      found = true;
      hi = s;
      searching = false;
    } else {
      lo = s;
      float den = ray_ratio + c.ratio;
      float step_ = max(c.ratio * h / (den > 0.0 ? den : 1.0),
                        bottom ? ramped_floor(j, ramp, floor_, view_floor) : floor_);
      s = min(s + step_, t_max);
      searching = s < t_max;
    }
  }
  if (bottom && searching) {
    // the short steps did not finish: k even samples over the rest, [s, t_max)
    float s0 = s, rest = t_max - s;
    for (int j = 0; j < k && searching; ++j) {
      float u = s0 + rest * (float(j) / float(k));
      float d = march_depth(depth, false, uv + ds * u);
      steps += 1.0;
      fetches += 1.0;
      if (d <= u) {
        found = true;
        hi = u;
        searching = false;
      } else {
        lo = u;
      }
    }
  }
  if (!found) {
    hi = t_max;
    found = bottom;
  }
  bool refine = found && hi > lo;
  for (int i = 0; i < m && refine; ++i) {
    float mid = (lo + hi) * 0.5;
    if (march_depth(depth, false, uv + ds * mid) <= mid)
      hi = mid;
    else
      lo = mid;
    steps += 1.0;
    fetches += 1.0;
  }
  return SearchHit(uv + ds * hi, hi, steps, fetches);
}

// cone_search: the view ray of all three cone techniques (n cone steps, k fallback steps, m
// halvings).
SearchHit cone_search(TextureDepth depth, ConeSource cone, vec2 uv, vec2 ds, int n, int k, int m) {
  ConeMarch mr = cone_march_state(depth, false, cone, uv, ds, n, 1.0);
  bool found;
  return cone_finish(depth, cone, uv, ds, mr, k, m, 1.0, true, half_texel_along(ds), found);
}

// light_ray_shadow + cone_light_visibility: the light ray from the surface above the hit (one
// depth fetch), lowered by kConeShadowBias, enters the depth range at uv + dl t_max and is
// searched down to t_max (cone_occluder_search: the march, then the linear fallback); a sample
// inside is shadow. Called on lit fragments only (the C++ `lit` mask).
float cone_light_visibility(TextureDepth depth, ConeSource cone, SearchHit hit, vec2 dl, float lz,
                            int n, int k, inout ShadeOut o) {
  bool lit_side = lz > 0.0;
  // from the surface above the hit (plugins/cone_shell.h): one depth fetch
  float surface = min(hit.depth, march_depth(depth, false, hit.uv));
  o.fetches += 1.0;
  float t_max = surface - kConeShadowBias;
  bool trace = lit_side && t_max > 0.0;
  float vis = lit_side ? 1.0 : 0.0;
  if (!trace) return vis;
  vec2 entry = hit.uv + dl * t_max;
  vec2 down = vec2(0.0 - dl.x, 0.0 - dl.y);
  if (cone.quad) cone = aim(cone, down);
  ConeMarch mr = cone_march_state(depth, false, cone, entry, down, n, t_max);
  bool found;
  SearchHit h = cone_finish(depth, cone, entry, down, mr, k, 0, t_max, false, 0.0, found);
  o.shadow_steps += h.steps;
  o.fetches += h.fetches;
  return found ? 0.0 : vis;
}
