// Surface reads every shading plugin shares: the base colour (and metallic and roughness) and the
// tangent-space normal map at a texture coordinate, with the quad's uv derivatives (texture_grad),
// and the material's lighting (Blinn-Phong or metallic-roughness) with or without the lights'
// shadow maps. flat, normal and the relief shell (plugins/relief_shell.h)
// call these, so the slot conventions and the fetch counts are the same everywhere.

#if defined(RELIEF_PLUGINS_SURFACE_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_PLUGINS_SURFACE_H_
#undef RELIEF_PLUGINS_SURFACE_H_
#else
#define RELIEF_PLUGINS_SURFACE_H_
#endif

#include "plugins/shading.h"
#include "shaders_cpp/lighting.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/shadow_lookup.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

inline constexpr TextureSlotSpec kBaseColorSlotSpec = {
    "base_color", false, "sRGB base colour, multiplied by the material's base colour"};
inline constexpr TextureSlotSpec kNormalSlotSpec = {
    "normal", false,
    "tangent-space normal map, glTF convention (x along +u, y toward the image top = -v, z out), "
    "linear RGB"};

// The fragment's tangent frame, re-orthonormalised, its normal flipped on back faces.
template <class F>
TangentFrame<F> fragment_frame(const FragIn<F>& in) {
  V3<F> geo_n = in.normal;
  if (!in.front_facing) geo_n = -geo_n;
  return make_tangent_frame(geo_n, in.tangent, in.tangent_sign);
}

// A texture's coordinates and their per-quad derivatives.
template <class F>
struct SlotUv {
  V2<F> uv, dx, dy;
};

// The coordinates of a texture whose UvMap is `map` at the (hit) uv, in the uv varying's space:
// the map's affine part applied to uv (set 0) or to the fragment's TEXCOORD_1 (set 1), the
// derivatives by its linear part. The identity is free.
template <class F>
SlotUv<F> map_uv(const UvMap& map, const V2<F>& uv, const FragIn<F>& in) {
  if (map.identity) return {uv, in.duv_dx, in.duv_dy};
  const bool s1 = map.set == 1;
  const V2<F>& u = s1 ? in.uv1 : uv;
  const V2<F>& dx = s1 ? in.duv1_dx : in.duv_dx;
  const V2<F>& dy = s1 ? in.duv1_dy : in.duv_dy;
  const V2<F> c0(map.col0), c1(map.col1);
  return {c0 * u.x + c1 * u.y + V2<F>(map.offset), c0 * dx.x + c1 * dx.y, c0 * dy.x + c1 * dy.y};
}

// The texture in `slot` (bound) at the varying-space uv, through the slot's UvMap.
template <class F>
V4<F> sample_slot(const MaterialUniforms& m, int slot, const V2<F>& uv, const FragIn<F>& in) {
  const SlotUv<F> s = map_uv(m.uv_maps[slot], uv, in);
  return texture_grad_call(*m.textures[slot], m.samplers[slot], s.uv, s.dx, s.dy, in.lod_memo);
}

// The material's base colour times the texture in `slot` (when bound) at uv times the vertex
// colour (COLOR_0, FragIn::color, when the mesh has one); adds one fetch.
// With `alpha`, also the fragment's alpha (the one definition, docs/scene-format.md "Alpha"):
// base colour factor alpha x texture alpha x vertex colour alpha.
template <class F>
V3<F> sample_albedo(const MaterialUniforms& m, int slot, const V2<F>& uv, const FragIn<F>& in,
                    F& fetches, F* alpha = nullptr) {
  V3<F> albedo(glm::vec3(m.base_color));
  F a(m.base_color.a);
  if (m.textures[slot]) {
    const V4<F> c = sample_slot(m, slot, uv, in);
    albedo = albedo * c.xyz();
    a = a * c.w;
    fetches += F(1.0f);
  }
  if (in.has_extended) {  // COLOR_0 (1 when the mesh has TEXCOORD_1 only)
    albedo = albedo * in.color.xyz();
    a = a * in.color.w;
  }
  if (alpha) *alpha = a;
  return albedo;
}

// sample_albedo, and for a metallic-roughness material its metallic and roughness factors times
// the metallicRoughness texture's blue and green channels at uv (when bound: one more fetch).
template <class F>
SurfaceColor<F> sample_surface(const MaterialUniforms& m, int slot, const V2<F>& uv,
                               const FragIn<F>& in, F& fetches, F* alpha = nullptr) {
  SurfaceColor<F> s{sample_albedo(m, slot, uv, in, fetches, alpha), F(m.metallic), F(m.roughness)};
  if (m.shading != ShadingModel::kMetallicRoughness) return s;
  if (const Texture* t = m.metallic_roughness_texture) {
    const SlotUv<F> su = map_uv(m.metallic_roughness_uv, uv, in);
    const V4<F> c =
        texture_grad_call(*t, m.metallic_roughness_sampler, su.uv, su.dx, su.dy, in.lod_memo);
    s.roughness = s.roughness * c.y;
    s.metallic = s.metallic * c.z;
    fetches += F(1.0f);
  }
  return s;
}

