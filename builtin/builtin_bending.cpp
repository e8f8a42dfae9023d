// The `bending` scene (see builtin_bending.h).
#include "builtin/builtin_bending.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "base/check.h"
#include "builtin/builtin.h"
#include "builtin/builtin_parts.h"
#include "scene/animation.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace {

constexpr float kRadius = 0.25f, kLength = 2.0f;

// The cylinder's rest mesh and its skin weights (joint 0 root, joint 1 bend).
void make_cylinder(Mesh& m, std::vector<glm::u16vec4>& joints, std::vector<glm::vec4>& weights) {
  m.name = "cylinder";
  auto bend_weight = [](float y) {
    const float x = std::clamp((y - 0.7f) / 0.6f, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
  };
  auto add = [&](glm::vec3 p, glm::vec3 n, glm::vec2 uv, float w) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    m.uvs.push_back(uv);
    joints.push_back(glm::u16vec4(0, 1, 0, 0));
    weights.push_back(glm::vec4(1.0f - w, w, 0.0f, 0.0f));
  };
  const float two_pi = 6.28318530717958647692f;
  for (int r = 0; r <= kBendRings; ++r) {
    const float y = kLength * r / kBendRings;
    for (int s = 0; s <= kBendSegments; ++s) {
      const float a = two_pi * s / kBendSegments;
      const glm::vec3 n(std::sin(a), 0.0f, std::cos(a));  // s = 0 faces +z (the camera)
      // Two brick tiles around, 2.5 along: bricks about as wide as tall.
      add(glm::vec3(kRadius * n.x, y, kRadius * n.z), n,
          glm::vec2(2.0f * s / kBendSegments, 2.5f * y / kLength), bend_weight(y));
    }
  }
  const uint32_t row = kBendSegments + 1;
  for (int r = 0; r < kBendRings; ++r)
    for (int s = 0; s < kBendSegments; ++s) {
      const uint32_t i = r * row + s;
      m.indices.insert(m.indices.end(), {i, i + 1, i + row + 1, i, i + row + 1, i + row});
    }
  // Caps: a fan at each end, planar uv, rigid with its joint.
  for (int end = 0; end < 2; ++end) {
    const float y = end ? kLength : 0.0f;
    const glm::vec3 n(0.0f, end ? 1.0f : -1.0f, 0.0f);
    const uint32_t centre = static_cast<uint32_t>(m.positions.size());
    add(glm::vec3(0.0f, y, 0.0f), n, glm::vec2(0.5f), static_cast<float>(end));
    for (int s = 0; s <= kBendSegments; ++s) {
      const float a = two_pi * s / kBendSegments;
      const glm::vec3 p(kRadius * std::sin(a), y, kRadius * std::cos(a));
      add(p, n, glm::vec2(0.5f + 2.0f * p.x, 0.5f + 2.0f * p.z), static_cast<float>(end));
    }
    for (int s = 0; s < kBendSegments; ++s) {
      const uint32_t a = centre + 1 + s, b = a + 1;
      if (end)
        m.indices.insert(m.indices.end(), {centre, a, b});
      else
        m.indices.insert(m.indices.end(), {centre, b, a});
    }
  }
  prepare_mesh(m);
  CHECK_EQ(m.positions.size(), joints.size());  // no mirrored uv seam was split
}

}  // namespace

Result<Scene> make_bending_scene() {
  Result<Scene> plane = make_builtin_scene("plane");  // its brick relief material and light
  if (!plane.ok()) return plane.status();
  Scene s;
  s.name = "bending";
  Material mat = plane->materials.at(0);
  mat.name = "bricks";
  s.materials.push_back(mat);
  auto anim = std::make_shared<SceneAnimation>();
  Deformer d;
  make_cylinder(d.rest, d.joints, d.weights);
  d.mesh = 0;
  d.node = 2;
  d.skin = 0;
  s.meshes.push_back(d.rest);
  s.instances.push_back({0, 0, glm::mat4(1.0f)});
  // Nodes: 0 root joint, 1 bend joint (child of root, at y = 1), 2 the cylinder.
  AnimNode root, bend, cylinder;
  root.name = "root";
  bend.name = "bend";
  bend.parent = 0;
  bend.translation = glm::dvec3(0.0, 1.0, 0.0);
  cylinder.name = "cylinder";
  anim->nodes = {root, bend, cylinder};
  Skin skin;
  skin.joints = {0, 1};
  skin.inverse_bind = {glm::dmat4(1.0), glm::dmat4(1.0)};
  skin.inverse_bind[1][3] = glm::dvec4(0.0, -1.0, 0.0, 1.0);  // translate (0, -1, 0)
  anim->skins.push_back(skin);
  anim->deformers.push_back(std::move(d));
  anim->instances.push_back({2, 0});
  AnimationClip clip;
  clip.name = "bend";
  AnimationSampler rot;
  rot.interpolation = Interpolation::kLinear;
  rot.width = 4;
  const int keys = 9;
  for (int k = 0; k < keys; ++k) {
    const double t = kBendPeriod * k / (keys - 1);
    const double half = 0.5 * glm::radians(kBendMaxDeg) * std::sin(M_PI * k / (keys - 1));
    rot.times.push_back(static_cast<float>(t));
    // Quaternion (x, y, z, w) about +z; key 0 and the last are exactly the identity.
    rot.values.insert(rot.values.end(), {0.0f, 0.0f, static_cast<float>(std::sin(half)),
                                         static_cast<float>(std::cos(half))});
  }
  clip.samplers.push_back(rot);
  clip.channels.push_back({1, AnimPath::kRotation, 0});
  clip.duration = kBendPeriod;
  anim->clips.push_back(clip);
  s.animation = anim;

  s.lights = plane->lights;  // the same sun
  s.cameras.push_back(look_at("side", {-0.2f, 1.1f, 3.4f}, {-0.3f, 1.0f, 0.0f}, 40.0f, 20.0f));
  s.ambient = plane->ambient;
  s.background = plane->background;
  return s;
}

}  // namespace relief
