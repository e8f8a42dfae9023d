// glTF 2.0 scenes (.gltf and .glb) through tinygltf, with the relief material extension
// `RELIEF_relief_mapping` (docs/scene-format.md, schema docs/relief_mapping.schema.json).
//
// What is read: the default scene (else scene 0) and its node hierarchy (matrix or TRS, composed
// in double precision), meshes and their TRIANGLES primitives (indexed or not) with POSITION,
// NORMAL, TEXCOORD_0 and TANGENT (missing normals and tangents are made by scene/mesh_prep),
// baseColorFactor / baseColorTexture, normalTexture, samplers, KHR_texture_transform,
// KHR_lights_punctual and perspective / orthographic cameras. Images decode through
// scene/image_io (OpenImageIO): base colour as sRGB, everything else linear.
// Conventions: glTF's (right-handed, y up, cameras and lights look down their node's -z);
// Scene::cameras holds one entry per node that references a camera, ordered by camera index and
// then by node traversal order (so with each camera used once, entry i is /cameras/i). A file
// with no camera gets the default framing described in docs/scene-format.md.
//
// Errors: one line, "<file>: <JSON pointer>: <what>", e.g.
//   scene.gltf: /meshes/0/primitives/0/indices: index 9 out of range (8 vertices)
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "base/status.h"
#include "scene/gltf_extensions.h"
#include "scene/scene.h"

namespace relief {

inline constexpr const char* kReliefExtension = "RELIEF_relief_mapping";

struct GltfLoadOptions {
  // Buffer and image URIs may lead outside the scene file's folder (`..`, symlinks):
  // `--allow-outside-scene-dir`. Schemes, absolute paths and control bytes stay refused.
  bool allow_outside_scene_dir = false;
  // What the file has that relief does not render (scene/gltf_extensions.h): an extension it
  // lacks, a material property or sampler setting it ignores, an attribute set it does not read.
  // Each is one warning line "relief: warning: FILE: POINTER: what" on stderr once the scene has
  // loaded; with `strict` (`--strict`) the first is the load's error instead.
  bool strict = false;
  // When set, the findings go here (warn == true: the ones with a line) instead of stderr.
  std::vector<GltfIgnored>* ignored = nullptr;
  // When set, runs on the scene read, before the findings above: its error is the load's error.
  // render/validate.h's load_scene sets validate_scene here (techniques and parameters).
  std::function<Status(Scene&)> validate;
};

// Loads a .gltf or .glb file as data: RELIEF_relief_mapping's technique and plugin parameters are
// recorded as the file gives them, with their JSON pointers (Material::source), for
// render/validate.h to check against the plugin registry; load_scene (render/validate.h) is
// load_gltf with that check, what a caller that renders uses. A relief material without a normal
// texture asks for the one derived from its depth map (Material::normal_from_depth).
// Input safety (docs/errors.md, "The scene folder rule", "Only regular files"): the file, its
// buffers and images are read only when they are regular files (at most kMaxInputFileBytes);
// URIs are relative references (or data: URIs) that resolve inside the file's folder.
Result<Scene> load_gltf(const std::string& path, const GltfLoadOptions& options = {});

// Writes `scene` as glTF: .gltf (JSON, a .bin buffer and one PNG per texture next to it, named
// after the file's stem) or .glb (everything embedded). Textures must be 8-bit (R8, RG8, RGBA8) or
// R16. Every texture the material holds is written; a material that asks for its normal map from
// depth (normal_from_depth, no "normal" texture) is written so (render/derived_maps.h's
// drop_derivable_normal_maps turns a normal map equal to the derived one into that request).
// Every file is written to a temporary name and renamed into place once all are written.
// load_gltf(save_gltf(s)) reproduces s's meshes, materials, lights and cameras bit for bit
// (camera and light orientations through double-precision quaternions; see the docs).
Status save_gltf(const Scene& scene, const std::string& path);

}  // namespace relief
