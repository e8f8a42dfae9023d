// Where a scene comes from: a built-in name or a file; and which backend renders it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/status.h"
#include "render/render.h"
#include "scene/gltf_extensions.h"
#include "scene/scene.h"

namespace relief::cli {

std::string default_scene_source();
// Whether `name` names a file rather than a built-in scene: it holds a '/', its last component
// has an extension ("a.obj", ".hidden" does not count), or it is no built-in name and something
// of that name exists.
bool is_scene_path(const std::string& name);
// Before anything else runs: a scene path (is_scene_path) that cannot be a scene file is an
// input error (exit 1) naming it: "<path>: is a directory", "<path>: unsupported scene format
// '.obj' (expected .gltf or .glb)", "<path>: no such file"; any other name must be a built-in
// scene ("unknown scene 'x' (built-in scenes: ...)").
Status check_scene_source(const std::string& name);
// A path ending in .gltf or .glb (any case) loads that file (scene/gltf.h); any other name is a
// built-in scene; check_scene_source() first.
// allow_outside_scene_dir: `--allow-outside-scene-dir` (the file's URIs may leave its folder).
Result<Scene> load_scene_source(const std::string& name_or_path,
                                bool allow_outside_scene_dir = false);
// As above, with `--strict` (what relief ignores in a glTF file is an error, not a warning line:
// scene/gltf_extensions.h) and, when `ignored` is set, the findings kept there for --explain (the
// warning lines are printed all the same).
Result<Scene> load_scene_source(const std::string& name_or_path, bool allow_outside_scene_dir,
                                bool strict, std::vector<GltfIgnored>* ignored = nullptr);
// The help text of `--strict` (render, export, bench).
inline constexpr const char* kStrictHelp =
    "Refuse a glTF file that uses anything relief ignores (extensions, material properties, "
    "sampler settings, attributes) instead of warning";
// `--explain`'s list of what each material of a loaded file ignores (empty for a built-in).
std::string explain_ignored(const Scene& scene, const std::vector<GltfIgnored>& ignored,
                            bool from_file);
// The help text of `--allow-outside-scene-dir` (render, export, bench, bake --dual).
inline constexpr const char* kAllowOutsideSceneDirHelp =
    "Let a glTF file's buffer and image URIs lead outside its folder (.., symlinks)";
// `--camera NAME|INDEX`: an index into Scene::cameras, or the first camera with that name; empty
// picks camera 0. Anything else is a usage error listing the scene's cameras.
Result<int> resolve_camera(const Scene& scene, const std::string& name_or_index);
// `--plugin FILE`: loads FILE into PluginRegistry::global(). A name without '/' that exists here
// is this folder's file ("my.so" is "./my.so"; dlopen would search the library path instead).
Status load_plugin_arg(const std::string& file);

}  // namespace relief::cli
