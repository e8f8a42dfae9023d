// Twin of shaders_cpp/shadow.h (hard shadows): Policarpo, Oliveira and Comba, "Real-Time Relief
// Mapping on Arbitrary Polygonal Surfaces", I3D 2005 (section 3, figure 10); the upward march of
// McGuire and McGuire, "Steep Parallax Mapping", I3D 2005 poster.
//
// The shadow ray from the hit (uv, t) is (uv + dl * s, t - s), s in (0, t]; a sample occludes when
// the surface is above the ray by more than `bias`: D(uv + dl * s) < t - s - bias.
#include "search.glsl"

struct ShadowResult {
  float visibility;  // 1 lit, 0 in shadow
  float steps;       // shadow-ray iterations
  float fetches;     // depth samples
};

// Marches up in depth steps of 1 / n; visibility 0 at the first occluding sample. L.z <= 0 (light
// below the surface) is in shadow and takes no step.
ShadowResult self_shadow(TextureDepth depth, vec2 uv, float t, vec2 dl, float lz, int n,
                         float bias) {
  float inv_n = 1.0 / float(n);
  bool lit_side = lz > 0.0;
  float vis = lit_side ? 1.0 : 0.0;
  float steps = 0.0, fetches = 0.0;
  bool marching = lit_side;
  for (int i = 1; marching && i <= kMaxLinearSteps; ++i) {
    float s = float(i) * inv_n;
    marching = marching && s < t;
    if (!marching) break;
    float d = sample_depth(depth, uv + dl * s);
    float above = (t - s) - d;  // > 0: surface above the ray
    steps += 1.0;
    fetches += 1.0;
    if (above > bias) {
      vis = 0.0;
      marching = false;
    }
  }
  return ShadowResult(vis, steps, fetches);
}

// Twin of shaders_cpp/shadow.h depth_darkening: 1 at depth 0, 1 - strength at depth 1.
float depth_darkening(float depth, float strength) {
  return 1.0 - strength * clamp(depth, 0.0, 1.0);
}
