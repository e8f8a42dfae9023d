// Animation of a scene over time (glTF 2.0 animations, skins and morph targets; the camera
// turntable of `relief render --frames`), evaluated on the CPU before each frame is rendered.
//
// glTF 2.0 specification, section 3.11 (animations: STEP, LINEAR with quaternion slerp,
// CUBICSPLINE Hermite splines, appendix C), 3.7.3 (skins: joint matrix = world(joint) x
// inverseBindMatrix, at most four influences per vertex here: JOINTS_0 / WEIGHTS_0) and 3.7.2.2
// (morph targets: POSITION / NORMAL / TANGENT deltas weighted by the node's or mesh's weights).
// Deforming normals and tangent frames with the surface keeps the relief attached to it: the
// claim of Policarpo, Oliveira and Comba 2005 (Real-time relief mapping on arbitrary polygonal
// surfaces), section 1, for animated characters.
//
// Conventions: times in seconds; quaternions (x, y, z, w) as in glTF; matrices in double until an
// instance transform or a joint matrix is rounded to float once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_precision.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "base/status.h"
#include "scene/scene.h"

namespace relief {

enum class Interpolation { kStep, kLinear, kCubicSpline };
enum class AnimPath { kTranslation, kRotation, kScale, kWeights };

// Keyframes of `width` components (3 translation / scale, 4 rotation x y z w, or one per morph
// target). `values` holds keys * width numbers, or keys * 3 * width for cubic splines (in-tangent,
// value, out-tangent per key, as glTF stores them). Times strictly increase.
struct AnimationSampler {
  Interpolation interpolation = Interpolation::kLinear;
  std::vector<float> times;
  std::vector<float> values;
  int width = 0;
};

// The sampler's value at time t into out[0 .. width): clamped to the first / last key outside
// the keys; STEP holds the key at or before t; LINEAR interpolates (slerp along the shorter arc
// when `rotation`); CUBICSPLINE is the Hermite spline of appendix C (a rotation is normalised).
void sample_animation(const AnimationSampler& sampler, double t, bool rotation, double* out);
// Spherical linear interpolation of unit quaternions along the shorter arc (glTF appendix C).
glm::dquat slerp_shortest(const glm::dquat& a, const glm::dquat& b, double u);

struct AnimationChannel {
  int node = 0;
  AnimPath path = AnimPath::kTranslation;
  int sampler = 0;
};

struct AnimationClip {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  double duration = 0.0;  // the last key time over all samplers
};

// A node of the animated hierarchy with its rest transform (a node given by `matrix` cannot be
// animated, as in glTF).
struct AnimNode {
  std::string name;
  int parent = -1;
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
  bool has_matrix = false;
  glm::dmat4 matrix{1.0};
  std::vector<float> weights;  // morph weights of the node's mesh (node's, else the mesh's)
};

struct Skin {
  std::vector<int> joints;               // node indices
  std::vector<glm::dmat4> inverse_bind;  // one per joint
};

// Per-vertex deltas of one morph target; each array empty or one entry per vertex.
struct MorphTarget {
  std::vector<glm::vec3> positions, normals, tangents;
};

// A mesh rewritten each frame from its rest data: morph targets first, then the skin.
struct Deformer {
  int mesh = 0;   // Scene::meshes entry written each frame (used by this node only)
  int node = 0;   // the node carrying the mesh (its world matrix places the deformed mesh)
  int skin = -1;  // index into SceneAnimation::skins, -1 for none
  Mesh rest;
  std::vector<glm::u16vec4> joints;  // indices into Skin::joints (up to four influences)
  std::vector<glm::vec4> weights;
  std::vector<MorphTarget> targets;
};

// Which node an instance, camera or light of the Scene follows.
struct NodeBinding {
  int node = 0;
  int index = 0;  // into Scene::instances, Scene::cameras or Scene::lights
};

struct SceneAnimation {
  std::vector<AnimNode> nodes;
  std::vector<AnimationClip> clips;
  std::vector<Skin> skins;
  std::vector<Deformer> deformers;
  std::vector<NodeBinding> instances, cameras, lights;
  glm::dvec3 centre{0.0};  // of the rest scene's bounds: where an animated camera's target lies
};

// What posing one frame cost: deforming meshes (morph + skin, tangent frames included) and
// refitting what a deformed surface's material needs (per-vertex quadrics for relief_quadric).
struct PoseStats {
  double deform_ms = 0.0;
  double refit_ms = 0.0;
  long long vertices = 0;  // deformed vertices
  int refitted_meshes = 0;
};

struct PoseOptions {
  int clip = 0;           // index into SceneAnimation::clips (ignored without clips)
  std::string technique;  // RenderOptions::technique: an override that may ask for refits
};

// Poses `scene` (which must carry `animation`, made from its rest state) at `time` seconds:
// instance transforms, cameras and lights of animated nodes, and every deformed mesh. Parts no
// channel moves keep their bits; with every weight 0 and every joint at its bind pose the meshes
// are the rest meshes bit for bit.
PoseStats pose_scene(const SceneAnimation& animation, const PoseOptions& options, double time,
                     Scene& scene);

// Composition of a glTF node's local matrix: T * R(normalised q) * S, in double.
glm::dmat4 trs_matrix(const glm::dvec3& t, const glm::dquat& q, const glm::dvec3& s);
// A camera looking down -z of `world` with +y up: position, target (the point of the view ray
// nearest `centre`, or one unit ahead when it lies behind) and up (world +y when the camera has
// no roll, else the node's +y) as docs/scene-format.md describes.
void orient_camera(Camera& camera, const glm::dmat4& world, const glm::dvec3& centre);
// World bounding box of every instance's vertices (0, 0 for an empty scene).
void scene_bounds(const Scene& scene, glm::dvec3& lo, glm::dvec3& hi);

// The turntable: `base` rotated by `angle` radians about the vertical (+y) axis through `centre`
// (position, target and up). Angle 0 gives `base` bit for bit.
Camera orbit_camera(const Camera& base, const glm::dvec3& centre, double angle);

// Linear blend skinning of one vertex set: out = rest deformed by `joint_matrices` (one per skin
// joint, mapping rest mesh space to posed mesh space). See Deformer. Normals by the cofactor of
// the blended matrix, tangents by the blended matrix then re-orthonormalised against the normal,
// bitangent sign kept. A vertex whose blended matrix is exactly the identity is copied.
void skin_mesh(const Mesh& rest, const std::vector<glm::u16vec4>& joints,
               const std::vector<glm::vec4>& weights, const std::vector<glm::mat4>& joint_matrices,
               Mesh& out);
// Morph targets with `weights` (one per target) applied to `rest` into `out` (positions, normals,
// tangents; normals and tangents re-normalised where a weight is non-zero). Weights of 0 leave
// `out` equal to `rest` bit for bit.
void morph_mesh(const Mesh& rest, const std::vector<MorphTarget>& targets,
                const std::vector<float>& weights, Mesh& out);

}  // namespace relief
