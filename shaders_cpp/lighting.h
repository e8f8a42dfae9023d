// Direct lighting of a shaded point in world space, shared by every plugin: Blinn-Phong (Blinn
// 1977) or the glTF 2.0 metallic-roughness BRDF (specification appendix B), as the material's
// ShadingModel says. gl/shaders/common.glsl is its GLSL twin and must stay line-for-line
// equivalent.
//
// Punctual lights follow glTF KHR_lights_punctual (docs/scene-format.md, "Lights"): a light's
// `color` is its colour times its intensity, in lux (lm/m^2, directional: the illuminance on a
// surface facing the light) or candela (lm/sr, point and spot: divided by d^2 it is the
// illuminance at distance d). Directional lights have no falloff; point and spot lights fall off
// as 1/d^2, times the specification's range window clamp(1 - (d/range)^4, 0, 1) when range > 0;
// spot lights blend between the outer and inner cone cosines with the specification's smooth
// (squared) ramp. The metallic-roughness BRDF carries the 1/pi of a Lambertian surface, so a
// white diffuse surface facing a 3.14159 lux light has radiance 1 (display white at exposure 0,
// the Khronos sample viewer's convention); Blinn-Phong has no 1/pi (radiance = albedo x
// illuminance x cos), as the papers' scenes were lit.

#if defined(RELIEF_SHADERS_CPP_LIGHTING_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_LIGHTING_H_
#undef RELIEF_SHADERS_CPP_LIGHTING_H_
#else
#define RELIEF_SHADERS_CPP_LIGHTING_H_
#endif

#include <cmath>

