// Twin of shaders_cpp/shadow_lookup.h: shadow-map lookups. Williams, "Casting Curved Shadows on
// Curved Surfaces", SIGGRAPH 1978 (depth from the light, then a depth comparison per receiver);
// percentage-closer filtering after Reeves, Salesin and Cook, "Rendering Antialiased Shadows with
// Depth Maps", SIGGRAPH 1987, with bilinear tap weights; the receiver's depth at each tap follows
// its tangent plane (receiver-plane depth), plus a constant and a slope-scaled bias. Each function
// keeps its C++ name and follows it operation by operation (`precise`: no fused multiply-adds, as
// the C++ is built with -ffp-contract=off); change both together.
//
// Data (gl/gl_backend.cpp): light i's ShadowMapView is kShadowViewFloats floats at
// shadow_views[i * kShadowViewFloats] of the ShadowViewsBuffer storage block (binding 2), faces
// == 0 when the light has no map; its depth faces are the layers of shadow_depth[i] (texture unit
// 8 + i), 32-bit float reversed-Z as the depth pass wrote them, read with texelFetch. The CPU map's
// row 0 is the top (clip y = +1); the GL layer's row 0 is the bottom, so row ty is size - 1 - ty.

const float kMaxShadowSlope = 10.0;
// Layout of one view: size, faces, orthographic, position.xyz, znear, zfar, texel, depth_bias,
// slope_bias, pcf_radius, 4 unused, then view[6] and proj[6] (16 floats each, column-major).
const int kShadowViewFloats = kShadowViewHeader + 2 * kMaxShadowFaces * 16;

layout(std430, binding = kShadowViewsBinding) readonly buffer ShadowViewsBuffer { float shadow_views[]; };
layout(binding = kShadowUnit) uniform sampler2DArray shadow_depth[kMaxLights];

float shadow_view_at(int light, int k) { return shadow_views[light * kShadowViewFloats + k]; }
int shadow_faces(int light) { return int(shadow_view_at(light, 1)); }
mat4 shadow_matrix(int light, int which, int face) {
  int o = light * kShadowViewFloats + kShadowViewHeader + (which * kMaxShadowFaces + face) * 16;
  mat4 m;
  for (int c = 0; c < 4; ++c)
    m[c] = vec4(shadow_views[o + 4 * c], shadow_views[o + 4 * c + 1], shadow_views[o + 4 * c + 2],
                shadow_views[o + 4 * c + 3]);
  return m;
}

// glm's mat4 * vec4: (m0 x + m1 y) + (m2 z + m3 w), column by column.
vec4 glm_mul(mat4 m, vec4 v) {
  precise vec4 a0 = m[0] * v.x + m[1] * v.y;
  precise vec4 a1 = m[2] * v.z + m[3] * v.w;
  precise vec4 r = a0 + a1;
  return r;
}
// glm's mat3 * vec3: per row, left to right.
vec3 glm_mul3(mat4 m, vec3 v) {
  precise vec3 r = vec3(m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
                        m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
                        m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z);
  return r;
}

int cube_face(vec3 d) {
  vec3 a = abs(d);
  if (a.x >= a.y && a.x >= a.z) return d.x >= 0.0 ? 0 : 1;
  if (a.y >= a.z) return d.y >= 0.0 ? 2 : 3;
  return d.z >= 0.0 ? 4 : 5;
}

// Distance from the light along its axis of a stored reversed-Z depth.
float shadow_distance(bool orthographic, float znear, float zfar, float depth) {
  precise float r;
  if (orthographic) {
    r = zfar - depth * (zfar - znear);
  } else {
    precise float a = znear / (zfar - znear);
    precise float b = znear * zfar / (zfar - znear);
    r = b / (depth + a);
  }
  return r;
}

