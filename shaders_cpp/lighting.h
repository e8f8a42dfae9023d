// Blinn-Phong lighting (Blinn 1977) of a shaded point in world space, shared by every plugin;
// gl/shaders/common.glsl is its GLSL twin and must stay line-for-line equivalent.
//
// Punctual lights follow glTF KHR_lights_punctual: directional lights have no falloff; point and
// spot lights fall off as 1/d^2 with the range window clamp(1 - (d/range)^4, 0, 1)^2 when range >
// 0; spot lights blend between the outer and inner cone cosines.

#if defined(RELIEF_SHADERS_CPP_LIGHTING_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SHADERS_CPP_LIGHTING_H_
#undef RELIEF_SHADERS_CPP_LIGHTING_H_
#else
#define RELIEF_SHADERS_CPP_LIGHTING_H_
#endif

#include <cmath>

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
  if (light.type == LightType::kDirectional) {
    s.l = normalize(-V3<F>(light.direction));
    s.radiance = color;
    return s;
  }
  const V3<F> d = V3<F>(light.position) - p;
  const F dist2 = vmax(dot(d, d), F(1e-8f));
  s.l = normalize(d);
  F atten = F(1.0f) / dist2;
  if (light.range > 0.0f) {
    const F r = dist2 / F(light.range * light.range);
    const F window = saturate(F(1.0f) - r * r);
    atten = atten * window * window;
  }
  if (light.type == LightType::kSpot) {
    const F cd = dot(normalize(V3<F>(light.direction)), -s.l);
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

// Shades point p with unit normal n, seen from the eye along unit v (point -> eye).
// visibility(i, l) returns the fraction of light i reaching p along l (self-shadow, shadow maps).
template <class F, class Visibility>
inline V3<F> blinn_phong(const FrameUniforms& frame, const MaterialUniforms& mat, V3<F> p, V3<F> n,
                         V3<F> v, V3<F> albedo, Visibility&& visibility) {
  V3<F> c = albedo * V3<F>(frame.ambient);
  for (int i = 0; i < frame.num_lights; ++i) {
    const LightSample<F> ls = light_sample<F>(frame.lights[i], p);
    const F ndotl = dot(n, ls.l);
    const mask_t<F> lit = ndotl > F(0.0f);
    if (none(lit)) continue;
    const F vis = visibility(i, ls.l, lit);
    const V3<F> h = normalize(ls.l + v);
    const F spec = vpow(vmax(dot(n, h), F(0.0f)), mat.shininess) * F(mat.specular);
    const F diffuse = vmax(ndotl, F(0.0f));
    const V3<F> contrib = (albedo * diffuse + V3<F>(spec, spec, spec)) * vis;
    c += select(lit, ls.radiance * contrib, V3<F>(F(0.0f), F(0.0f), F(0.0f)));
  }
  return c;
}

template <class F>
struct NoShadow {
  F operator()(int, V3<F>, mask_t<F>) const { return F(1.0f); }
};

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SHADERS_CPP_LIGHTING_H_