// The fragment's alpha alone, as sample_albedo computes it, for passes that need no colour (the
// shadow passes of MASK materials); adds one fetch when the texture is bound.
template <class F>
F sample_alpha(const MaterialUniforms& m, int slot, const V2<F>& uv, const FragIn<F>& in,
               F& fetches) {
  F a;
  sample_albedo(m, slot, uv, in, fetches, &a);
  return a;
}

// A normal-map texel c (rgb in [0, 1]) in the frame's (t, b, n) coordinates, not normalised:
// glTF convention, x along +u, y toward the image top (-v, so along -b), z out; x and y scaled by
// `strength`. The one decode of every CPU plugin (gl/shaders/common.glsl has its twin).
template <class F>
V3<F> normal_from_texel(const V4<F>& c, F strength) {
  return V3<F>((c.x * F(2.0f) - F(1.0f)) * strength, (F(1.0f) - c.y * F(2.0f)) * strength,
               c.z * F(2.0f) - F(1.0f));
}

// The world normal from the tangent-space normal map in `slot` at uv, its x and y scaled by
// `strength` times the material's normal_scale (glTF normalTexture.scale) before renormalising
// (1: the map as is); tf.n when no map is bound. Adds one fetch.
template <class F>
V3<F> sample_normal_map(const MaterialUniforms& m, int slot, const TangentFrame<F>& tf,
                        const V2<F>& uv, const FragIn<F>& in, F strength, F& fetches) {
  const Texture* t = m.textures[slot];
  if (!t) return tf.n;
  if (m.normal_scale != 1.0f) strength = strength * F(m.normal_scale);
  const V4<F> c = sample_slot(m, slot, uv, in);
  fetches += F(1.0f);
  return normalize(tf.to_world(normal_from_texel(c, strength)));
}

// Unit direction from the fragment at p to the eye: normalize(eye - p) for perspective views, the
// reversed view direction for orthographic ones (where every eye ray is parallel).
template <class F>
V3<F> to_eye(const FrameUniforms& frame, const V3<F>& p) {
  return frame.orthographic ? V3<F>(-frame.view_dir) : normalize(V3<F>(frame.eye) - p);
}

// The material's lighting (shade_direct) at p for the frame's lights; with kReceive, each light's
// shadow map (if it has one) is compared against the plane through p with normal `receiver_n`
// (counted into `fetches`).
template <bool kReceive, class F>
V3<F> shade_lights(const ShadeContext& ctx, const V3<F>& p, const V3<F>& n, const V3<F>& receiver_n,
                   const V3<F>& v, const SurfaceColor<F>& surface, F& fetches) {
  if constexpr (kReceive)
    return shade_direct(*ctx.frame, *ctx.material, p, n, v, surface,
                        ShadowMapReceiver<F>{*ctx.frame, p, receiver_n, fetches});
  else
    return shade_direct(*ctx.frame, *ctx.material, p, n, v, surface, NoShadow<F>());
}

// The material-wide terms of every plugin's final colour (glTF): `lit()` (the lit colour of
// `surface`) unless the material is unlit (then its albedo itself: no lights, no shadows, no
// other term); the occlusion texture's red channel, by occlusion_strength, sets
// surface.occlusion (which scales the indirect term only) before `lit()` runs; the emissive
// colour (times its texture) added. uv is the shown point's varying-space uv.
// gl/shaders/common.glsl finish_surface is the twin.
template <class F, class Lit>
V3<F> finish_surface(const ShadeContext& ctx, const FragIn<F>& in, const V2<F>& uv,
                     SurfaceColor<F>& surface, F& fetches, Lit&& lit) {
  const MaterialUniforms& m = *ctx.material;
  if (m.unlit) return surface.albedo;
  if (const Texture* t = m.occlusion_texture) {
    const SlotUv<F> s = map_uv(m.occlusion_uv, uv, in);
    const F r = texture_grad_call(*t, m.occlusion_sampler, s.uv, s.dx, s.dy, in.lod_memo).x;
    fetches += F(1.0f);
    surface.occlusion = surface.occlusion * (F(1.0f) + F(m.occlusion_strength) * (r - F(1.0f)));
  }
  V3<F> c = lit();
  if (m.emissive != glm::vec3(0.0f)) {
    V3<F> e(m.emissive);
    if (const Texture* t = m.emissive_texture) {
      const SlotUv<F> s = map_uv(m.emissive_uv, uv, in);
      e = e * texture_grad_call(*t, m.emissive_sampler, s.uv, s.dx, s.dy, in.lod_memo).xyz();
      fetches += F(1.0f);
    }
    c += e;
  }
  return c;
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_PLUGINS_SURFACE_H_