// Fraction of the light reaching world point p with unit normal n, l the unit direction to the
// light; adds the taps to `fetches`. Points outside the map or nearer than its near plane are lit.
float shadow_lookup(int light, vec3 p, vec3 n, vec3 l, inout float fetches) {
  int size_i = int(shadow_view_at(light, 0));
  int faces = int(shadow_view_at(light, 1));
  bool ortho = shadow_view_at(light, 2) != 0.0;
  vec3 position = vec3(shadow_view_at(light, 3), shadow_view_at(light, 4), shadow_view_at(light, 5));
  float znear = shadow_view_at(light, 6), zfar = shadow_view_at(light, 7);
  float texel = shadow_view_at(light, 8);
  float depth_bias = shadow_view_at(light, 9), slope_bias = shadow_view_at(light, 10);
  int r = int(shadow_view_at(light, 11));
  int f = faces == kMaxShadowFaces ? cube_face(p - position) : 0;
  mat4 view = shadow_matrix(light, 0, f);
  mat4 pr = shadow_matrix(light, 1, f);
  vec4 q = glm_mul(view, vec4(p, 1.0));
  float dist = -q.z;
  if (!(dist > znear)) return 1.0;
  vec4 c = glm_mul(pr, q);
  float size = float(size_i);
  precise float px = (c.x / c.w * 0.5 + 0.5) * size;
  precise float py = (0.5 - c.y / c.w * 0.5) * size;
  if (!(px >= 0.0 && px <= size && py >= 0.0 && py <= size)) return 1.0;
  vec3 ne = glm_mul3(view, n);
  precise float cos_t = clamp(n.x * l.x + n.y * l.y + n.z * l.z, 0.0, 1.0);
  precise float tan_t = min(sqrt(1.0 - cos_t * cos_t) / max(cos_t, 1e-6), kMaxShadowSlope);
  precise float texel_w = ortho ? texel : texel * dist;
  precise float bias = texel_w * (depth_bias + slope_bias * tan_t);
  precise float plane = ne.x * q.x + ne.y * q.y + ne.z * q.z;  // perspective: n . q
  precise float bx = px - 0.5, by = py - 0.5;
  float x0f = floor(bx), y0f = floor(by);
  precise float fx = bx - x0f, fy = by - y0f;
  int x0 = int(x0f), y0 = int(y0f);
  precise float lit = 0.0, total = 0.0;
  for (int j = -r; j <= r + 1; ++j) {
    precise float wy = j == -r ? 1.0 - fy : (j == r + 1 ? fy : 1.0);
    int ty = clamp(y0 + j, 0, size_i - 1);
    precise float ny = 1.0 - 2.0 * (float(y0 + j) + 0.5) / size;
    for (int i = -r; i <= r + 1; ++i) {
      precise float wx = i == -r ? 1.0 - fx : (i == r + 1 ? fx : 1.0);
      int tx = clamp(x0 + i, 0, size_i - 1);
      precise float nx = 2.0 * (float(x0 + i) + 0.5) / size - 1.0;
      // the receiver's tangent plane under the tap's texel centre
      precise float d;
      if (ortho) {
        precise float ex = (nx - pr[3][0]) / pr[0][0], ey = (ny - pr[3][1]) / pr[1][1];
        d = dist + (ne.x * (ex - q.x) + ne.y * (ey - q.y)) / ne.z;
      } else {
        precise float ex = nx / pr[0][0], ey = ny / pr[1][1];
        d = plane / (ne.x * ex + ne.y * ey - ne.z);
      }
      precise float reach = texel_w * kMaxShadowSlope * float(abs(i) + abs(j) + 1);
      d = isnan(d) ? dist : clamp(d, dist - reach, dist + reach);
      precise float w = wx * wy;
      total += w;
      float stored = texelFetch(shadow_depth[light], ivec3(tx, size_i - 1 - ty, f), 0).r;
      if (d - bias <= shadow_distance(ortho, znear, zfar, stored)) lit += w;
    }
  }
  fetches += float((2 * r + 2) * (2 * r + 2));
  return lit / total;
}

// shadow_map_visibility for one fragment: light i's map, if it has one.
float shadow_map_visibility(int light, vec3 p, vec3 n, vec3 l, inout float fetches) {
  if (shadow_faces(light) == 0) return 1.0;
  return shadow_lookup(light, p, n, l, fetches);
}
