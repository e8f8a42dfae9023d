// glTF input, the scene graph (scene/gltf_internal.h): glTF 2.0 specification sections 3.5
// (scenes, nodes and their matrix or TRS, composed in double precision), 3.10 (perspective and
// orthographic cameras) and KHR_lights_punctual (directional, point and spot lights). Nodes are
// walked depth first from the default scene; meshes become instances, and cameras and lights
// keep our export's exact values (RELIEF_relief_mapping) while the node agrees with them.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "scene/gltf.h"
#include "scene/gltf_internal.h"

namespace relief::gltf_detail {

Result<glm::dmat4> Reader::local_matrix(int index) const {
  const tinygltf::Node& n = m_.nodes[index];
  const std::string np = "/nodes/" + std::to_string(index);
  auto finite = [&](const std::vector<double>& v, const char* key, size_t size) -> Status {
    if (!v.empty() && v.size() != size)
      return fail(np + "/" + key, "expected " + std::to_string(size) + " numbers");
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i])) return fail(np + "/" + key + "/" + std::to_string(i), "not finite");
    return {};
  };
  RELIEF_RETURN_IF_ERROR(finite(n.matrix, "matrix", 16));
  RELIEF_RETURN_IF_ERROR(finite(n.translation, "translation", 3));
  RELIEF_RETURN_IF_ERROR(finite(n.rotation, "rotation", 4));
  RELIEF_RETURN_IF_ERROR(finite(n.scale, "scale", 3));
  if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
  glm::dmat4 m(1.0);
  if (n.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4) {
    const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (glm::length(q) < 1e-6) return fail(np + "/rotation", "quaternion has zero length");
    m = m * glm::mat4_cast(glm::normalize(q));
  }
  if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
  return m;
}

Status Reader::read_nodes() {
  if (m_.scenes.empty()) {
    if (!m_.nodes.empty()) return fail("/scenes", "the file has nodes but no scene");
    return {};
  }
  const int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
  if (si >= static_cast<int>(m_.scenes.size()))
    return fail("/scene", "scene " + std::to_string(si) + " does not exist");
  std::vector<bool> seen(m_.nodes.size(), false);
  int order = 0;
  node_parent_.assign(m_.nodes.size(), -1);
  // Depth first with an explicit stack (a file may nest thousands of nodes), children pushed
  // in reverse so that nodes are visited in the order a recursive walk would take.
  struct Visit {
    int index, parent_index, depth;
    glm::dmat4 parent;
    std::string ref;  // JSON pointer of the reference to the node
  };
  std::vector<Visit> stack;
  const auto& roots = m_.scenes[si].nodes;
  for (size_t r = roots.size(); r-- > 0;)
    stack.push_back({roots[r], -1, 1, glm::dmat4(1.0),
                     "/scenes/" + std::to_string(si) + "/nodes/" + std::to_string(r)});
  while (!stack.empty()) {
    Visit v = std::move(stack.back());
    stack.pop_back();
    const int index = v.index;
    if (index < 0 || index >= static_cast<int>(m_.nodes.size()))
      return fail(v.ref, "node " + std::to_string(index) + " does not exist");
    const std::string np = "/nodes/" + std::to_string(index);
    if (seen[index])
      return fail(v.ref,
                  "node " + std::to_string(index) + " is reached twice (a cycle or two parents)");
    if (v.depth > kMaxNodeDepth)
      return fail(np, "node is " + std::to_string(v.depth) +
                          " levels deep in the hierarchy, more than the limit of " +
                          std::to_string(kMaxNodeDepth));
    seen[index] = true;
    const tinygltf::Node& n = m_.nodes[index];
    Result<glm::dmat4> local = local_matrix(index);
    if (!local.ok()) return local.status();
    const glm::dmat4 world = v.parent * *local;
    if (n.skin >= 0 && n.skin >= static_cast<int>(m_.skins.size()))
      return fail(np + "/skin", "skin " + std::to_string(n.skin) + " does not exist");
    if (n.skin >= 0 && n.mesh < 0) return fail(np + "/skin", "a skin needs a mesh on its node");
    node_parent_[index] = v.parent_index;
    if (n.mesh >= 0) {
      if (n.mesh >= static_cast<int>(m_.meshes.size()))
        return fail(np + "/mesh", "mesh " + std::to_string(n.mesh) + " does not exist");
      const auto& prims = m_.meshes[n.mesh].primitives;
      if (prims.empty())
        return fail("/meshes/" + std::to_string(n.mesh) + "/primitives",
                    "a mesh needs at least one primitive");
      for (size_t k = 0; k < prims.size(); ++k) {
        int mat = prims[k].material;
        if (mat >= static_cast<int>(materials_.size()))
          return fail("/meshes/" + std::to_string(n.mesh) + "/primitives/" + std::to_string(k) +
                          "/material",
                      "material " + std::to_string(mat) + " does not exist");
        const bool deformed = n.skin >= 0 || !prims[k].targets.empty();
        Result<int> mesh = primitive_mesh(n.mesh, static_cast<int>(k), mat, deformed ? index : -1);
        if (!mesh.ok()) return mesh.status();
        if (mat < 0) {
          if (default_material_ < 0) default_material_ = static_cast<int>(materials_.size());
          mat = default_material_;
        }
        if (scene_.instances.size() >= kMaxSceneInstances)
          return fail("/scenes/" + std::to_string(si),
                      "more than " + std::to_string(kMaxSceneInstances) +
                          " mesh instances (node and primitive pairs), the limit");
        instance_nodes_.push_back({index, static_cast<int>(scene_.instances.size())});
        scene_.instances.push_back({*mesh, mat, glm::mat4(world)});
      }
    }
    if (n.camera >= 0) {
      if (n.camera >= static_cast<int>(m_.cameras.size()))
        return fail(np + "/camera", "camera " + std::to_string(n.camera) + " does not exist");
      camera_nodes_.push_back({n.camera, index, order++, world});
    }
    RELIEF_RETURN_IF_ERROR(read_node_light(index, world));
    for (size_t c = n.children.size(); c-- > 0;)
      stack.push_back(
          {n.children[c], index, v.depth + 1, world, np + "/children/" + std::to_string(c)});
  }
  return {};
}