#include "shaders_cpp/environment.h"
#include "shaders_cpp/uniforms.h"
#include "shaders_cpp/vec.h"

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {

template <class F>
struct LightSample {
  V3<F> l;         // unit direction from the point to the light
  V3<F> radiance;  // colour times attenuation
};

template <class F>
inline LightSample<F> light_sample(const LightUniform& light, V3<F> p) {
  LightSample<F> s;
  const V3<F> color(light.color);
  // A uniform direction is normalised in float and broadcast: the same IEEE operations as over
  // the lanes, without a vector square root and division.
  if (light.type == LightType::kDirectional) {
    const V3<float> l = normalize(-V3<float>(light.direction));
    s.l = V3<F>(F(l.x), F(l.y), F(l.z));
    s.radiance = color;
    return s;
  }
  const V3<F> d = V3<F>(light.position) - p;
  const F dist2 = vmax(dot(d, d), F(1e-8f));
  s.l = normalize(d);
  F atten = F(1.0f) / dist2;
  if (light.range > 0.0f) {
    const F r = dist2 / F(light.range * light.range);
    atten = atten * saturate(F(1.0f) - r * r);
  }
  if (light.type == LightType::kSpot) {
    const V3<float> axis = normalize(V3<float>(light.direction));
    const F cd = dot(V3<F>(F(axis.x), F(axis.y), F(axis.z)), -s.l);
    const float span = std::max(light.inner_cone_cos - light.outer_cone_cos, 1e-4f);
    const F k = saturate((cd - F(light.outer_cone_cos)) / F(span));
    atten = atten * k * k;
  }
  s.radiance = color * atten;
  return s;
}

inline float pow_lane(float x, float e) {
  return std::pow(x, e);
}
// pow for the specular lobe: vpow_fast (shaders_cpp/lanes.h), written over F so the scalar and F8
// paths agree bit for bit; relative error 3e-7 * max(1, |e log2 x|) against std::pow.
template <class F>
inline F vpow(F x, float e) {
  return vpow_fast(x, e);
}

// A light as seen from point p with unit normal n: its sample, n.l and the lanes it reaches
// (n.l > 0). sum_lights' view of each light; a kernel that traces each light's self-shadow ray
// before lighting (plugins/relief_shell.h) computes the same with it.
template <class F>
struct LightToward {
  LightSample<F> ls;
  F ndotl;
  mask_t<F> lit;
};
template <class F>
inline LightToward<F> light_toward(const LightUniform& light, V3<F> p, V3<F> n) {
  const LightSample<F> ls = light_sample<F>(light, p);
  const F ndotl = dot(n, ls.l);
  return {ls, ndotl, ndotl > F(0.0f)};
}

// The indirect term `indirect` plus, for each light, its radiance x brdf_cos(l, n.l) x
// visibility(i, l, lit) on the lanes the light reaches (n.l > 0); a light no lane faces is
// skipped, visibility included.
template <class F, class Visibility, class BrdfCos>
inline V3<F> sum_lights(const FrameUniforms& frame, V3<F> p, V3<F> n, V3<F> indirect,
                        Visibility&& visibility, BrdfCos&& brdf_cos) {
  V3<F> c = indirect;
  for (int i = 0; i < frame.num_lights; ++i) {
    const LightToward<F> lt = light_toward(frame.lights[i], p, n);
    if (none(lt.lit)) continue;
    const F vis = visibility(i, lt.ls.l, lt.lit);
    const V3<F> contrib = brdf_cos(lt.ls.l, vmax(lt.ndotl, F(0.0f))) * vis;
    c += select(lt.lit, lt.ls.radiance * contrib, V3<F>(F(0.0f), F(0.0f), F(0.0f)));
  }
  return c;
}

// The diffuse light a white Lambertian surface with unit normal n reflects without direct
// light: the environment's irradiance / pi at n when the frame has one, else the constant
// `ambient`.
template <class F>
inline V3<F> ambient_light(const FrameUniforms& frame, V3<F> n) {
  if (frame.environment) return env_irradiance(*frame.environment, frame.env_view, n);
  return V3<F>(frame.ambient);
}

// Shades point p with unit normal n, seen from the eye along unit v (point -> eye): albedo x
// ambient_light x occlusion, plus the lights. visibility(i, l) returns the fraction of light i
// reaching p along l (self-shadow, shadow maps).
template <class F, class Visibility>
inline V3<F> blinn_phong(const FrameUniforms& frame, const MaterialUniforms& mat, V3<F> p, V3<F> n,
                         V3<F> v, V3<F> albedo, F occlusion, Visibility&& visibility) {
  const V3<F> indirect = albedo * ambient_light(frame, n) * occlusion;
  return sum_lights(frame, p, n, indirect, visibility, [&](V3<F> l, F ndotl) {
    const V3<F> h = normalize(l + v);
    const F spec = vpow(vmax(dot(n, h), F(0.0f)), mat.shininess) * F(mat.specular);
    return albedo * ndotl + V3<F>(spec, spec, spec);
  });
}

// What a surface is at the shaded point, before lighting: the base colour (linear, texture and
// vertex colour applied), for metallic-roughness materials metallic and roughness in [0, 1], and
// the fraction of indirect light that reaches it (occlusion texture, height-field occlusion).
template <class F>
struct SurfaceColor {
  V3<F> albedo;
  F metallic, roughness;  // set for metallic-roughness materials only
  F occlusion = F(1.0f);  // multiplies the indirect term only
};

// The glTF 2.0 metallic-roughness BRDF (specification appendix B) times cos(theta_l) for one light
// direction l: c_diff = base (1 - metallic), f0 = lerp(0.04, base, metallic), alpha = roughness^2,
// Schlick's F = f0 + (1 - f0)(1 - v.h)^5, the GGX (Trowbridge-Reitz) D = alpha^2 / (pi
// ((n.h)^2 (alpha^2 - 1) + 1)^2) (evaluated in a form without cancellation), the height-correlated
// Smith visibility V = 0.5 / (n.l sqrt((n.v)^2 (1 - alpha^2) + alpha^2) + n.v sqrt((n.l)^2 (1 -
// alpha^2) + alpha^2)); returns
// ((1 - F) c_diff / pi + F D V) n.l. n.v is clamped to [0, 1]: a normal-mapped normal may face
// away from the eye, and with alpha >= kMinGgxAlpha and n.l > 0 the sum stays finite.
// What the BRDF needs of a surface and view that no light changes: made once per fragment.
template <class F>
struct BrdfSurface {
  V3<F> f0, diffuse;  // Fresnel at normal incidence; c_diff / pi
  F alpha, a2, nv;    // GGX alpha (clamped), alpha^2, n.v clamped to [0, 1]
};

template <class F>
inline BrdfSurface<F> brdf_surface(const SurfaceColor<F>& s, V3<F> n, V3<F> v) {
  constexpr float kInvPi = 0.318309886f;
  BrdfSurface<F> b;
  const F metallic = saturate(s.metallic);
  b.alpha = vmax(saturate(s.roughness) * saturate(s.roughness), F(kMinGgxAlpha));
  b.a2 = b.alpha * b.alpha;
  b.nv = saturate(dot(n, v));
  const F dielectric = F(0.04f) * (F(1.0f) - metallic);
  b.f0 = V3<F>(dielectric, dielectric, dielectric) + s.albedo * metallic;
  b.diffuse = s.albedo * ((F(1.0f) - metallic) * F(kInvPi));
  return b;
}

// The BRDF times n.l for light direction l, from the fragment's brdf_surface.
template <class F>
inline V3<F> metallic_roughness_brdf_cos(const BrdfSurface<F>& b, V3<F> n, V3<F> v, V3<F> l,
                                         F ndotl) {
  constexpr float kInvPi = 0.318309886f;
  const F alpha = b.alpha, a2 = b.a2, nv = b.nv;
  const V3<F> h = normalize(l + v);
  const F nh = saturate(dot(n, h));
  const F vh = saturate(dot(v, h));
  const F m = F(1.0f) - vh;
  const F m5 = (m * m) * (m * m) * m;
  const V3<F> fresnel = b.f0 + (V3<F>(F(1.0f), F(1.0f), F(1.0f)) - b.f0) * m5;
  // D as alpha^2 / (pi (sin^2 + (n.h alpha)^2)^2), sin^2 = 1 - (n.h)^2 = |n x h|^2 without the
  // cancellation of 1 - (n.h)^2 near the peak (Filament's form; 1e-3 relative at alpha 0.01)
  // (>= alpha^2 for a unit h; the bound also keeps h = 0, l = -v, finite)
  const V3<F> nxh = cross(n, h);
  const F k = alpha / vmax(dot(nxh, nxh) + (nh * alpha) * (nh * alpha), a2);
  const F d = k * k * F(kInvPi);
  const F gv = ndotl * vsqrt(nv * nv * (F(1.0f) - a2) + a2);
  const F gl = nv * vsqrt(ndotl * ndotl * (F(1.0f) - a2) + a2);
  const F vis = F(0.5f) / vmax(gv + gl, F(1e-12f));
  const V3<F> one(F(1.0f), F(1.0f), F(1.0f));
  return ((one - fresnel) * b.diffuse + fresnel * (d * vis)) * ndotl;
}

// The same for a surface colour (tests; one light).
template <class F>
inline V3<F> metallic_roughness_brdf_cos(const SurfaceColor<F>& s, V3<F> n, V3<F> v, V3<F> l,
                                         F ndotl) {
  return metallic_roughness_brdf_cos(brdf_surface(s, n, v), n, v, l, ndotl);
}

// The indirect light a metallic-roughness surface reflects toward v, before occlusion. Without an
// environment: base colour x ambient (a constant environment's first-order look, as before
// image-based light). With one, the split-sum image-based light of the Khronos glTF sample
// viewer (single scattering): specular = prefiltered radiance along reflect(-v, n) at the
// roughness x (f0 A + B), and the diffuse c_diff x irradiance/pi x (1 - (f0 A + B)), the light
// the specular lobe did not take. A white dielectric in a constant white environment then
// returns 1 and a white metal A + B <= 1 (the documented single-scattering loss).
template <class F>
inline V3<F> metallic_roughness_indirect(const FrameUniforms& frame, V3<F> n, V3<F> v,
                                         const SurfaceColor<F>& s, const BrdfSurface<F>& b) {
  if (!frame.environment) return s.albedo * V3<F>(frame.ambient);
  const EnvironmentMaps& env = *frame.environment;
  const F rough = saturate(s.roughness);
  const V2<F> ab = env_brdf(env, b.nv, rough);
  const V3<F> spec_weight = b.f0 * ab.x + V3<F>(ab.y, ab.y, ab.y);
  const V3<F> r = n * (F(2.0f) * dot(n, v)) - v;
  const V3<F> specular = env_specular(env, frame.env_view, r, rough) * spec_weight;
  const V3<F> c_diff = s.albedo * (F(1.0f) - saturate(s.metallic));
  const V3<F> one(F(1.0f), F(1.0f), F(1.0f));
  const V3<F> diffuse = c_diff * env_irradiance(env, frame.env_view, n) * (one - spec_weight);
  return diffuse + specular;
}

// The metallic-roughness counterpart of blinn_phong: the indirect term x occlusion plus each
// light's BRDF x cos x radiance x visibility.
template <class F, class Visibility>
inline V3<F> metallic_roughness(const FrameUniforms& frame, V3<F> p, V3<F> n, V3<F> v,
                                const SurfaceColor<F>& s, Visibility&& visibility) {
  const BrdfSurface<F> b = brdf_surface(s, n, v);  // once, whatever the number of lights
  const V3<F> indirect = metallic_roughness_indirect(frame, n, v, s, b) * s.occlusion;
  return sum_lights(frame, p, n, indirect, visibility, [&](V3<F> l, F ndotl) {
    return metallic_roughness_brdf_cos(b, n, v, l, ndotl);
  });
}

// The light at p by the material's shading model: the lights plus the indirect term.
template <class F, class Visibility>
inline V3<F> shade_direct(const FrameUniforms& frame, const MaterialUniforms& mat, V3<F> p, V3<F> n,
                          V3<F> v, const SurfaceColor<F>& s, Visibility&& visibility) {
  if (mat.shading == ShadingModel::kMetallicRoughness)
    return metallic_roughness(frame, p, n, v, s, visibility);
  return blinn_phong(frame, mat, p, n, v, s.albedo, s.occlusion, visibility);
}

template <class F>
struct NoShadow {
  F operator()(int, V3<F>, mask_t<F>) const { return F(1.0f); }
};

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_LIGHTING_H_
