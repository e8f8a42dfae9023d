// Shadow passes: fitting a light's depth pass and handing its maps to receivers (Williams 1978;
// see render/shadow_map.h).
#include "render/shadow_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

namespace relief {

void Bounds::add(glm::vec3 p) {
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return;
  lo = glm::min(lo, p);
  hi = glm::max(hi, p);
}

void Bounds::add(const Bounds& b) {
  if (b.empty()) return;
  add(b.lo);
  add(b.hi);
}

glm::vec3 Bounds::corner(int i) const {
  return {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
}

Bounds instance_bounds(const Scene& scene, int instance) {
  const Instance& inst = scene.instances[instance];
  Bounds b;
  for (const glm::vec3& p : scene.meshes[inst.mesh].positions)
    b.add(glm::vec3(inst.transform * glm::vec4(p, 1.0f)));
  return b;
}

bool bounds_in_view(const Bounds& b, const glm::mat4& view_proj) {
  if (b.empty()) return false;
  glm::vec4 c[8];
  for (int i = 0; i < 8; ++i) c[i] = view_proj * glm::vec4(b.corner(i), 1.0f);
  // clip volume (reversed-Z): -w <= x, y <= w, 0 <= z <= w
  auto all_out = [&](auto outside) {
    for (const glm::vec4& v : c)
      if (!outside(v)) return false;
    return true;
  };
  return !(all_out([](glm::vec4 v) { return v.x < -v.w; }) ||
           all_out([](glm::vec4 v) { return v.x > v.w; }) ||
           all_out([](glm::vec4 v) { return v.y < -v.w; }) ||
           all_out([](glm::vec4 v) { return v.y > v.w; }) ||
           all_out([](glm::vec4 v) { return v.z < 0.0f; }) ||
           all_out([](glm::vec4 v) { return v.z > v.w; }));
}

Bounds clip_to_view(const Bounds& b, const glm::mat4& view_proj) {
  const glm::mat4 inv = glm::inverse(view_proj);
  Bounds frustum;
  for (int i = 0; i < 8; ++i) {
    // NDC corners; reversed-Z depth 1 at near, 0 at far
    const glm::vec4 h = inv * glm::vec4((i & 1) ? 1.0f : -1.0f, (i & 2) ? 1.0f : -1.0f,
                                        (i & 4) ? 1.0f : 0.0f, 1.0f);
    if (!(h.w > 0.0f)) return b;  // far plane at infinity: no tighter box
    frustum.add(glm::vec3(h) / h.w);
  }
  Bounds r;
  r.lo = glm::max(b.lo, frustum.lo);
  r.hi = glm::min(b.hi, frustum.hi);
  return r.empty() ? b : r;
}

namespace {

glm::vec3 up_for(glm::vec3 forward) {
  return std::fabs(forward.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, -1);
}

// Near and far distances from `p` enclosing the box `b`.
void distance_range(glm::vec3 p, const Bounds& b, float& znear, float& zfar) {
  float far2 = 0.0f;
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 d = b.corner(i) - p;
    far2 = std::max(far2, glm::dot(d, d));
  }
  const glm::vec3 q = glm::clamp(p, b.lo, b.hi);
  zfar = std::sqrt(far2) * 1.01f + 1e-3f;
  znear = std::max(glm::length(q - p) * 0.9f, zfar * 1e-3f);
}

}  // namespace

ShadowPassSetup fit_shadow_pass(const Light& light, const Bounds& receivers, const Bounds& casters,
                                const ShadowSettings& settings) {
  ShadowPassSetup s;
  s.type = light.type;
  s.size = light.shadow_resolution;
  const float size = static_cast<float>(s.size);
  // texels of margin so that the filter's taps stay inside the map
  const float margin = 2.0f * static_cast<float>(settings.pcf_radius + 2) / size;
  Bounds all = receivers;
  all.add(casters);
  if (light.type == LightType::kDirectional) {
    s.faces = 1;
    s.orthographic = true;
    const glm::vec3 dir = glm::normalize(light.direction);
    const glm::vec3 center = (receivers.lo + receivers.hi) * 0.5f;
    const float radius = glm::length(all.hi - all.lo) + 1.0f;
    s.position = center - dir * radius * 2.0f;
    s.forward[0] = dir;
    s.view[0] = glm::lookAt(s.position, center, up_for(dir));
    Bounds r, a;  // receivers and everything, in light eye space
    for (int i = 0; i < 8; ++i) {
      r.add(glm::vec3(s.view[0] * glm::vec4(receivers.corner(i), 1.0f)));
      a.add(glm::vec3(s.view[0] * glm::vec4(all.corner(i), 1.0f)));
    }
    const glm::vec2 half =
        glm::max((glm::vec2(r.hi) - glm::vec2(r.lo)) * 0.5f * (1.0f + margin), glm::vec2(1e-4f));
    const glm::vec2 mid = (glm::vec2(r.hi) + glm::vec2(r.lo)) * 0.5f;
    // eye space looks down -z: distance = -z
    const float depth_margin = (a.hi.z - a.lo.z) * 0.01f + 1e-3f;
    s.znear = std::max(-a.hi.z - depth_margin, 1e-3f);
    s.zfar = -r.lo.z + depth_margin;
    s.proj[0] = ortho_reversed_z(mid.x - half.x, mid.x + half.x, mid.y - half.y, mid.y + half.y,
                                 s.znear, s.zfar);
    s.texel = 2.0f * std::max(half.x, half.y) / size;
    return s;
  }
  s.orthographic = false;
  s.position = light.position;
  distance_range(light.position, all, s.znear, s.zfar);
  if (light.type == LightType::kSpot) {
    s.faces = 1;
    const float fov =
        std::clamp(2.0f * light.outer_cone_deg * (1.0f + margin) + 2.0f, 1.0f, 170.0f);
    const glm::vec3 dir = glm::normalize(light.direction);
    s.forward[0] = dir;
    s.view[0] = glm::lookAt(s.position, s.position + dir, up_for(dir));
    s.proj[0] = perspective_reversed_z(glm::radians(fov), 1.0f, s.znear, s.zfar);
    s.texel = 2.0f * std::tan(glm::radians(fov) * 0.5f) / size;
    return s;
  }
  s.faces = kMaxShadowFaces;
  static const glm::vec3 kForward[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                        {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  static const glm::vec3 kUp[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1},
                                   {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  for (int f = 0; f < 6; ++f) {
    s.forward[f] = kForward[f];
    s.view[f] = glm::lookAt(s.position, s.position + kForward[f], kUp[f]);
    s.proj[f] = perspective_reversed_z(glm::radians(90.0f), 1.0f, s.znear, s.zfar);
  }
  s.texel = 2.0f / size;
  return s;
}

namespace {

// The part of the convex polygon `in` (world points) inside the clip volume of `m` (world ->
// clip): -w <= x <= w, -w <= y <= w and, with `depth`, 0 <= z <= w (reversed-Z), else only w > 0
// (in front). Each bound is a half-space whose distance is affine in the world point, so cutting
// edges in world space puts the new corners exactly on the planes (Sutherland and Hodgman 1974).
// Buffers clip_polygon reuses from call to call (no allocation a polygon once they have grown).
struct ClipScratch {
  std::vector<glm::vec3> next;
  std::vector<float> dist;
};

void clip_polygon(const std::vector<glm::vec3>& in, const glm::mat4& m, bool depth,
                  std::vector<glm::vec3>& out, ClipScratch& scratch) {
  static constexpr float kFront = 1e-6f;  // w > 0: points at the eye are cut away
  // clip-space planes (a, b, c, d): a x + b y + c z + d w >= e
  static constexpr float kPlanes[7][4] = {{0, 0, 0, 1},  {1, 0, 0, 1}, {-1, 0, 0, 1}, {0, 1, 0, 1},
                                          {0, -1, 0, 1}, {0, 0, 1, 0}, {0, 0, -1, 1}};
  out = in;
  std::vector<glm::vec3>& next = scratch.next;
  std::vector<float>& dist = scratch.dist;
  for (int plane = 0; plane < (depth ? 7 : 5) && !out.empty(); ++plane) {
    const glm::vec4 n(kPlanes[plane][0], kPlanes[plane][1], kPlanes[plane][2], kPlanes[plane][3]);
    const float e = plane == 0 ? kFront : 0.0f;
    dist.clear();
    for (const glm::vec3& p : out) dist.push_back(glm::dot(n, m * glm::vec4(p, 1.0f)) - e);
    next.clear();
    for (size_t i = 0; i < out.size(); ++i) {
      const size_t j = (i + 1) % out.size();
      const float a = dist[i], b = dist[j];
      if (a >= 0.0f) next.push_back(out[i]);
      if ((a >= 0.0f) != (b >= 0.0f)) next.push_back(out[i] + (out[j] - out[i]) * (a / (a - b)));
    }
    out.swap(next);
  }
}

}  // namespace

std::vector<std::vector<glm::vec3>> visible_receiver_polygons(const Scene& scene,
                                                              const std::vector<int>& instances,
                                                              const glm::mat4& view_proj,
                                                              size_t budget) {
  size_t triangles = 0;
  for (int i : instances) triangles += scene.meshes[scene.instances[i].mesh].indices.size() / 3;
  const size_t stride = std::max<size_t>(1, (triangles + budget - 1) / std::max<size_t>(budget, 1));
  std::vector<std::vector<glm::vec3>> out;
  std::vector<glm::vec3> tri(3), clipped;
  ClipScratch scratch;
  size_t t_index = 0;
  for (int i : instances) {
    const Instance& inst = scene.instances[i];
    const Mesh& m = scene.meshes[inst.mesh];
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3, ++t_index) {
      if (t_index % stride != 0) continue;
      for (int k = 0; k < 3; ++k)
        tri[k] = glm::vec3(inst.transform * glm::vec4(m.positions[m.indices[t + k]], 1.0f));
      // the depth planes too: the near plane bounds how close a receiver point can be
      clip_polygon(tri, view_proj, true, clipped, scratch);
      if (clipped.size() >= 3) out.push_back(clipped);
    }
  }
  return out;
}

int view_shadow_size(const ShadowPassSetup& setup,
                     const std::vector<std::vector<glm::vec3>>& polygons, const glm::mat4& view,
                     const glm::mat4& proj, int height, int max_side) {
  const glm::mat4 view_proj = proj * view;
  const double pixel_scale = 2.0 / (static_cast<double>(height) * std::fabs(proj[1][1]));
  double need = 0.0;  // the largest side a corner asks for
  bool seen = false;
  std::vector<glm::vec3> in_map;
  ClipScratch scratch;
  for (const std::vector<glm::vec3>& poly : polygons)
    for (int f = 0; f < setup.faces; ++f) {
      // the part each face's map covers: texel / pixel is a ratio of two affine functions of
      // the point (distance along the face's axis, the view's clip w), largest at a corner
      clip_polygon(poly, setup.proj[f] * setup.view[f], false, in_map, scratch);
      for (const glm::vec3& p : in_map) {
        const double along = -(setup.view[f] * glm::vec4(p, 1.0f)).z;
        const double texel = setup.orthographic ? setup.texel : setup.texel * std::max(along, 0.0);
        const double pixel = pixel_scale * (view_proj * glm::vec4(p, 1.0f)).w;
        seen = true;
        if (!(pixel > 0.0)) return max_side;  // a point at the eye: the most the light allows
        need = std::max(need, setup.size * texel / pixel);
      }
    }
  if (!seen || !(need < static_cast<double>(max_side))) return max_side;
  return std::clamp(static_cast<int>(std::ceil(need)), 16, max_side);
}

FrameUniforms shadow_face_frame(const ShadowPassSetup& s, int face) {
  FrameUniforms f;
  f.view = s.view[face];
  f.view_proj = s.proj[face] * s.view[face];
  f.eye = s.position;
  f.orthographic = s.orthographic;
  f.view_dir = s.forward[face];
  f.num_lights = 0;
  f.aovs = 0;
  f.width = s.size;
  f.height = s.size;
  return f;
}

ShadowMapView make_shadow_view(const ShadowPassSetup& s, std::span<const float* const> faces,
                               const ShadowSettings& settings) {
  ShadowMapView v;
  v.size = s.size;
  v.faces = s.faces;
  v.orthographic = s.orthographic;
  v.position = s.position;
  for (int f = 0; f < s.faces; ++f) {
    v.view[f] = s.view[f];
    v.proj[f] = s.proj[f];
    v.depth[f] = faces[static_cast<size_t>(f)];
  }
  v.znear = s.znear;
  v.zfar = s.zfar;
  v.texel = s.texel;
  v.settings = settings;
  return v;
}

std::string describe_shadow_pass(const ShadowPassSetup& s) {
  char buf[160];
  const char* kind = s.orthographic ? "orthographic" : (s.faces == 6 ? "cube" : "perspective");
  std::snprintf(buf, sizeof buf, "%s %dx%d%s, depth %.3g..%.3g, texel %.3g%s", kind, s.size, s.size,
                s.faces == 6 ? " x 6 faces" : "", s.znear, s.zfar, s.texel,
                s.orthographic ? " world units" : " at distance 1");
  return buf;
}

}  // namespace relief
