#include "apps/scene_source.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>

#include "builtin/builtin.h"
#include "gl/gl_backend.h"
#include "plugins/registry.h"
#include "rasterizer/safe_file.h"
#include "render/validate.h"
#include "scene/gltf.h"

namespace relief::cli {

std::string default_scene_source() {
  return default_scene_name();
}

namespace {

// The extension of the last path component, lower case ("" when none; a leading dot is a hidden
// file's name, not an extension).
std::string extension_of(const std::string& name) {
  const size_t slash = name.find_last_of('/');
  const std::string base = slash == std::string::npos ? name : name.substr(slash + 1);
  const size_t dot = base.find_last_of('.');
  if (dot == std::string::npos || dot == 0) return "";
  std::string e = base.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

bool is_builtin_name(const std::string& name) {
  for (const BuiltinSceneInfo& b : builtin_scenes())
    if (b.name == name) return true;
  return false;
}

}  // namespace

bool is_scene_path(const std::string& name) {
  if (name.find('/') != std::string::npos || !extension_of(name).empty()) return true;
  struct stat st;
  return !is_builtin_name(name) && ::stat(name.c_str(), &st) == 0;
}

Status check_scene_source(const std::string& name) {
  if (!is_scene_path(name))  // the error of an unknown name lists the built-in scenes
    return is_builtin_name(name) ? Status() : make_builtin_scene(name).status();
  struct stat st;
  const bool exists = ::stat(name.c_str(), &st) == 0;
  const int stat_errno = exists ? 0 : errno;
  const std::string shown = printable(name);
  if (exists && S_ISDIR(st.st_mode)) return Status::error(shown + ": is a directory");
  const std::string ext = extension_of(name);
  if (ext != ".gltf" && ext != ".glb")
    return Status::error(shown + ": unsupported scene format" +
                         (ext.empty() ? std::string(" (no extension; expected")
                                      : " '" + printable(ext) + "' (expected") +
                         " .gltf or .glb)");
  if (!exists && (stat_errno == ENOENT || stat_errno == ENOTDIR))
    return Status::error(shown + ": no such file");
  return {};  // the loader reports anything else (permissions, FIFOs, ...)
}

Result<Scene> load_scene_source(const std::string& name, bool allow_outside_scene_dir) {
  return load_scene_source(name, allow_outside_scene_dir, false, nullptr);
}

Result<Scene> load_scene_source(const std::string& name, bool allow_outside_scene_dir, bool strict,
                                std::vector<GltfIgnored>* ignored) {
  RELIEF_RETURN_IF_ERROR(check_scene_source(name));
  if (ignored) ignored->clear();
  GltfLoadOptions options;
  options.allow_outside_scene_dir = allow_outside_scene_dir;
  options.strict = strict;
  options.ignored = ignored;
  const std::string ext = extension_of(name);
  if (is_scene_path(name) && (ext == ".gltf" || ext == ".glb")) {
    Result<Scene> s = load_scene(name, options);
    if (s.ok() && ignored)  // the lines load_gltf prints when it keeps nothing
      for (const GltfIgnored& g : *ignored)
        if (g.warn)
          std::fprintf(stderr, "relief: warning: %s\n", ignored_line(printable(name), g).c_str());
    return s;
  }
  return make_builtin_scene(name);
}

std::string explain_ignored(const Scene& scene, const std::vector<GltfIgnored>& ignored,
                            bool from_file) {
  if (!from_file) return "";
  std::string out = "ignored from the file (docs/scene-format.md, \"Support table\"):\n";
  for (size_t m = 0; m < scene.materials.size(); ++m) {
    std::string list;
    for (const GltfIgnored& g : ignored)
      if (g.material == static_cast<int>(m))
        list += (list.empty() ? "" : "; ") + g.feature + " (" + g.pointer + ")";
    out += "  material " + std::to_string(m) + " '" + scene.materials[m].name +
           "': " + (list.empty() ? "nothing" : list) + "\n";
  }
  for (const GltfIgnored& g : ignored)
    if (g.material < 0 && g.warn) out += "  " + g.pointer + ": " + g.what + "\n";
  return out;
}

Result<int> resolve_camera(const Scene& scene, const std::string& name_or_index) {
  if (name_or_index.empty()) return 0;
  const int n = static_cast<int>(scene.cameras.size());
  const bool digits = name_or_index.find_first_not_of("0123456789") == std::string::npos;
  if (digits && name_or_index.size() <= 9) {
    const int i = std::stoi(name_or_index);
    if (i < n) return i;
  }
  for (int i = 0; i < n; ++i)
    if (scene.cameras[i].name == name_or_index) return i;
  std::string known;
  for (int i = 0; i < n; ++i)
    known += (known.empty() ? "" : ", ") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
  return Status::usage("--camera: scene '" + scene.name + "' has no camera '" + name_or_index +
                       "' (cameras: " + (known.empty() ? "none" : known) + ")");
}

Status load_plugin_arg(const std::string& file) {
  struct stat st;
  if (file.find('/') == std::string::npos && ::stat(file.c_str(), &st) == 0)
    return PluginRegistry::global().load("./" + file);
  return PluginRegistry::global().load(file);
}

}  // namespace relief::cli
