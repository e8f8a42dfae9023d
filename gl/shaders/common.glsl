// Shared by every GLSL twin: the fragment ABI of plugins/plugin.h and plugins/shading.h, the
// tangent frame of shaders_cpp/frame.h, the lighting of shaders_cpp/lighting.h (Blinn 1977, glTF
// metallic-roughness) and the image-based light lookups of shaders_cpp/environment.h. Each function keeps its C++ name and follows it line by line; change both
// together.
//
// Interface (set by gl/gl_backend.cpp):
//   uniform FrameUniforms frame        camera and lights of the pass (FrameUniforms)
//   uniform MaterialUniforms material  params[] in schema order, base colour, specular, shininess
//   textures[slot], has_texture[slot]  the material's textures by slot index (TextureSlotSpec order)
//   vary[kCountGl / 4]                 the varyings (namespace varying), padded to kCountGl
// Constants shared with C++ come from the generated prelude.glsl (included below; the names in
// docs/plugins.md, "Adding a built-in technique"); a twin includes it first, to define its
// parameter and slot indices from them.
// Variant defines (0 or 1): EFFECT_SELF_SHADOW, EFFECT_DEPTH_WRITE, EFFECT_SILHOUETTE,
// EFFECT_SHADOW_PASS, EFFECT_RECEIVE_SHADOW, RELIEF_WRITES_DEPTH (the variant's DepthOutput is not
// kNone), RELIEF_AOVS (the pass writes AOVs); optional, 0 when absent: RELIEF_DEPTH_FARTHER (the
// DepthOutput is kFarther: gl_FragDepth is declared depth_less, reversed-Z farther = smaller, so
// the polygon depth stays a conservative early test as on the CPU) and RELIEF_COUNT (the work
// counters of WorkCounters go to the WorkCountersBuffer storage block, binding 0).
//
// Coordinates: gl_FragCoord is redeclared origin_upper_left so x, y match the CPU's (pixel
// centres, rows top to bottom). GL's window y runs up while image rows run down, so the image-space
// derivative the CPU calls dFdy is -dFdyCoarse here (load_fragment does it).

layout(origin_upper_left) in vec4 gl_FragCoord;

#ifndef RELIEF_DEPTH_FARTHER
#define RELIEF_DEPTH_FARTHER 0
#endif
#ifndef RELIEF_COUNT
#define RELIEF_COUNT 0
#endif
#if RELIEF_WRITES_DEPTH && RELIEF_DEPTH_FARTHER
layout(depth_less) out float gl_FragDepth;
#endif
#ifndef RELIEF_MAY_DISCARD
#define RELIEF_MAY_DISCARD 0
#endif
#ifndef RELIEF_ALPHA_TEST
#define RELIEF_ALPHA_TEST 0  // gl_backend.cpp: 1 for MASK materials, which discard below the cutoff
#endif
#if !RELIEF_WRITES_DEPTH && !RELIEF_MAY_DISCARD && !RELIEF_ALPHA_TEST
// The CPU tests depth before shading when the shader writes none (DepthTest::kEarly); GL would
// run a shader with side effects (the RELIEF_COUNT atomics) before the test, counting fragments
// the CPU never shades. Not in a twin that discards (it defines RELIEF_MAY_DISCARD 1 before
// including this file: relief_quadric, relief_dual): early tests write the depth of every
// fragment that passes them, discarded or not, where the CPU writes none for a discarded one;
// such a twin, like a depth-writing one, counts the fragments hidden behind earlier surfaces too.
layout(early_fragment_tests) in;
#endif

// The limits, light kinds, varying layout (kPosition .. kCountGl) and alpha modes of
// shaders_cpp/uniforms.h, generated from it at build time (gl/tools/glsl_prelude.cpp).
#include "prelude.glsl"

struct LightUniform {
  int type;
  vec3 position;
  vec3 direction;
  vec3 color;
  float range;
  float inner_cone_cos;
  float outer_cone_cos;
};