Status Reader::read_node_light(int node, const glm::dmat4& world) {
  const std::string np = "/nodes/" + std::to_string(node);
  Result<json> ext = extension(m_.nodes[node].extensions_json_string, kLightsPunctual, np);
  if (!ext.ok()) return ext.status();
  if (ext->is_null()) return {};
  const std::string ep = np + "/extensions/" + kLightsPunctual;
  int li = -1;
  if (!ext->contains("light")) return fail(ep, "missing 'light'");
  RELIEF_RETURN_IF_ERROR(get_int(*ext, "light", ep, li, 0, 1 << 30));
  if (li >= static_cast<int>(m_.lights.size()))
    return fail(ep + "/light", "light " + std::to_string(li) + " does not exist");
  const tinygltf::Light& gl = m_.lights[li];
  glm::dvec3 direction_hint(0.0);
  const std::string lp =
      std::string("/extensions/") + kLightsPunctual + "/lights/" + std::to_string(li);
  Light l;
  l.name = gl.name.empty() ? "light" + std::to_string(li) : gl.name;
  if (gl.type == "directional")
    l.type = LightType::kDirectional;
  else if (gl.type == "point")
    l.type = LightType::kPoint;
  else if (gl.type == "spot")
    l.type = LightType::kSpot;
  else
    return fail(lp + "/type", "unknown light type '" + gl.type + "' (directional, point or spot)");
  if (!gl.color.empty()) {
    if (gl.color.size() != 3) return fail(lp + "/color", "expected 3 numbers");
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(gl.color[i]) || gl.color[i] < 0.0)
        return fail(lp + "/color/" + std::to_string(i), "expected a number >= 0");
      l.color[i] = static_cast<float>(gl.color[i]);
    }
  }
  if (!std::isfinite(gl.intensity) || gl.intensity < 0.0)
    return fail(lp + "/intensity", "expected a number >= 0");
  l.intensity = static_cast<float>(gl.intensity);
  if (!std::isfinite(gl.range) || gl.range < 0.0)
    return fail(lp + "/range", "expected a number > 0");
  l.range = static_cast<float>(gl.range);
  if (l.type == LightType::kSpot) {
    const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
    if (!(outer > 0.0 && outer <= kPi / 2))
      return fail(lp + "/spot/outerConeAngle", "expected an angle in (0, pi/2]");
    if (!(inner >= 0.0 && inner < outer))
      return fail(lp + "/spot/innerConeAngle", "expected an angle in [0, outerConeAngle)");
    l.inner_cone_deg = static_cast<float>(inner * 180.0 / kPi);
    l.outer_cone_deg = static_cast<float>(outer * 180.0 / kPi);
  }
  Result<json> rext = extension(gl.extensions_json_string, kReliefExtension, lp);
  if (!rext.ok()) return rext.status();
  if (!rext->is_null()) {
    const std::string rp = lp + "/extensions/" + kReliefExtension;
    RELIEF_RETURN_IF_ERROR(check_keys(
        *rext, rp, {"casts_shadows", "shadow_resolution", "direction", "color", "intensity"}));
    RELIEF_RETURN_IF_ERROR(get_bool(*rext, "casts_shadows", rp, l.casts_shadows));
    RELIEF_RETURN_IF_ERROR(get_int(*rext, "shadow_resolution", rp, l.shadow_resolution, 16, 16384));
    RELIEF_RETURN_IF_ERROR(get_vec<3>(*rext, "direction", rp, direction_hint, -2.0, 2.0));
    // The colour and intensity as relief had them (glTF's colour lies in [0, 1]), kept while
    // their product is the file's.
    glm::dvec3 color(-1.0);
    double intensity = -1.0;
    RELIEF_RETURN_IF_ERROR(get_vec<3>(*rext, "color", rp, color, 0.0, 1e30));
    RELIEF_RETURN_IF_ERROR(get_number(*rext, "intensity", rp, intensity, 0.0, 1e30));
    if (color.x >= 0.0 && intensity >= 0.0) {
      const glm::dvec3 want = glm::dvec3(l.color) * double(l.intensity);
      const glm::dvec3 got = color * intensity;
      if (glm::length(got - want) <= 1e-6 * glm::length(want)) {
        l.color = glm::vec3(color);
        l.intensity = static_cast<float>(intensity);
      }
    }
  }
  l.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
  l.direction = glm::vec3(glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, -1)));
  // Our export's exact direction bits, kept while the node still points that way.
  if (glm::length(direction_hint) > 0.0 &&
      glm::dot(glm::normalize(direction_hint), glm::normalize(glm::dvec3(l.direction))) >
          1.0 - 1e-9)
    l.direction = glm::vec3(direction_hint);
  light_nodes_.push_back({node, static_cast<int>(scene_.lights.size())});
  scene_.lights.push_back(l);
  return {};
}

