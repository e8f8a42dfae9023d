// Twin of shaders_cpp/quadric.h: the view ray against a height field deformed onto the per-vertex
// quadric z = a x^2 + b y^2, in texture space. Oliveira and Policarpo, "An Efficient
// Representation for Surface Details", UFRGS RP-351, 2005: section 3.1 (equation 6, the
// ray-quadric distance along U), 3.2 (equation 7, the vertical distance), 3.3 (the search range
// [0, t_max]; rays that come back to depth 0 are silhouette), 3.4 (equations 8 and 9). Each
// function keeps its C++ name and follows it operation by operation; change both together.
// Conventions: see the C++ header (texture space x, y in uv units, z in depth-map units).
// Needs ray.glsl (kMinRayCos, normalize_or), search.glsl (TextureDepth, SearchHit) and, for the
// relaxed cone search, cone.glsl (march_depth, cone_ratio).

const int kQuadricApproximate = 0;
const int kQuadricAccurate = 1;

struct QuadricRay {
  vec3 dir;          // unit, texture space, dir.z > 0
  vec3 up;           // U: perpendicular to the ray in tangent space, texture units per depth unit
  float alpha, beta; // equation 8
  float t_max;       // section 3.3
  bool bottom;       // t_max is where the ray reaches depth 1 (else where it returns to 0)
  float world_per_t; // world distance along the view ray per unit of t
};

// The smallest root in (0, inf) of q2 t^2 + q1 t + q0 = 0, or `none` (numerically stable form).
float smallest_positive_root(float q2, float q1, float q0, float none) {
  precise float disc = q1 * q1 - 4.0 * q2 * q0;
  bool real = disc >= 0.0;
  float sq = sqrt(max(disc, 0.0));
  precise float q = (q1 + (q1 < 0.0 ? -sq : sq)) * -0.5;
  bool qok = abs(q) > 1e-30, q2ok = abs(q2) > 1e-30;
  float r1 = (qok && q2ok) ? q / (q2ok ? q2 : 1.0) : none;
  float r2 = qok ? q0 / (qok ? q : 1.0) : none;
  float best = none;
  best = (real && r1 > 0.0 && r1 < best) ? r1 : best;
  best = (real && r2 > 0.0 && r2 < best) ? r2 : best;
  return best;
}

// Equation 7: D = P.z - (alpha P.x^2 + beta P.y^2).
float quadric_distance_vertical(QuadricRay r, float t) {
  precise float px = r.dir.x * t, py = r.dir.y * t;
  precise float d = r.dir.z * t - (r.alpha * px * px + r.beta * py * py);
  return d;
}

// Equation 6 along U: -2C / (B + sqrt(B^2 - 4AC)); equation 7 where there is no finite root.
float quadric_distance_accurate(QuadricRay r, float t) {
  precise vec3 p = r.dir * t;
  vec3 u = r.up;
  precise float A = r.alpha * u.x * u.x + r.beta * u.y * u.y;
  precise float B = 2.0 * (r.alpha * p.x * u.x + r.beta * p.y * u.y) - u.z;
  precise float C = r.alpha * p.x * p.x + r.beta * p.y * p.y - p.z;
  precise float disc = B * B - 4.0 * A * C;
  precise float den = B + sqrt(max(disc, 0.0));
  bool ok = disc >= 0.0 && den > 1e-6;
  precise float s = -2.0 * C / (ok ? den : 1.0);
  return ok ? s : quadric_distance_vertical(r, t);
}

float quadric_distance(int kind, QuadricRay r, float t) {
  return kind == kQuadricAccurate ? quadric_distance_accurate(r, t)
                                  : quadric_distance_vertical(r, t);
}

