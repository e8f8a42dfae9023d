// Texture sampling over lanes: the GLSL texture(), textureLod() and textureGrad() of kernels.
// Each lane calls the scalar sampler (rasterizer/texture.h), so float and F8 agree exactly.
#pragma once

#include "rasterizer/texture.h"
#include "shaders_cpp/vec.h"

namespace relief {

template <class F> struct V4 {
  F x, y, z, w;
  V3<F> xyz() const { return {x, y, z}; }
};

template <class F>
inline V4<F> texture_grad(const Texture& t, const SamplerState& s, V2<F> uv, V2<F> dx, V2<F> dy) {
  V4<F> r;
  for (int i = 0; i < lane_width<F>; ++i) {
    const glm::vec4 c = sample_grad(t, s, {lane(uv.x, i), lane(uv.y, i)},
                                    {lane(dx.x, i), lane(dx.y, i)}, {lane(dy.x, i), lane(dy.y, i)});
    set_lane(r.x, i, c.x);
    set_lane(r.y, i, c.y);
    set_lane(r.z, i, c.z);
    set_lane(r.w, i, c.w);
  }
  return r;
}

template <class F>
inline V4<F> texture_lod(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  V4<F> r;
  for (int i = 0; i < lane_width<F>; ++i) {
    const glm::vec4 c = sample_lod(t, s, {lane(uv.x, i), lane(uv.y, i)}, lane(lod, i));
    set_lane(r.x, i, c.x);
    set_lane(r.y, i, c.y);
    set_lane(r.z, i, c.z);
    set_lane(r.w, i, c.w);
  }
  return r;
}

template <class F>
inline F texture_r_lod(const Texture& t, const SamplerState& s, V2<F> uv, F lod) {
  return per_lane(uv.x, [&](int i) {
    return sample_r_lod(t, s, {lane(uv.x, i), lane(uv.y, i)}, lane(lod, i));
  });
}

}  // namespace relief