// Our export's exact target and up (the camera node's RELIEF_relief_mapping), kept while the
// node still looks that way (view direction and roll within 1e-9 of the node's).
Status Reader::camera_hint(const CameraNode& cn, Camera& c) const {
  const std::string np = "/nodes/" + std::to_string(cn.node);
  Result<json> ext = extension(m_.nodes[cn.node].extensions_json_string, kReliefExtension, np);
  if (!ext.ok()) return ext.status();
  if (ext->is_null()) return {};
  const std::string ep = np + "/extensions/" + kReliefExtension;
  RELIEF_RETURN_IF_ERROR(check_keys(*ext, ep, {"target", "up"}));
  glm::dvec3 target(c.target), up(c.up);
  RELIEF_RETURN_IF_ERROR(get_vec<3>(*ext, "target", ep, target, -1e30, 1e30));
  RELIEF_RETURN_IF_ERROR(get_vec<3>(*ext, "up", ep, up, -1e30, 1e30));
  const glm::dmat3 rot(cn.world);
  const glm::dvec3 fwd = glm::normalize(rot * glm::dvec3(0, 0, -1));
  const glm::dvec3 node_side = glm::normalize(glm::cross(fwd, rot * glm::dvec3(0, 1, 0)));
  const glm::dvec3 to = glm::dvec3(glm::vec3(target)) - glm::dvec3(c.position);
  const glm::dvec3 side = glm::cross(fwd, glm::dvec3(glm::vec3(up)));
  if (glm::length(to) > 0.0 && glm::length(side) > 0.0 &&
      glm::dot(glm::normalize(to), fwd) > 1.0 - 1e-9 &&
      glm::dot(glm::normalize(side), node_side) > 1.0 - 1e-9) {
    c.target = glm::vec3(target);
    c.up = glm::vec3(up);
  }
  return {};
}