// The texture-space ray of a fragment (V unit tangent-space view direction, q = (a, b), tile =
// (sx, sy) world units per uv, sz the relief depth in world units).
QuadricRay make_quadric_ray(int kind, vec3 V, vec2 q, vec2 tile, float sz) {
  QuadricRay r;
  const float tiny = 1e-12;
  float sx = max(tile.x, tiny), sy = max(tile.y, tiny), s_z = max(sz, tiny);
  precise vec3 vt = vec3(V.x / sx, V.y / sy, max(-V.z, kMinRayCos) / s_z);
  precise float len = sqrt(vt.x * vt.x + vt.y * vt.y + vt.z * vt.z);
  r.dir = vt * (1.0 / len);
  r.world_per_t = 1.0 / len;
  r.alpha = q.x * sx * sx / s_z;
  r.beta = q.y * sy * sy / s_z;
  // U perpendicular to the ray in tangent space, in texture units per depth unit (quadric.h)
  precise vec3 vo0 = vec3(V.x, V.y, max(-V.z, kMinRayCos));
  precise vec3 vo = vo0 * (1.0 / sqrt(vo0.x * vo0.x + vo0.y * vo0.y + vo0.z * vo0.z));
  vec3 up0 = vec3(0.0, 0.0, -1.0);
  precise float du = up0.x * vo.x + up0.y * vo.y + up0.z * vo.z;
  vec3 uo = normalize_or(up0 - vo * du, vec3(1.0, 0.0, 0.0));
  r.up = vec3(uo.x * (s_z / sx), uo.y * (s_z / sy), uo.z);
  vec3 d = r.dir;
  precise float k = r.alpha * d.x * d.x + r.beta * d.y * d.y;
  const float none = 3.0e38;
  float t_return = k > 1e-30 ? d.z / max(k, 1e-30) : none;
  float t_bottom;
  if (kind == kQuadricAccurate) {
    vec3 u = r.up;
    precise float A = r.alpha * u.x * u.x + r.beta * u.y * u.y;
    precise float m = 2.0 * (r.alpha * d.x * u.x + r.beta * d.y * u.y) - d.z;
    t_bottom = smallest_positive_root(k, m, A - u.z, none);
  } else {
    t_bottom = smallest_positive_root(k, -d.z, 1.0, none);
  }
  r.bottom = t_bottom <= t_return;
  r.t_max = min(t_bottom, t_return);
  r.bottom = r.bottom || r.t_max >= none;
  r.t_max = r.t_max >= none ? 1.0 / d.z : r.t_max;
  return r;
}

struct QuadricHit {
  SearchHit hit;
  float t;
  bool miss;  // the ray left the relief without a hit (silhouette: discard)
};

// The C++ bisect() of the quadric searches: m halvings of [lo, hi] when `found` and hi > lo,
// the inside end kept; returns it. One step and one fetch per halving.
float quadric_bisect(int kind, TextureDepth depth, vec2 uv, QuadricRay r, float lo, float hi,
                     bool found, int m, inout float steps, inout float fetches) {
  vec2 duv = vec2(r.dir.x, r.dir.y);
  bool refine = found && hi > lo;
  for (int i = 0; i < m && refine; ++i) {
    float mid = (lo + hi) * 0.5;
    bool inside = sample_depth(depth, uv + duv * mid) <= quadric_distance(kind, r, mid);
    if (inside)
      hi = mid;
    else
      lo = mid;
    steps += 1.0;
    fetches += 1.0;
  }
  return hi;
}

// Linear search over t_i = t_max i / n, i = 0..n, stopping at the first inside sample (depth map
// <= D(t)); at t_max a bottom ray is inside whatever it reads. Then m binary halvings.
QuadricHit quadric_search(int kind, TextureDepth depth, vec2 uv, QuadricRay r, float n, int m) {
  float dt = r.t_max / n;
  vec2 duv = vec2(r.dir.x, r.dir.y);
  float t_out = 0.0, t_in = 0.0, steps = 0.0, fetches = 0.0;
  bool found = false;
  for (int i = 0; i <= kMaxLinearSteps; ++i) {
    float fi = float(i);
    bool last = fi >= n || i == kMaxLinearSteps;
    float t = last ? r.t_max : fi * dt;
    float h = sample_depth(depth, uv + duv * t);
    float D = quadric_distance(kind, r, t);
    bool inside = h <= D || (last && r.bottom);
    steps += 1.0;
    fetches += 1.0;
    if (inside) {
      t_in = t;
      found = true;
      break;
    }
    t_out = t;
    if (last) break;
  }
  float hi = quadric_bisect(kind, depth, uv, r, t_out, t_in, found, m, steps, fetches);
  QuadricHit o;
  o.t = found ? hi : 0.0;
  o.miss = !found;
  o.hit = SearchHit(uv + duv * o.t, clamp(quadric_distance(kind, r, o.t), 0.0, 1.0), steps, fetches);
  return o;
}

