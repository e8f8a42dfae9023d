// Twin of shaders_cpp/ray.h: eye rays in tangent and texture space, and depth correction, after
// Policarpo, Oliveira and Comba, "Real-Time Relief Mapping on Arbitrary Polygonal Surfaces",
// I3D 2005 (appendix: ds = s.xy * depth / s.z; depth correction of the hit point). Each function
// keeps its C++ name and follows it operation by operation; change both together.
//
// Conventions (DESIGN.md): depth map in [0, 1], 0 at the reference surface, 1 deepest. V points
// from the eye to the surface (V.z < 0 looks into it); a texture-space ray reaches depth t at
// uv + t * ds, ds = V.xy * depth_scale / (-V.z). Depth is float reversed-Z (near = 1, far = 0).

// The smallest -V.z (and light L.z) a texture-space step divides by.
const float kMinRayCos = 1e-4;

// Normalises `a`; a zero, huge, Inf or NaN vector gives `fallback` instead.
vec3 normalize_or(vec3 a, vec3 fallback) {
  float len2 = dot(a, a);
  bool ok = len2 > 1e-30 && len2 < 1e30;
  float inv = 1.0 / sqrt(ok ? len2 : 1.0);
  return ok ? a * inv : fallback;
}

// Unit world view direction, eye -> fragment (view_dir when orthographic); -n at the eye.
vec3 world_view_dir(vec3 world_pos, vec3 eye, bool orthographic, vec3 view_dir, vec3 fallback) {
  vec3 d = orthographic ? view_dir : world_pos - eye;
  return normalize_or(d, fallback);
}

// Texture-space uv step per unit depth of the ray along V.
vec2 texture_step(vec3 V, float depth_scale) {
  float s = depth_scale / max(-V.z, kMinRayCos);
  return vec2(V.x * s, V.y * s);
}

// Texture-space uv step per unit of depth decrease toward a light at tangent direction L.
vec2 light_step(vec3 L, float depth_scale) {
  float s = depth_scale / max(L.z, kMinRayCos);
  return vec2(L.x * s, L.y * s);
}

// Relief step count from the view angle: round(mix(steps, min_steps, |V.z|)), at least 1. The
// mix is written out as lanes.h's a + (b - a) * t (GLSL's mix may round differently).
float relief_step_count(float vz, float min_steps, float steps) {
  float n = floor(steps + (min_steps - steps) * clamp(abs(vz), 0.0, 1.0) + 0.5);
  return max(n, 1.0);
}

// World position of the hit at ray depth t.
vec3 hit_world_position(vec3 world_pos, vec3 w_view, float vz, float t, float world_height) {
  float dist = t * world_height / max(-vz, kMinRayCos);
  return world_pos + w_view * dist;
}

// Reversed-Z depth of a world point, clamped to [0, 1]; behind the eye or NaN gives `fallback`.
float reversed_z_depth(mat4 m, vec3 p, float fallback) {
  float z = p.x * m[0][2] + p.y * m[1][2] + p.z * m[2][2] + m[3][2];
  float w = p.x * m[0][3] + p.y * m[1][3] + p.z * m[2][3] + m[3][3];
  bool ok = w > 1e-30;
  float d = z / (ok ? w : 1.0);
  ok = ok && !isnan(d);
  return ok ? clamp(d, 0.0, 1.0) : clamp(isnan(fallback) ? 0.0 : fallback, 0.0, 1.0);
}
