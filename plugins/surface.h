// Surface reads every shading plugin shares: the base colour and the tangent-space normal map at a
// texture coordinate, with the quad's uv derivatives (texture_grad), and Blinn-Phong lighting with
// or without the lights' shadow maps. flat, normal and the relief shell (plugins/relief_shell.h)
// call these, so the slot conventions and the fetch counts are the same everywhere.
#pragma once

#include "plugins/shading.h"
#include "shaders_cpp/lighting.h"
#include "shaders_cpp/sampling_simd.h"
#include "shaders_cpp/shadow_map.h"

namespace relief {

inline constexpr TextureSlotSpec kBaseColorSlotSpec = {
    "base_color", false, "sRGB base colour, multiplied by the material's base colour"};
inline constexpr TextureSlotSpec kNormalSlotSpec = {
    "normal", false, "tangent-space normal map (x along +u, y along +v, z out), linear RGB"};

// The fragment's tangent frame, re-orthonormalised, its normal flipped on back faces.
template <class F> TangentFrame<F> fragment_frame(const FragIn<F>& in) {
  V3<F> geo_n = in.normal;
  if (!in.front_facing) geo_n = -geo_n;
  return make_tangent_frame(geo_n, in.tangent, in.tangent_sign);
}

// The material's base colour times the texture in `slot` (when bound) at uv; adds one fetch.
template <class F>
V3<F> sample_albedo(const MaterialUniforms& m, int slot, const V2<F>& uv, const FragIn<F>& in,
                    F& fetches) {
  V3<F> albedo(glm::vec3(m.base_color));
  if (const Texture* t = m.textures[slot]) {
    const V4<F> c = texture_grad_call(*t, m.samplers[slot], uv, in.duv_dx, in.duv_dy);
    albedo = albedo * c.xyz();
    fetches += F(1.0f);
  }
  return albedo;
}

// The world normal from the tangent-space normal map in `slot` at uv, its x and y scaled by
// `strength` before renormalising (1: the map as is); tf.n when no map is bound. Adds one fetch.
template <class F>
V3<F> sample_normal_map(const MaterialUniforms& m, int slot, const TangentFrame<F>& tf,
                        const V2<F>& uv, const FragIn<F>& in, F strength, F& fetches) {
  const Texture* t = m.textures[slot];
  if (!t) return tf.n;
  const V4<F> c = texture_grad_call(*t, m.samplers[slot], uv, in.duv_dx, in.duv_dy);
  fetches += F(1.0f);
  return normalize(tf.to_world(V3<F>((c.x * F(2.0f) - F(1.0f)) * strength,
                                     (c.y * F(2.0f) - F(1.0f)) * strength,
                                     c.z * F(2.0f) - F(1.0f))));
}

// Unit direction from the fragment at p to the eye: normalize(eye - p) for perspective views, the
// reversed view direction for orthographic ones (where every eye ray is parallel).
template <class F> V3<F> to_eye(const FrameUniforms& frame, const V3<F>& p) {
  return frame.orthographic ? V3<F>(-frame.view_dir) : normalize(V3<F>(frame.eye) - p);
}

// Blinn-Phong at p for the frame's lights; with kReceive, each light's shadow map (if it has one)
// is compared against the plane through p with normal `receiver_n` (counted into `fetches`).
template <bool kReceive, class F>
V3<F> shade_lights(const ShadeContext& ctx, const V3<F>& p, const V3<F>& n,
                   const V3<F>& receiver_n, const V3<F>& v, const V3<F>& albedo, F& fetches) {
  if constexpr (kReceive)
    return blinn_phong(*ctx.frame, *ctx.material, p, n, v, albedo,
                       ShadowMapReceiver<F>{*ctx.frame, p, receiver_n, fetches});
  else
    return blinn_phong(*ctx.frame, *ctx.material, p, n, v, albedo, NoShadow<F>());
}

}  // namespace relief