// quadric_relaxed_cone_search (search=relaxed_cone): relaxed cone stepping on the deformed field,
// n steps of the filtered depth and the cone map (cone.glsl, included before this file), each
// solving r k dt^2 - (rho + r D') dt + r h = 0 for the step to the cone's boundary; a lane left
// outside takes k floored cone steps (at least min((t_max - t) / k, half a texel along the ray),
// ramped up from 1/2^16 of it over the first fallback_ramp(k): cone.glsl ramped_floor)
// then k even samples of the rest; at t_max a bottom ray is inside, a returning ray a silhouette
// miss. Then m halvings of [last outside, first inside], all on the filtered depth.
float quadric_cone_t, quadric_cone_t_out;
bool quadric_cone_found;
// one cone step from quadric_cone_t, at least `floor`; returns whether the lane goes on
bool quadric_cone_step(int kind, TextureDepth depth, ConeSource cone, vec2 uv, QuadricRay r,
                       float floor_, inout float steps, inout float fetches) {
  vec2 duv = vec2(r.dir.x, r.dir.y);
  float rho = sqrt(duv.x * duv.x + duv.y * duv.y);
  precise float k = r.alpha * r.dir.x * r.dir.x + r.beta * r.dir.y * r.dir.y;
  float t = quadric_cone_t;
  ConeTexel c = cone_texel(depth, false, cone, uv + duv * t, steps, fetches);
  bool end_ = t >= r.t_max;
  precise float h = c.depth - quadric_distance(kind, r, t);
  bool inside = h <= 0.0 || (end_ && r.bottom);
  quadric_cone_found = quadric_cone_found || inside;
  if (inside || end_) return false;
  quadric_cone_t_out = t;
  precise float slope = r.dir.z - 2.0 * k * t;
  precise float q1 = 0.0 - (rho + c.ratio * slope);
  float root = smallest_positive_root(c.ratio * k, q1, c.ratio * h, 3.0e38);
  float dt = c.ratio > 0.0 ? root : 0.0;
  quadric_cone_t = min(t + max(dt, floor_), r.t_max);
  return true;
}

QuadricHit quadric_relaxed_cone_search(int kind, TextureDepth depth, ConeSource cone, vec2 uv,
                                       QuadricRay r, int n, int k, int m) {
  vec2 duv = vec2(r.dir.x, r.dir.y);
  float steps = 0.0, fetches = 0.0;
  quadric_cone_t = 0.0;
  quadric_cone_t_out = 0.0;
  quadric_cone_found = false;
  bool marching = true;
  for (int i = 0; i < n && marching; ++i)
    marching = quadric_cone_step(kind, depth, cone, uv, r, 0.0, steps, fetches);
  float inv_k = 1.0 / float(k);
  float floor_ = min((r.t_max - quadric_cone_t) * inv_k, half_texel_along(duv));
  float view_floor = half_texel_along(duv);
  int ramp = fallback_ramp(k);
  for (int j = 0; j < k && marching; ++j)
    marching = quadric_cone_step(kind, depth, cone, uv, r,
                                 ramped_floor(j, ramp, floor_, view_floor), steps, fetches);
  float s0 = quadric_cone_t, rest = r.t_max - quadric_cone_t;
  for (int j = 0; j < k && marching; ++j) {
    float t = s0 + rest * (float(j) * inv_k);
    quadric_cone_t = t;
    float d = sample_depth(depth, uv + duv * t);
    steps += 1.0;
    fetches += 1.0;
    bool inside = d <= quadric_distance(kind, r, t);
    quadric_cone_found = quadric_cone_found || inside;
    marching = !inside;
    if (marching) quadric_cone_t_out = t;
  }
  if (marching) {
    quadric_cone_t = r.t_max;
    quadric_cone_found = quadric_cone_found || r.bottom;
  }
  bool found = quadric_cone_found;
  float hi = quadric_bisect(kind, depth, uv, r, quadric_cone_t_out, quadric_cone_t, found, m,
                            steps, fetches);
  QuadricHit o;
  o.t = found ? hi : 0.0;
  o.miss = !found;
  o.hit = SearchHit(uv + duv * o.t, clamp(quadric_distance(kind, r, o.t), 0.0, 1.0), steps, fetches);
  return o;
}
