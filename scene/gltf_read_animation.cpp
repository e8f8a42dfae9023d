// glTF input, animation (scene/gltf_internal.h): glTF 2.0 specification sections 3.7.2.2 (morph
// target weights), 3.7.3 (skins and inverse bind matrices) and 3.11 (animations: channels and
// LINEAR, STEP or CUBICSPLINE samplers) read into Scene::animation (scene/animation.h), which
// poses the scene at time 0 of the first animation.
#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/gtc/type_ptr.hpp>

#include "scene/gltf_internal.h"

namespace relief::gltf_detail {

// Builds Scene::animation when the file has animations, skins or morph targets, and poses the
// scene at time 0 of the first animation.
Status Reader::read_animation() {
  if (m_.animations.empty() && deformers_.empty()) return {};
  auto anim = std::make_shared<SceneAnimation>();
  anim->centre = centre_;
  anim->instances = instance_nodes_;
  anim->cameras = camera_nodes_bound_;
  anim->lights = light_nodes_;
  for (size_t i = 0; i < m_.nodes.size(); ++i) {
    const tinygltf::Node& n = m_.nodes[i];
    AnimNode an;
    an.name = n.name;
    an.parent = node_parent_[i];
    an.has_matrix = n.matrix.size() == 16;
    if (an.has_matrix) an.matrix = glm::make_mat4(n.matrix.data());
    if (n.translation.size() == 3)
      an.translation = glm::dvec3(n.translation[0], n.translation[1], n.translation[2]);
    if (n.rotation.size() == 4)
      an.rotation = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
    if (n.scale.size() == 3) an.scale = glm::dvec3(n.scale[0], n.scale[1], n.scale[2]);
    RELIEF_RETURN_IF_ERROR(node_weights(static_cast<int>(i), an.weights));
    anim->nodes.push_back(std::move(an));
  }
  RELIEF_RETURN_IF_ERROR(read_skins(*anim));
  for (size_t a = 0; a < m_.animations.size(); ++a) {
    Result<AnimationClip> clip = read_clip(static_cast<int>(a), *anim);
    if (!clip.ok()) return clip.status();
    anim->clips.push_back(std::move(*clip));
  }
  anim->deformers = deformers_;
  pose_scene(*anim, PoseOptions{}, 0.0, scene_);
  scene_.animation = std::move(anim);
  return {};
}

// The skins: their joints (nodes) and inverse bind matrices (identity where the file gives
// none).
Status Reader::read_skins(SceneAnimation& anim) const {
  for (size_t s = 0; s < m_.skins.size(); ++s) {
    const tinygltf::Skin& gs = m_.skins[s];
    const std::string sp = "/skins/" + std::to_string(s);
    Skin skin;
    for (size_t j = 0; j < gs.joints.size(); ++j) {
      if (gs.joints[j] < 0 || gs.joints[j] >= static_cast<int>(m_.nodes.size()))
        return fail(sp + "/joints/" + std::to_string(j),
                    "node " + std::to_string(gs.joints[j]) + " does not exist");
      skin.joints.push_back(gs.joints[j]);
    }
    if (skin.joints.empty()) return fail(sp + "/joints", "a skin needs at least one joint");
    skin.inverse_bind.assign(skin.joints.size(), glm::dmat4(1.0));
    if (gs.inverseBindMatrices >= 0) {
      std::vector<float> m;
      RELIEF_RETURN_IF_ERROR(read_floats(gs.inverseBindMatrices, sp + "/inverseBindMatrices",
                                         TINYGLTF_TYPE_MAT4, {kFloat}, m));
      if (m.size() < 16 * skin.joints.size())
        return fail(sp + "/inverseBindMatrices",
                    "has " + std::to_string(m.size() / 16) + " matrices for " +
                        std::to_string(skin.joints.size()) + " joints");
      for (size_t j = 0; j < skin.joints.size(); ++j)
        skin.inverse_bind[j] = glm::dmat4(glm::make_mat4(&m[16 * j]));
    }
    anim.skins.push_back(std::move(skin));
  }
  return {};
}

// The morph weights of node i's mesh: the node's, else the mesh's, else zeros.
Status Reader::node_weights(int i, std::vector<float>& out) const {
  const tinygltf::Node& n = m_.nodes[i];
  if (n.mesh < 0 || n.mesh >= static_cast<int>(m_.meshes.size())) return {};
  const tinygltf::Mesh& mesh = m_.meshes[n.mesh];
  const size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
  for (size_t k = 1; k < mesh.primitives.size(); ++k)
    if (mesh.primitives[k].targets.size() != targets)
      return fail(
          "/meshes/" + std::to_string(n.mesh) + "/primitives/" + std::to_string(k) + "/targets",
          "every primitive of a mesh needs the same number of morph targets");
  const bool own = !n.weights.empty();
  const std::vector<double>& w = own ? n.weights : mesh.weights;
  const std::string wp = own ? "/nodes/" + std::to_string(i) + "/weights"
                             : "/meshes/" + std::to_string(n.mesh) + "/weights";
  if (!w.empty() && w.size() != targets)
    return fail(wp, std::to_string(w.size()) + " weights for " + std::to_string(targets) +
                        " morph targets");
  out.assign(targets, 0.0f);
  for (size_t k = 0; k < w.size(); ++k) {
    if (!std::isfinite(w[k])) return fail(wp + "/" + std::to_string(k), "not finite");
    out[k] = static_cast<float>(w[k]);
  }
  return {};
}

Result<AnimationClip> Reader::read_clip(int index, const SceneAnimation& anim) const {
  const tinygltf::Animation& ga = m_.animations[index];
  const std::string ap = "/animations/" + std::to_string(index);
  AnimationClip clip;
  clip.name = ga.name.empty() ? "animation" + std::to_string(index) : ga.name;
  // Samplers are read for the channels that use them (their width depends on the path).
  std::vector<int> width(ga.samplers.size(), -1);
  std::vector<AnimPath> path(ga.samplers.size(), AnimPath::kTranslation);
  for (size_t c = 0; c < ga.channels.size(); ++c) {
    const tinygltf::AnimationChannel& gc = ga.channels[c];
    const std::string cp = ap + "/channels/" + std::to_string(c);
    // KHR_animation_pointer's channels (path "pointer", no node): ignored with a warning line
    // (scene/gltf_extensions.h), the rest of the animation plays.
    if (gc.target_path == "pointer" && gc.target_node < 0) continue;
    AnimationChannel ch;
    ch.node = gc.target_node;
    ch.sampler = gc.sampler;
    if (gc.sampler < 0 || gc.sampler >= static_cast<int>(ga.samplers.size()))
      return fail(cp + "/sampler", "sampler " + std::to_string(gc.sampler) + " does not exist");
    if (ch.node < 0 || ch.node >= static_cast<int>(m_.nodes.size()))
      return fail(cp + "/target/node", "node " + std::to_string(ch.node) + " does not exist");
    int w = 3;
    if (gc.target_path == "translation") {
      ch.path = AnimPath::kTranslation;
    } else if (gc.target_path == "rotation") {
      ch.path = AnimPath::kRotation;
      w = 4;
    } else if (gc.target_path == "scale") {
      ch.path = AnimPath::kScale;
    } else if (gc.target_path == "weights") {
      ch.path = AnimPath::kWeights;
      w = static_cast<int>(anim.nodes[ch.node].weights.size());
      if (w == 0)
        return fail(cp + "/target/path",
                    "node " + std::to_string(ch.node) + " has no mesh with morph targets");
    } else {
      return fail(cp + "/target/path",
                  "unknown path '" + gc.target_path + "' (translation, rotation, scale, weights)");
    }
    if (ch.path != AnimPath::kWeights && anim.nodes[ch.node].has_matrix)
      return fail(cp + "/target/node",
                  "node " + std::to_string(ch.node) + " has a matrix and cannot be animated");
    if (width[ch.sampler] >= 0 && width[ch.sampler] != w)
      return fail(cp + "/sampler", "sampler shared by channels of different widths");
    width[ch.sampler] = w;
    path[ch.sampler] = ch.path;
    clip.channels.push_back(ch);
  }
  for (size_t i = 0; i < ga.samplers.size(); ++i) {
    const tinygltf::AnimationSampler& gs = ga.samplers[i];
    const std::string sp = ap + "/samplers/" + std::to_string(i);
    AnimationSampler s;
    if (width[i] < 0) {  // no channel uses it
      clip.samplers.push_back(s);
      continue;
    }
    s.width = width[i];
    if (gs.interpolation.empty() || gs.interpolation == "LINEAR")
      s.interpolation = Interpolation::kLinear;
    else if (gs.interpolation == "STEP")
      s.interpolation = Interpolation::kStep;
    else if (gs.interpolation == "CUBICSPLINE")
      s.interpolation = Interpolation::kCubicSpline;
    else
      return fail(sp + "/interpolation",
                  "unknown interpolation '" + gs.interpolation + "' (LINEAR, STEP, CUBICSPLINE)");
    RELIEF_RETURN_IF_ERROR(
        read_floats(gs.input, sp + "/input", TINYGLTF_TYPE_SCALAR, {kFloat}, s.times));
    for (size_t k = 0; k < s.times.size(); ++k)
      if (s.times[k] < 0.0f || (k > 0 && !(s.times[k] > s.times[k - 1])))
        return fail(sp + "/input", "key times must be >= 0 and strictly increasing (key " +
                                       std::to_string(k) + ")");
    const bool rot = path[i] == AnimPath::kRotation;
    const int type = path[i] == AnimPath::kWeights ? TINYGLTF_TYPE_SCALAR
                     : rot                         ? TINYGLTF_TYPE_VEC4
                                                   : TINYGLTF_TYPE_VEC3;
    std::vector<int> ctypes = {kFloat};
    if (rot) ctypes = {kFloat, -kByte, -kUByte, -kShort, -kUShort};
    RELIEF_RETURN_IF_ERROR(read_floats(gs.output, sp + "/output", type, ctypes, s.values));
    const size_t per_key =
        static_cast<size_t>(s.width) * (s.interpolation == Interpolation::kCubicSpline ? 3 : 1);
    if (s.values.size() != s.times.size() * per_key)
      return fail(sp + "/output", std::to_string(s.values.size()) + " values for " +
                                      std::to_string(s.times.size()) + " keys, expected " +
                                      std::to_string(s.times.size() * per_key));
    clip.duration = std::max(clip.duration, static_cast<double>(s.times.back()));
    clip.samplers.push_back(std::move(s));
  }
  return clip;
}

}  // namespace relief::gltf_detail
