// Animation sampling, posing, skinning and morphing (see animation.h): glTF 2.0 specification
// sections 3.7.2.2, 3.7.3, 3.11 and appendix C; Policarpo, Oliveira and Comba 2005 for why tangent
// frames deform with the surface.
#include "scene/animation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "scene/mesh_prep.h"

namespace relief {
namespace {

glm::dquat quat_from(const double* xyzw) {
  return glm::dquat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]);
}

// Any unit vector perpendicular to unit n (Frisvad / Duff et al.).
glm::vec3 any_perpendicular(glm::vec3 n) {
  const float sign = n.z >= 0.0f ? 1.0f : -1.0f;
  const float a = -1.0f / (sign + n.z);
  const float b = n.x * n.y * a;
  return {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
}

// n normalised, or `fallback` when n has no usable length.
glm::vec3 unit_or(glm::vec3 n, glm::vec3 fallback) {
  const float len = glm::length(n);
  return len > 1e-20f && std::isfinite(len) ? n / len : fallback;
}

// Tangent t made unit and perpendicular to unit n (Gram-Schmidt); any perpendicular when t is
// (nearly) parallel to n.
glm::vec3 orthonormal_tangent(glm::vec3 t, glm::vec3 n) {
  return unit_or(t - n * glm::dot(n, t), any_perpendicular(n));
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

glm::dquat slerp_shortest(const glm::dquat& a, const glm::dquat& b_in, double u) {
  glm::dquat b = b_in;
  double d = glm::dot(a, b);
  if (d < 0.0) {
    b = -b;
    d = -d;
  }
  if (d > 1.0 - 1e-12) return glm::normalize(a * (1.0 - u) + b * u);
  const double theta = std::acos(std::min(d, 1.0));
  const double s = std::sin(theta);
  return a * (std::sin((1.0 - u) * theta) / s) + b * (std::sin(u * theta) / s);
}

void sample_animation(const AnimationSampler& s, double t, bool rotation, double* out) {
  const int w = s.width;
  const size_t n = s.times.size();
  const bool cubic = s.interpolation == Interpolation::kCubicSpline;
  // Key k's value (cubic splines store in-tangent, value, out-tangent).
  auto value = [&](size_t k) { return &s.values[(cubic ? 3 * k + 1 : k) * w]; };
  auto copy = [&](const float* v) {
    for (int c = 0; c < w; ++c) out[c] = v[c];
  };
  if (n == 0) return;
  if (n == 1 || t <= s.times.front()) return copy(value(0));
  if (t >= s.times.back()) return copy(value(n - 1));
  const size_t k =
      static_cast<size_t>(std::upper_bound(s.times.begin(), s.times.end(), t) - s.times.begin()) -
      1;
  if (s.interpolation == Interpolation::kStep) return copy(value(k));
  const double t0 = s.times[k], t1 = s.times[k + 1], td = t1 - t0;
  const double u = (t - t0) / td;
  const float* a = value(k);
  const float* b = value(k + 1);
  if (!cubic) {
    if (rotation) {
      const double qa[4] = {a[0], a[1], a[2], a[3]}, qb[4] = {b[0], b[1], b[2], b[3]};
      const glm::dquat q = slerp_shortest(quat_from(qa), quat_from(qb), u);
      out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
      return;
    }
    for (int c = 0; c < w; ++c) out[c] = a[c] + u * (static_cast<double>(b[c]) - a[c]);
    return;
  }
  // Hermite basis (appendix C): p = h00 v_k + h10 td b_k + h01 v_k+1 + h11 td a_k+1, with b_k the
  // out-tangent of key k and a_k+1 the in-tangent of key k + 1.
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
               h11 = u3 - u2;
  const float* out_tangent = &s.values[(3 * k + 2) * w];
  const float* in_tangent = &s.values[(3 * (k + 1)) * w];
  for (int c = 0; c < w; ++c)
    out[c] = h00 * a[c] + h10 * td * out_tangent[c] + h01 * b[c] + h11 * td * in_tangent[c];
  if (rotation) {
    const double len =
        std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
    if (len > 0.0)
      for (int c = 0; c < 4; ++c) out[c] /= len;
  }
}

glm::dmat4 trs_matrix(const glm::dvec3& t, const glm::dquat& q, const glm::dvec3& s) {
  glm::dmat4 m(1.0);
  m = glm::translate(m, t);
  if (glm::length(q) > 1e-12) m = m * glm::mat4_cast(glm::normalize(q));
  return glm::scale(m, s);
}

void orient_camera(Camera& c, const glm::dmat4& world, const glm::dvec3& centre) {
  const glm::dvec3 pos(world * glm::dvec4(0, 0, 0, 1));
  const glm::dmat3 rot(world);
  const glm::dvec3 fwd = glm::normalize(rot * glm::dvec3(0, 0, -1));
  const glm::dvec3 node_up = glm::normalize(rot * glm::dvec3(0, 1, 0));
  c.position = glm::vec3(pos);
  // target: the point of the view ray nearest the centre of the scene bounds.
  const double t = glm::dot(centre - pos, fwd);
  c.target = glm::vec3(pos + fwd * (t > 1e-6 ? t : 1.0));
  // up: world +y when the camera has no roll (the same view, canonically written).
  const glm::dvec3 side = glm::cross(fwd, glm::dvec3(0, 1, 0));
  const bool no_roll = glm::length(side) > 1e-6 &&
                       std::abs(glm::dot(glm::normalize(side), node_up)) < 1e-9 && node_up.y > 0.0;
  c.up = no_roll ? glm::vec3(0, 1, 0) : glm::vec3(node_up);
}

void scene_bounds(const Scene& scene, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Instance& inst : scene.instances)
    for (const glm::vec3& p : scene.meshes[inst.mesh].positions) {
      const glm::dvec3 w(glm::dmat4(inst.transform) * glm::dvec4(glm::dvec3(p), 1.0));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  if (lo.x > hi.x) lo = hi = glm::dvec3(0.0);
}

Camera orbit_camera(const Camera& base, const glm::dvec3& centre, double angle) {
  if (angle == 0.0) return base;
  const double c = std::cos(angle), s = std::sin(angle);
  // Rotation about +y (counter-clockwise seen from above).
  auto rotate = [&](const glm::dvec3& v) {
    return glm::dvec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z);
  };
  Camera cam = base;
  cam.position = glm::vec3(centre + rotate(glm::dvec3(base.position) - centre));
  cam.target = glm::vec3(centre + rotate(glm::dvec3(base.target) - centre));
  cam.up = glm::vec3(rotate(glm::dvec3(base.up)));
  return cam;
}

void morph_mesh(const Mesh& rest, const std::vector<MorphTarget>& targets,
                const std::vector<float>& weights, Mesh& out) {
  if (out.positions.size() != rest.positions.size()) out = rest;
  std::vector<size_t> active;
  for (size_t k = 0; k < targets.size() && k < weights.size(); ++k)
    if (weights[k] != 0.0f) active.push_back(k);
  if (active.empty()) {
    out.positions = rest.positions;
    out.normals = rest.normals;
    out.tangents = rest.tangents;
    return;
  }
  for (size_t v = 0; v < rest.positions.size(); ++v) {
    glm::vec3 p = rest.positions[v], n = rest.normals[v], t = glm::vec3(rest.tangents[v]);
    for (size_t k : active) {
      const MorphTarget& m = targets[k];
      const float w = weights[k];
      if (!m.positions.empty()) p += w * m.positions[v];
      if (!m.normals.empty()) n += w * m.normals[v];
      if (!m.tangents.empty()) t += w * m.tangents[v];
    }
    n = unit_or(n, rest.normals[v]);
    out.positions[v] = p;
    out.normals[v] = n;
    out.tangents[v] = glm::vec4(orthonormal_tangent(t, n), rest.tangents[v].w);
  }
}

void skin_mesh(const Mesh& rest, const std::vector<glm::u16vec4>& joints,
               const std::vector<glm::vec4>& weights, const std::vector<glm::mat4>& matrices,
               Mesh& out) {
  if (out.positions.size() != rest.positions.size()) out = rest;
  const glm::mat4 identity(1.0f);
  for (size_t v = 0; v < rest.positions.size(); ++v) {
    const glm::u16vec4 j = joints[v];
    const glm::vec4 w = weights[v];
    // Blend around the heaviest influence, M = S_b + sum_i (w_i / sum w) (S_i - S_b): exactly S_b
    // when every influence has the same matrix, whatever the weights' rounding.
    int b = 0;
    for (int i = 1; i < 4; ++i)
      if (w[i] > w[b]) b = i;
    const float sum = w.x + w.y + w.z + w.w;
    glm::mat4 m = matrices[j[b]];
    if (sum > 0.0f)
      for (int i = 0; i < 4; ++i)
        if (i != b && w[i] != 0.0f) m += (w[i] / sum) * (matrices[j[i]] - matrices[j[b]]);
    if (m == identity) {
      out.positions[v] = rest.positions[v];
      out.normals[v] = rest.normals[v];
      out.tangents[v] = rest.tangents[v];
      continue;
    }
    const glm::vec3 c0(m[0]), c1(m[1]), c2(m[2]);
    out.positions[v] = glm::vec3(m * glm::vec4(rest.positions[v], 1.0f));
    // Normals by the cofactor matrix (det M times M^-T: columns c1 x c2, c2 x c0, c0 x c1).
    const glm::vec3 rn = rest.normals[v];
    const glm::vec3 n = unit_or(
        glm::cross(c1, c2) * rn.x + glm::cross(c2, c0) * rn.y + glm::cross(c0, c1) * rn.z, rn);
    const glm::vec4 rt = rest.tangents[v];
    const glm::vec3 t = c0 * rt.x + c1 * rt.y + c2 * rt.z;
    out.normals[v] = n;
    out.tangents[v] = glm::vec4(orthonormal_tangent(t, n), rt.w);
  }
}

PoseStats pose_scene(const SceneAnimation& anim, const PoseOptions& options, double time,
                     Scene& scene) {
  PoseStats stats;
  const size_t nn = anim.nodes.size();
  // Local transforms: rest, then the clip's channels.
  std::vector<glm::dvec3> tr(nn), sc(nn);
  std::vector<glm::dquat> rot(nn);
  std::vector<std::vector<float>> weights(nn);
  std::vector<char> moved(nn, 0);
  for (size_t i = 0; i < nn; ++i) {
    tr[i] = anim.nodes[i].translation;
    rot[i] = anim.nodes[i].rotation;
    sc[i] = anim.nodes[i].scale;
    weights[i] = anim.nodes[i].weights;
  }
  if (!anim.clips.empty()) {
    const AnimationClip& clip =
        anim.clips[std::clamp<size_t>(options.clip, 0, anim.clips.size() - 1)];
    std::vector<double> v;
    for (const AnimationChannel& ch : clip.channels) {
      const AnimationSampler& s = clip.samplers[ch.sampler];
      v.assign(s.width, 0.0);
      sample_animation(s, time, ch.path == AnimPath::kRotation, v.data());
      const size_t i = ch.node;
      switch (ch.path) {
        case AnimPath::kTranslation:
          tr[i] = glm::dvec3(v[0], v[1], v[2]);
          break;
        case AnimPath::kRotation:
          rot[i] = quat_from(v.data());
          break;
        case AnimPath::kScale:
          sc[i] = glm::dvec3(v[0], v[1], v[2]);
          break;
        case AnimPath::kWeights:
          weights[i].assign(v.begin(), v.end());
          break;
      }
      if (ch.path != AnimPath::kWeights) moved[i] = 1;
    }
  }
  // World matrices; `dirty` marks nodes whose world matrix a channel changed.
  std::vector<glm::dmat4> world(nn);
  std::vector<char> done(nn, 0), dirty(nn, 0);
  std::function<void(size_t)> resolve = [&](size_t i) {
    if (done[i]) return;
    const AnimNode& n = anim.nodes[i];
    const glm::dmat4 local = n.has_matrix
                                 ? n.matrix
                                 : (moved[i] ? trs_matrix(tr[i], rot[i], sc[i])
                                             : trs_matrix(n.translation, n.rotation, n.scale));
    if (n.parent >= 0) {
      resolve(n.parent);
      world[i] = world[n.parent] * local;
      dirty[i] = moved[i] || dirty[n.parent];
    } else {
      world[i] = local;
      dirty[i] = moved[i];
    }
    done[i] = 1;
  };
  for (size_t i = 0; i < nn; ++i) resolve(i);

  for (const NodeBinding& b : anim.instances)
    if (dirty[b.node]) scene.instances[b.index].transform = glm::mat4(world[b.node]);
  for (const NodeBinding& b : anim.cameras)
    if (dirty[b.node]) orient_camera(scene.cameras[b.index], world[b.node], anim.centre);
  for (const NodeBinding& b : anim.lights)
    if (dirty[b.node]) {
      Light& l = scene.lights[b.index];
      l.position = glm::vec3(world[b.node] * glm::dvec4(0, 0, 0, 1));
      l.direction = glm::vec3(glm::normalize(glm::dmat3(world[b.node]) * glm::dvec3(0, 0, -1)));
    }

  Mesh morphed;
  std::vector<glm::mat4> joint_matrices;
  for (const Deformer& d : anim.deformers) {
    const auto t0 = std::chrono::steady_clock::now();
    Mesh& out = scene.meshes[d.mesh];
    const Mesh* source = &d.rest;
    if (!d.targets.empty()) {
      Mesh& dst = d.skin >= 0 ? morphed : out;
      morph_mesh(d.rest, d.targets, weights[d.node], dst);
      source = &dst;
    }
    if (d.skin >= 0) {
      // Joint matrices in the mesh node's space: world(node)^-1 world(joint) inverseBind.
      const Skin& skin = anim.skins[d.skin];
      const glm::dmat4 to_mesh = glm::inverse(world[d.node]);
      joint_matrices.resize(skin.joints.size());
      for (size_t j = 0; j < skin.joints.size(); ++j)
        joint_matrices[j] = glm::mat4(to_mesh * world[skin.joints[j]] * skin.inverse_bind[j]);
      skin_mesh(*source, d.joints, d.weights, joint_matrices, out);
    }
    stats.deform_ms += elapsed_ms(t0);
    stats.vertices += static_cast<long long>(d.rest.positions.size());
    // Refit what the material derives from the surface's shape: relief_quadric's per-vertex
    // quadric (a, b) and tile scale (scene/mesh_prep) follow the deformed surface.
    bool refit = options.technique == "relief_quadric";
    for (const Instance& inst : scene.instances)
      if (inst.mesh == d.mesh && options.technique.empty())
        refit = refit || scene.materials[inst.material].technique == "relief_quadric";
    if (refit) {
      const auto t1 = std::chrono::steady_clock::now();
      compute_tile_scale(out);
      compute_quadrics(out);
      stats.refit_ms += elapsed_ms(t1);
      ++stats.refitted_meshes;
    }
  }
  return stats;
}

}  // namespace relief