struct FrameUniforms {
  mat4 view;
  mat4 view_proj;
  vec3 eye;
  bool orthographic;
  vec3 view_dir;
  vec3 ambient;  // the indirect light when there is no environment
  // Image-based light (shaders_cpp/environment_maps.h; gl_programs.cpp sets them from
  // FrameUniforms::environment and env_view): SH of irradiance / pi, the rotation's (cos, sin),
  // the intensity and the specular chain's last level (levels - 1).
  bool has_environment;
  vec3 env_sh[kEnvShCount];
  vec2 env_rotation;
  float env_intensity;
  float env_max_lod;
  LightUniform lights[kMaxLights];
  int num_lights;
  int width;
  int height;
};

// plugins/plugin.h UvMap: uv' = col0 * uv.x + col1 * uv.y + offset from uv (set 0) or uv1 (set 1).
struct UvMap {
  vec2 col0;
  vec2 col1;
  vec2 offset;
  int set;
  bool identity;
};

struct MaterialUniforms {
  float params[kMaxParams];
  vec4 base_color;
  int shading;  // plugins/plugin.h ShadingModel: kShadingBlinnPhong, kShadingMetallicRoughness
  float specular;
  float shininess;
  float metallic;
  float roughness;
  bool has_metallic_roughness_texture;
  UvMap metallic_roughness_uv;
  int alpha_mode;  // plugins/plugin.h AlphaMode: kAlphaOpaque, kAlphaMask, kAlphaBlend
  float alpha_cutoff;
  // glTF material terms (plugins/plugin.h MaterialUniforms; finish_surface below)
  UvMap uv_maps[kMaxTextureSlots];
  vec3 emissive;
  bool has_emissive_texture;
  UvMap emissive_uv;
  bool has_occlusion_texture;
  UvMap occlusion_uv;
  float occlusion_strength;
  float normal_scale;
  bool unlit;
};

uniform FrameUniforms frame;
uniform MaterialUniforms material;
layout(binding = 0) uniform sampler2D textures[kMaxTextureSlots];
uniform bool has_texture[kMaxTextureSlots];
// Material-wide textures (gl_backend.cpp kEmissiveUnit, kOcclusionUnit, kMetallicRoughnessUnit).
layout(binding = kEmissiveUnit) uniform sampler2D emissive_texture;
layout(binding = kOcclusionUnit) uniform sampler2D occlusion_texture;
layout(binding = kMetallicRoughnessUnit) uniform sampler2D metallic_roughness_texture;
// The environment's prefiltered specular chain (trilinear, clamp to edge) and split-sum table
// (bilinear, clamp to edge), bound by gl_passes.cpp when the frame has an environment.
layout(binding = kEnvSpecularUnit) uniform sampler2D env_specular_map;
layout(binding = kEnvBrdfUnit) uniform sampler2D env_brdf_lut;

in vec4 vary[kCountGl / 4];

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_aov0;  // uv.xy, hit_depth, steps
layout(location = 2) out vec4 out_aov1;  // normal.xyz

// The CPU rasterizer's interpolation (rasterizer/pipeline.h cpu_triangle_planes): per triangle
// of the draw a header (offset of its first part, number of parts: the triangles the CPU's setup
// makes of it after clipping), then per part (x0, y0), its corners in pixels and (c, dx, dy) of
// the planes depth, 1/w and the header's count of varyings (16, or kCountGl with COLOR_0 or
// TEXCOORD_1: header[2]) times 1/w, evaluated as the CPU does at whole-pixel
// offsets from (x0, y0), in the same float operations. A pixel of a clipped triangle takes the
// part whose corners hold its centre (helper pixels: the nearest). tri_base < 0 (warm-up draws)
// or no part falls back to GL's own interpolation.
layout(std430, binding = kTrianglePlanesBinding) readonly buffer TrianglePlanesBuffer { float tri_planes[]; };
uniform int tri_base;
float exact_vary[kCountGl];
float exact_z;
bool use_exact = false;

