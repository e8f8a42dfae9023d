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

ShadowMapView make_shadow_view(const ShadowPassSetup& s, const std::vector<Plane>& faces,
                               const ShadowSettings& settings) {
  ShadowMapView v;
  v.size = s.size;
  v.faces = s.faces;
  v.orthographic = s.orthographic;
  v.position = s.position;
  for (int f = 0; f < s.faces; ++f) {
    v.view[f] = s.view[f];
    v.proj[f] = s.proj[f];
    v.depth[f] = faces[f].values.data();
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