Status Reader::place_cameras() {
  glm::dvec3 lo, hi;
  scene_bounds(scene_, lo, hi);
  const glm::dvec3 centre = (lo + hi) * 0.5;
  centre_ = centre;
  const double radius = std::max(glm::length(hi - lo) * 0.5, 1e-3);
  if (camera_nodes_.empty()) {
    scene_.cameras.push_back(default_camera(centre, radius));
    return {};
  }
  std::stable_sort(camera_nodes_.begin(), camera_nodes_.end(),
                   [](const CameraNode& a, const CameraNode& b) { return a.camera < b.camera; });
  for (const CameraNode& cn : camera_nodes_) {
    const tinygltf::Camera& gc = m_.cameras[cn.camera];
    const std::string cp = "/cameras/" + std::to_string(cn.camera);
    Camera c;
    c.name = !gc.name.empty()                  ? gc.name
             : !m_.nodes[cn.node].name.empty() ? m_.nodes[cn.node].name
                                               : "camera" + std::to_string(cn.camera);
    double znear = 0.0, zfar = 0.0;
    if (gc.type == "perspective") {
      const auto& p = gc.perspective;
      if (!(std::isfinite(p.yfov) && p.yfov > 0.0 && p.yfov < kPi))
        return fail(cp + "/perspective/yfov", "expected an angle in (0, pi)");
      c.yfov_deg = static_cast<float>(p.yfov * 180.0 / kPi);
      znear = p.znear;
      zfar = p.zfar;
      if (!(std::isfinite(znear) && znear > 0.0))
        return fail(cp + "/perspective/znear", "expected a number > 0");
    } else if (gc.type == "orthographic") {
      const auto& o = gc.orthographic;
      if (!(std::isfinite(o.ymag) && o.ymag > 0.0))
        return fail(cp + "/orthographic/ymag", "expected a number > 0");
      c.orthographic = true;
      c.ortho_half_height = static_cast<float>(o.ymag);
      znear = o.znear;
      zfar = o.zfar;
      if (!(std::isfinite(znear) && znear >= 0.0))
        return fail(cp + "/orthographic/znear", "expected a number >= 0");
      if (!(zfar > 0.0)) return fail(cp + "/orthographic/zfar", "expected a number > 0");
    } else {
      return fail(cp + "/type", "unknown camera type '" + gc.type + "'");
    }
    const glm::dvec3 pos(cn.world * glm::dvec4(0, 0, 0, 1));
    if (zfar == 0.0) {  // infinite perspective: reach past the farthest corner of the bounds
      double far = 0.0;
      for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y,
                                (k & 4) ? hi.z : lo.z);
        far = std::max(far, glm::length(corner - pos));
      }
      zfar = std::max(far * 1.5, znear * 2.0);
    }
    if (!(std::isfinite(zfar) && zfar > znear))
      return fail(cp + (c.orthographic ? "/orthographic" : "/perspective") + "/zfar",
                  "expected a number > znear");
    c.znear = static_cast<float>(znear);
    c.zfar = static_cast<float>(zfar);
    orient_camera(c, cn.world, centre);
    RELIEF_RETURN_IF_ERROR(camera_hint(cn, c));
    camera_nodes_bound_.push_back({cn.node, static_cast<int>(scene_.cameras.size())});
    scene_.cameras.push_back(c);
  }
  return {};
}

// No camera in the file: look at the centre of the bounds from +z, 30 degrees above the
// horizon, far enough for the bounding sphere to fit a 45-degree vertical field of view.
Camera Reader::default_camera(const glm::dvec3& centre, double radius) {
  Camera c;
  c.name = "default";
  c.yfov_deg = 45.0f;
  const double dist = radius / std::sin(22.5 * kPi / 180.0);
  const glm::dvec3 dir(0.0, std::sin(kPi / 6), std::cos(kPi / 6));
  c.position = glm::vec3(centre + dir * dist);
  c.target = glm::vec3(centre);
  c.up = glm::vec3(0, 1, 0);
  c.znear = static_cast<float>(dist * 0.01);
  c.zfar = static_cast<float>(dist + 2.0 * radius);
  return c;
}

}  // namespace relief::gltf_detail