float edge_side(vec2 a, vec2 b, vec2 p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

void interpolate_like_cpu() {
  use_exact = false;
  if (tri_base < 0) return;
  int h = (tri_base + gl_PrimitiveID) * kTriangleHeader;
  int first = floatBitsToInt(tri_planes[h]), n = floatBitsToInt(tri_planes[h + 1]);
  if (n <= 0) return;
  int nv = floatBitsToInt(tri_planes[h + 2]);
  int kPartFloats = 8 + (2 + nv) * 3;
  int o = first;
  if (n > 1) {
    vec2 pc = floor(gl_FragCoord.xy) + 0.5;
    float best = -3.0e38;
    for (int i = 0; i < n; ++i) {
      int q = first + i * kPartFloats;
      vec2 a = vec2(tri_planes[q + 2], tri_planes[q + 3]);
      vec2 b = vec2(tri_planes[q + 4], tri_planes[q + 5]);
      vec2 c = vec2(tri_planes[q + 6], tri_planes[q + 7]);
      float m = min(min(edge_side(a, b, pc), edge_side(b, c, pc)), edge_side(c, a, pc));
      if (m > best) {
        best = m;
        o = q;
      }
    }
  }
  float fx = float(int(gl_FragCoord.x) - floatBitsToInt(tri_planes[o]));
  float fy = float(int(gl_FragCoord.y) - floatBitsToInt(tri_planes[o + 1]));
  o += 8;
  precise float z = (tri_planes[o] + tri_planes[o + 1] * fx) + tri_planes[o + 2] * fy;
  exact_z = clamp(z, 0.0, 1.0);
  precise float iw = (tri_planes[o + 3] + tri_planes[o + 4] * fx) + tri_planes[o + 5] * fy;
  iw = iw < 1e-30 ? 1e-30 : iw;  // helper lanes far outside may pass the horizon
  precise float wv = 1.0 / iw;
  for (int k = 0; k < nv; ++k) {
    int c = o + 6 + 3 * k;
    precise float v = ((tri_planes[c] + tri_planes[c + 1] * fx) + tri_planes[c + 2] * fy) * wv;
    exact_vary[k] = v;
  }
  for (int k = nv; k < kCountGl; ++k) exact_vary[k] = k < kUv1 ? 1.0 : 0.0;
  use_exact = true;
}

float varying_at(int k) { return use_exact ? exact_vary[k] : vary[k >> 2][k & 3]; }

// ---- shaders_cpp/vec.h ----
// Normalises; a zero vector stays zero (no NaN). GLSL's normalize() would return NaN.
vec3 normalize_safe(vec3 a) {
  float len2 = dot(a, a);
  float inv = len2 > 1e-30 ? 1.0 / sqrt(max(len2, 1e-30)) : 0.0;
  return a * inv;
}

// ---- plugins/shading.h ----
struct FragIn {
  vec3 position;  // world
  vec3 normal;    // world, interpolated (not unit)
  vec3 tangent;   // world, interpolated
  float tangent_sign;
  vec2 uv;
  vec2 duv_dx, duv_dy;  // per quad (coarse), image-space rows top to bottom
  vec2 quadric;
  vec2 tile_scale;
  vec4 color;  // vertex colour (COLOR_0), 1 when the mesh has none
  vec2 uv1;    // TEXCOORD_1, 0 when the mesh has none
  vec2 duv1_dx, duv1_dy;
  float frag_z;  // polygon depth (reversed-Z)
  bool front_facing;
};

struct ShadeOut {
  vec3 color;
  float alpha;
  float depth;  // read when the variant writes depth
  bool discarded;
  vec2 hit_uv;
  float hit_depth;
  float steps;
  vec3 shading_normal;
  float fetches;
  float shadow_steps;
};

ShadeOut shade_out_default() {
  ShadeOut o;
  o.color = vec3(0.0);
  o.alpha = 1.0;
  o.depth = 0.0;
  o.discarded = false;
  o.hit_uv = vec2(0.0);
  o.hit_depth = 0.0;
  o.steps = 0.0;
  o.shading_normal = vec3(0.0, 0.0, 1.0);
  o.fetches = 0.0;
  o.shadow_steps = 0.0;
  return o;
}

FragIn load_fragment() {
  interpolate_like_cpu();
  FragIn f;
  f.position = vec3(varying_at(kPosition), varying_at(kPosition + 1), varying_at(kPosition + 2));
  f.normal = vec3(varying_at(kNormal), varying_at(kNormal + 1), varying_at(kNormal + 2));
  f.tangent = vec3(varying_at(kTangent), varying_at(kTangent + 1), varying_at(kTangent + 2));
  f.tangent_sign = varying_at(kTangent + 3);
  f.uv = vec2(varying_at(kUv), varying_at(kUv + 1));
  vec2 fx = dFdxFine(f.uv), fy = -dFdyFine(f.uv), cross_ = -dFdyFine(fx);
  bool bottom = (int(gl_FragCoord.y) & 1) != 0, right = (int(gl_FragCoord.x) & 1) != 0;
  f.duv_dx = fx - (bottom ? cross_ : vec2(0.0));
  f.duv_dy = fy - (right ? cross_ : vec2(0.0));
  f.quadric = vec2(varying_at(kQuadric), varying_at(kQuadric + 1));
  f.tile_scale = vec2(varying_at(kTileScale), varying_at(kTileScale + 1));
  f.color = vec4(varying_at(kColor), varying_at(kColor + 1), varying_at(kColor + 2),
                 varying_at(kColor + 3));
  f.uv1 = vec2(varying_at(kUv1), varying_at(kUv1 + 1));
  vec2 fx1 = dFdxFine(f.uv1), fy1 = -dFdyFine(f.uv1), cross1 = -dFdyFine(fx1);
  f.duv1_dx = fx1 - (bottom ? cross1 : vec2(0.0));
  f.duv1_dy = fy1 - (right ? cross1 : vec2(0.0));
  f.frag_z = use_exact ? exact_z : gl_FragCoord.z;
  f.front_facing = gl_FrontFacing;
  return f;
}

// ---- plugins/surface.h: texture coordinates per texture, final colour terms ----
// map_uv: a texture's coordinates at the varying-space uv (identity: uv itself), derivatives by
// the map's linear part. Returns uv; dx, dy out.
vec2 map_uv(UvMap m, vec2 uv, FragIn in_, out vec2 dx, out vec2 dy) {
  if (m.identity) {
    dx = in_.duv_dx;
    dy = in_.duv_dy;
    return uv;
  }
  bool s1 = m.set == 1;
  vec2 u = s1 ? in_.uv1 : uv;
  vec2 ux = s1 ? in_.duv1_dx : in_.duv_dx;
  vec2 uy = s1 ? in_.duv1_dy : in_.duv_dy;
  dx = m.col0 * ux.x + m.col1 * ux.y;
  dy = m.col0 * uy.x + m.col1 * uy.y;
  return (m.col0 * u.x + m.col1 * u.y) + m.offset;
}

// sample_slot: the texture in `slot` at the varying-space uv through the slot's UvMap.
vec4 sample_slot(int slot, vec2 uv, FragIn in_) {
  vec2 dx, dy;
  vec2 t = map_uv(material.uv_maps[slot], uv, in_, dx, dy);
  return textureGrad(textures[slot], t, dx, dy);
}

// plugins/surface.h finish_surface, in two parts around the lighting. surface_occlusion: the
// SurfaceColor::occlusion the occlusion texture's red channel sets by occlusion_strength (1
// without one, or for an unlit material, which reads nothing), for shade_direct's indirect term;
// the twin calls it before lighting.
float surface_occlusion(vec2 uv, FragIn in_, inout float fetches) {
  if (material.unlit || !material.has_occlusion_texture) return 1.0;
  vec2 dx, dy;
  vec2 t = map_uv(material.occlusion_uv, uv, in_, dx, dy);
  float r = textureGrad(occlusion_texture, t, dx, dy).x;
  fetches += 1.0;
  return 1.0 + material.occlusion_strength * (r - 1.0);
}

// finish_surface: `lit` is the lit colour (occlusion applied), or albedo itself when the material
// is unlit (the twin computes `material.unlit ? albedo : shade_direct(...)`); emissive added.
vec3 finish_surface(vec3 lit, vec2 uv, vec3 albedo, FragIn in_, inout float fetches) {
  if (material.unlit) return albedo;
  vec3 c = lit;
  vec2 dx, dy;
  if (material.emissive != vec3(0.0)) {
    vec3 e = material.emissive;
    if (material.has_emissive_texture) {
      vec2 t = map_uv(material.emissive_uv, uv, in_, dx, dy);
      e = e * textureGrad(emissive_texture, t, dx, dy).xyz;
      fetches += 1.0;
    }
    c += e;
  }
  return c;
}

// plugins/surface.h sample_surface's metallic and roughness: the factors, times the
// metallicRoughness texture's blue and green at uv when bound (one fetch); (metallic, roughness).
// Blinn-Phong materials read nothing.
vec2 sample_metallic_roughness(vec2 uv, FragIn in_, inout float fetches) {
  if (material.shading != kShadingMetallicRoughness) return vec2(0.0, 1.0);
  float metallic = material.metallic;
  float roughness = material.roughness;
  if (material.has_metallic_roughness_texture) {
    vec2 dx, dy;
    vec2 t = map_uv(material.metallic_roughness_uv, uv, in_, dx, dy);
    vec4 c = textureGrad(metallic_roughness_texture, t, dx, dy);
    roughness = roughness * c.y;
    metallic = metallic * c.z;
    fetches += 1.0;
  }
  return vec2(metallic, roughness);
}

// plugins/surface.h sample_alpha: base colour factor alpha x the alpha of the base colour
// texture (in `slot`) at uv; for passes that need no colour (MASK shadow casters).
float base_alpha_at(int slot, vec2 uv, FragIn in_, inout float fetches) {
  float a = material.base_color.a;
  if (has_texture[slot]) {
    a *= sample_slot(slot, uv, in_).w;
    fetches += 1.0;
  }
  a *= in_.color.a;  // COLOR_0 (1 when the mesh has none)
  return a;
}

// plugins/shading.h resolve_alpha: MASK discards below the cutoff; OPAQUE and MASK write alpha
// 1, BLEND its alpha in [0, 1] (blended by glBlendFuncSeparate in gl_backend.cpp).
void resolve_alpha(inout ShadeOut o) {
  if (material.alpha_mode == kAlphaBlend) {
    o.alpha = clamp(o.alpha, 0.0, 1.0);
    return;
  }
  if (material.alpha_mode == kAlphaMask && o.alpha < material.alpha_cutoff) o.discarded = true;
  o.alpha = 1.0;
}

#if RELIEF_COUNT
// rasterizer/fragment.h WorkCounters, summed by the backend over kCounterSlots slots (pixels hash
// to a slot so that atomics on one address do not serialise a whole GPU).
layout(std430, binding = kCountersBinding) buffer WorkCountersBuffer { uint work_counters[]; };

void count_work(uint slot, uint counter, float n) {
  if (n > 0.0) atomicAdd(work_counters[slot * uint(kCounterCount) + counter], uint(n));
}
#endif

void store_out(ShadeOut o) {
  resolve_alpha(o);
#if RELIEF_COUNT
  uvec2 px = uvec2(gl_FragCoord.xy);
  uint slot = (px.x * 7u + px.y * 61u) % uint(kCounterSlots);
  count_work(slot, uint(kCounterFragments), 1.0);
  count_work(slot, uint(kCounterFetches), o.fetches);
  count_work(slot, uint(kCounterSearchSteps), o.steps);
  count_work(slot, uint(kCounterShadowSteps), o.shadow_steps);
  count_work(slot, uint(kCounterDiscarded), o.discarded ? 1.0 : 0.0);
#endif
  if (o.discarded) discard;
  out_color = vec4(o.color, o.alpha);
#if RELIEF_WRITES_DEPTH
  gl_FragDepth = o.depth;
#endif
#if RELIEF_AOVS
  out_aov0 = vec4(o.hit_uv, o.hit_depth, o.steps);
  out_aov1 = vec4(o.shading_normal, 0.0);
#endif
}

// ---- shaders_cpp/frame.h ----
struct TangentFrame {
  vec3 t, b, n;  // orthonormal; t along +u, b along +v, n out of the surface
};

vec3 to_tangent(TangentFrame f, vec3 w) { return vec3(dot(w, f.t), dot(w, f.b), dot(w, f.n)); }
vec3 to_world(TangentFrame f, vec3 v) { return f.t * v.x + f.b * v.y + f.n * v.z; }

// A normal-map texel in the frame's (t, b, n) coordinates (plugins/surface.h normal_from_texel):
// glTF convention, x along +u, y toward the image top (-v, so along -b), z out; x and y scaled by
// `strength` (1: the map as is). Not normalised.
vec3 normal_from_texel(vec4 c, float strength) {
  return vec3((c.x * 2.0 - 1.0) * strength, -(c.y * 2.0 - 1.0) * strength, c.z * 2.0 - 1.0);
}

// Any unit vector perpendicular to unit n (Duff et al. 2017).
vec3 any_perpendicular(vec3 n) {
  float sign_ = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (sign_ + n.z);
  float b = n.x * n.y * a;
  return vec3(1.0 + sign_ * n.x * n.x * a, sign_ * b, -sign_ * n.x);
}

TangentFrame make_tangent_frame(vec3 normal, vec3 tangent, float sign_) {
  TangentFrame f;
  vec3 n = normalize_safe(normal);
  n = dot(n, n) > 0.5 ? n : vec3(0.0, 0.0, 1.0);
  vec3 t = tangent - n * dot(n, tangent);
  float len2 = dot(t, t);
  bool good = len2 > 1e-12 * max(dot(tangent, tangent), 1e-30);
  t = good ? normalize_safe(t) : any_perpendicular(n);
  f.n = n;
  f.t = t;
  f.b = cross(n, t) * (sign_ < 0.0 ? -1.0 : 1.0);
  return f;
}

// ---- shaders_cpp/lighting.h ----
struct LightSample {
  vec3 l;         // unit direction from the point to the light
  vec3 radiance;  // colour times attenuation
};

LightSample light_sample(LightUniform light, vec3 p) {
  LightSample s;
  vec3 color = light.color;
  if (light.type == kLightDirectional) {
    s.l = normalize_safe(-light.direction);
    s.radiance = color;
    return s;
  }
  vec3 d = light.position - p;
  float dist2 = max(dot(d, d), 1e-8);
  s.l = normalize_safe(d);
  float atten = 1.0 / dist2;
  if (light.range > 0.0) {
    float r = dist2 / (light.range * light.range);
    atten = atten * clamp(1.0 - r * r, 0.0, 1.0);
  }
  if (light.type == kLightSpot) {
    float cd = dot(normalize_safe(light.direction), -s.l);
    float span = max(light.inner_cone_cos - light.outer_cone_cos, 1e-4);
    float k = clamp((cd - light.outer_cone_cos) / span, 0.0, 1.0);
    atten = atten * k * k;
  }
  s.radiance = color * atten;
  return s;
}

// The C++ `visibility` functor: each twin defines it (return 1.0 for NoShadow).
float visibility(int i, vec3 l);

// ---- shaders_cpp/environment.h ----
// +1 for x >= 0 (and +0, -0), else -1: the octahedral fold's signNotZero (not GLSL's sign).
float sign_not_zero(float x) { return x < 0.0 ? -1.0 : 1.0; }

// Octahedral uv in [0, 1]^2 of direction d (any length; zero reads as +Y).
vec2 octahedral_uv(vec3 d) {
  float sum = max(abs(d.x) + abs(d.y) + abs(d.z), 1e-30);
  float px = d.x / sum, pz = d.z / sum;
  bool lower = d.y < 0.0;
  float fx = (1.0 - abs(pz)) * sign_not_zero(px);
  float fz = (1.0 - abs(px)) * sign_not_zero(pz);
  return vec2((lower ? fx : px) * 0.5 + 0.5, (lower ? fz : pz) * 0.5 + 0.5);
}

// World direction w in the environment's frame (x' = c x - s z, z' = s x + c z).
vec3 env_direction(vec3 w) {
  float c = frame.env_rotation.x, s = frame.env_rotation.y;
  return vec3(c * w.x - s * w.z, w.y, s * w.x + c * w.z);
}

// E(n) / pi times the intensity at unit world normal n, from the 9 SH coefficients.
vec3 env_irradiance(vec3 n_world) {
  vec3 n = env_direction(n_world);
  float y[kEnvShCount];
  y[0] = 0.28209479177387814;
  y[1] = 0.48860251190291992 * n.y;
  y[2] = 0.48860251190291992 * n.z;
  y[3] = 0.48860251190291992 * n.x;
  y[4] = 1.09254843059207907 * (n.x * n.y);
  y[5] = 1.09254843059207907 * (n.y * n.z);
  y[6] = 0.31539156525252005 * (3.0 * (n.z * n.z) - 1.0);
  y[7] = 1.09254843059207907 * (n.x * n.z);
  y[8] = 0.54627421529603959 * (n.x * n.x - n.y * n.y);
  vec3 e = vec3(0.0);
  for (int i = 0; i < kEnvShCount; ++i) e += frame.env_sh[i] * y[i];
  return e * frame.env_intensity;
}

// Prefiltered radiance times the intensity along r (any length) at perceptual roughness (NaN
// reads as 0, clamped to [0, 1]): textureLod at roughness * (levels - 1).
vec3 env_specular(vec3 r, float roughness) {
  vec2 uv = octahedral_uv(env_direction(r));
  float rough = clamp(roughness == roughness ? roughness : 0.0, 0.0, 1.0);
  return textureLod(env_specular_map, uv, rough * frame.env_max_lod).xyz * frame.env_intensity;
}

// The split-sum (A, B) at NdotV and perceptual roughness, level 0 of the table.
vec2 env_brdf(float ndotv, float roughness) {
  return textureLod(env_brdf_lut, vec2(ndotv, roughness), 0.0).xy;
}

// ---- shaders_cpp/lighting.h (continued) ----
// ambient_light: irradiance / pi at n with an environment, else the constant ambient.
vec3 ambient_light(vec3 n) { return frame.has_environment ? env_irradiance(n) : frame.ambient; }

// Shades point p with unit normal n, seen from the eye along unit v (point -> eye): albedo x
// ambient_light x occlusion, plus the lights.
vec3 blinn_phong(vec3 p, vec3 n, vec3 v, vec3 albedo, float occlusion) {
  vec3 c = albedo * ambient_light(n) * occlusion;
  for (int i = 0; i < frame.num_lights; ++i) {
    LightSample ls = light_sample(frame.lights[i], p);
    float ndotl = dot(n, ls.l);
    bool lit = ndotl > 0.0;
    if (!lit) continue;
    float vis = visibility(i, ls.l);
    vec3 h = normalize_safe(ls.l + v);
    float spec = pow(max(dot(n, h), 0.0), material.shininess) * material.specular;
    float diffuse = max(ndotl, 0.0);
    vec3 contrib = (albedo * diffuse + vec3(spec, spec, spec)) * vis;
    c += ls.radiance * contrib;
  }
  return c;
}

// BrdfSurface, brdf_surface: what no light changes, made once per fragment (shaders_cpp/lighting.h).
struct BrdfSurface {
  vec3 f0, diffuse;
  float alpha, a2, nv;
};

BrdfSurface brdf_surface(vec3 albedo, vec2 mr, vec3 n, vec3 v) {
  const float kInvPi = 0.318309886;
  BrdfSurface b;
  float metallic = clamp(mr.x, 0.0, 1.0);
  b.alpha = max(clamp(mr.y, 0.0, 1.0) * clamp(mr.y, 0.0, 1.0), kMinGgxAlpha);
  b.a2 = b.alpha * b.alpha;
  b.nv = clamp(dot(n, v), 0.0, 1.0);
  float dielectric = 0.04 * (1.0 - metallic);
  b.f0 = vec3(dielectric, dielectric, dielectric) + albedo * metallic;
  b.diffuse = albedo * ((1.0 - metallic) * kInvPi);
  return b;
}

// metallic_roughness_brdf_cos: the glTF 2.0 metallic-roughness BRDF (appendix B) times n.l.
vec3 metallic_roughness_brdf_cos(BrdfSurface b, vec3 n, vec3 v, vec3 l, float ndotl) {
  const float kInvPi = 0.318309886;
  float alpha = b.alpha, a2 = b.a2, nv = b.nv;
  vec3 h = normalize_safe(l + v);
  float nh = clamp(dot(n, h), 0.0, 1.0);
  float vh = clamp(dot(v, h), 0.0, 1.0);
  float m = 1.0 - vh;
  float m5 = (m * m) * (m * m) * m;
  vec3 fresnel = b.f0 + (vec3(1.0) - b.f0) * m5;
  vec3 nxh = cross(n, h);
  float k = alpha / max(dot(nxh, nxh) + (nh * alpha) * (nh * alpha), a2);
  float d = k * k * kInvPi;
  float gv = ndotl * sqrt(nv * nv * (1.0 - a2) + a2);
  float gl = nv * sqrt(ndotl * ndotl * (1.0 - a2) + a2);
  float vis = 0.5 / max(gv + gl, 1e-12);
  return ((vec3(1.0) - fresnel) * b.diffuse + fresnel * (d * vis)) * ndotl;
}

// metallic_roughness_indirect: base colour x ambient without an environment; with one the
// split-sum specular along reflect(-v, n) x (f0 A + B) plus c_diff x irradiance x (1 - (f0 A + B)).
vec3 metallic_roughness_indirect(vec3 n, vec3 v, vec3 albedo, vec2 mr, BrdfSurface b) {
  if (!frame.has_environment) return albedo * frame.ambient;
  float rough = clamp(mr.y, 0.0, 1.0);
  vec2 ab = env_brdf(b.nv, rough);
  vec3 spec_weight = b.f0 * ab.x + vec3(ab.y);
  vec3 r = n * (2.0 * dot(n, v)) - v;
  vec3 specular = env_specular(r, rough) * spec_weight;
  vec3 c_diff = albedo * (1.0 - clamp(mr.x, 0.0, 1.0));
  vec3 diffuse = c_diff * env_irradiance(n) * (vec3(1.0) - spec_weight);
  return diffuse + specular;
}

// metallic_roughness: the indirect term x occlusion plus each light's BRDF x cos x radiance x
// visibility.
vec3 metallic_roughness(vec3 p, vec3 n, vec3 v, vec3 albedo, vec2 mr, float occlusion) {
  BrdfSurface b = brdf_surface(albedo, mr, n, v);
  vec3 c = metallic_roughness_indirect(n, v, albedo, mr, b) * occlusion;
  for (int i = 0; i < frame.num_lights; ++i) {
    LightSample ls = light_sample(frame.lights[i], p);
    float ndotl = dot(n, ls.l);
    if (!(ndotl > 0.0)) continue;
    float vis = visibility(i, ls.l);
    c += ls.radiance * (metallic_roughness_brdf_cos(b, n, v, ls.l, ndotl) * vis);
  }
  return c;
}

// shade_direct: the light at p by the material's shading model, the lights plus the indirect
// term x occlusion (mr from sample_metallic_roughness, occlusion from surface_occlusion).
vec3 shade_direct(vec3 p, vec3 n, vec3 v, vec3 albedo, vec2 mr, float occlusion) {
  if (material.shading == kShadingMetallicRoughness)
    return metallic_roughness(p, n, v, albedo, mr, occlusion);
  return blinn_phong(p, n, v, albedo, occlusion);
}
