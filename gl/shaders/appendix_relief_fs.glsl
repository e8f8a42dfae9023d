#version 450 core
// The fragment shader of the relief paper's appendix (Policarpo, Oliveira and Comba, "Real-Time
// Relief Mapping on Arbitrary Polygonal Surfaces", I3D 2005: `main_frag_relief` and
// `ray_intersect_rm`), the lean yardstick of `relief bench` (gl/appendix_relief.h). Its search as
// printed: LINEAR_STEPS - 1 linear samples at depths 1/n .. (n-1)/n, every one taken, then
// BINARY_STEPS halvings around the first inside sample, every one taken; one RGBA8 texture with
// the normal in rgb and depth in a. As the issue restates it: textureLod 0 (bilinear level 0), one
// directional light, diffuse only (no colour texture, no specular), no self-shadow, no depth
// write. World space instead of eye space, which changes no operation count.

in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;

layout(binding = 0) uniform sampler2D rmtex;  // normal (rgb, n * 0.5 + 0.5, y down) and depth (a)
uniform vec3 eye;
uniform vec3 view_dir;    // orthographic cameras: the view direction, eye to scene
uniform int orthographic;
uniform float depth;      // relief depth in uv units (depth_scale)
uniform vec3 light_dir;   // unit, from the surface toward the light
uniform vec3 ambient;
uniform vec3 diffuse;

layout(location = 0) out vec4 out_color;
#ifdef APPENDIX_HITS
layout(location = 1) out vec4 out_hit;  // (u, v, depth, 1) of the hit
#endif

float ray_intersect_rm(vec2 dp, vec2 ds) {
  const int linear_search_steps = LINEAR_STEPS;
  const int binary_search_steps = BINARY_STEPS;
  float depth_step = 1.0 / float(linear_search_steps);
  float size = depth_step;  // current size of the search window
  float d = 0.0;            // current depth position
  float best_depth = 1.0;   // best match found (starts with the last position 1.0)
  // front to back: the first point inside the object
  for (int i = 0; i < linear_search_steps - 1; i++) {
    d += size;
    vec4 t = textureLod(rmtex, dp + ds * d, 0.0);
    if (best_depth > 0.996)  // no depth found yet
      if (d >= t.w) best_depth = d;
  }
  d = best_depth;
  // around the first point inside, the closest match
  for (int i = 0; i < binary_search_steps; i++) {
    size *= 0.5;
    vec4 t = textureLod(rmtex, dp + ds * d, 0.0);
    if (d >= t.w) {
      best_depth = d;
      d -= 2.0 * size;
    }
    d += size;
  }
  return best_depth;
}

void main() {
  vec3 n = normalize(v_normal);
  vec3 t = normalize(v_tangent.xyz);
  vec3 b = v_tangent.w * cross(n, t);
  vec3 v = orthographic != 0 ? view_dir : normalize(v_position - eye);
  // the view vector in tangent space; its z away from the eye, as the paper's dot(normal, -v)
  vec3 s = normalize(vec3(dot(v, t), dot(v, b), dot(n, -v)));
  vec2 ds = s.xy * depth / max(s.z, 1e-4);
  vec2 dp = v_uv;
  float d = ray_intersect_rm(dp, ds);
  vec2 uv = dp + ds * d;
  vec4 tx = textureLod(rmtex, uv, 0.0);
  vec3 nn = normalize((tx.x * 2.0 - 1.0) * t + (1.0 - tx.y * 2.0) * b + (tx.z * 2.0 - 1.0) * n);
  float att = clamp(dot(light_dir, n), 0.0, 1.0);
  float diff = clamp(dot(light_dir, nn), 0.0, 1.0);
  out_color = vec4(ambient * diffuse + att * diff * diffuse, 1.0);
#ifdef APPENDIX_HITS
  out_hit = vec4(uv, d, 1.0);
#endif
}
