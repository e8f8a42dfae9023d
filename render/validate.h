// The one validator of techniques and parameters (DESIGN.md, "One frame, as data"): every
// technique name and parameter value relief takes, from a scene file (recorded by the glTF loader
// with its JSON pointers, scene/scene.h MaterialSource), from the command line (--technique,
// --param) or from a material built in code, is checked here against the plugin registry
// (PluginRegistry::global()), and nowhere else. make_plan calls it for the options and the
// materials; load_scene calls it for a file's materials, once, when the file loads.
//
// Messages: a file's value names the file and the JSON pointer, as the loader's own errors do
// ("<file>: <pointer>: <what>", exit 1); a command-line value is a usage error (exit 2); a
// material's value names the material.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "base/status.h"
#include "plugins/plugin.h"
#include "scene/gltf.h"
#include "scene/scene.h"

namespace relief {

// Where a technique name or a parameter value was given, for its message.
struct ValueOrigin {
  enum class Kind { kOption, kFile, kMaterial } kind = Kind::kOption;
  std::string file;      // kFile: the scene file
  std::string pointer;   // kFile: the value's JSON pointer
  std::string material;  // kMaterial: the material's name

  static ValueOrigin option() { return {}; }
  static ValueOrigin in_file(std::string file, std::string pointer) {
    return {Kind::kFile, std::move(file), std::move(pointer), {}};
  }
  static ValueOrigin of_material(std::string name) {
    return {Kind::kMaterial, {}, {}, std::move(name)};
  }
};

// The plugin called `name`. Unknown: "unknown technique 'x' (see `relief techniques`)" (usage)
// for an option, "<file>: <pointer>: unknown technique 'x' (known: a, b, ...)" for a file,
// "material 'm': unknown technique 'x'" for a material.
Result<const PluginDescriptor*> find_technique(const std::string& name, const ValueOrigin& origin);

// Resolves what a scene file said of `material` (Material::source; nothing when not pending):
// the technique, each parameter typed by the schema of the technique that declares it (the
// material's own first; parameters of other techniques apply when --technique switches) into
// Material::params, the kind of a cone map given without cone_kind (the technique's), and the
// texture slots the technique requires. Clears the source. Errors name the file and the pointer.
Status validate_material(Material& material);
// validate_material for every material of `scene`, in order.
Status validate_scene(Scene& scene);

// load_gltf with validate_scene run on the scene it reads (GltfLoadOptions::validate): what every
// caller that renders a file uses, so that nothing renders an unvalidated material. Its errors
// are those the glTF loader gave when it checked techniques itself, at the same moment.
Result<Scene> load_scene(const std::string& path, const GltfLoadOptions& options = {});

// The values of `plugin`'s parameters for `material` in schema order: defaults, the material's
// params (those `plugin` declares; a value out of range is an error naming the material), then
// the command-line `options` (key=value) that `plugin` declares, each marked in `used`. Each
// option's text is parsed once per plugin in the process (param_option).
Result<std::vector<float>> material_param_values(const PluginDescriptor& plugin,
                                                 const Material& material,
                                                 const std::map<std::string, std::string>& options,
                                                 std::map<std::string, bool>& used);

// The value of --param `key`=`text` for `plugin` (which declares `key`), parsed by the schema's
// rules (usage errors) and kept, so a frame loop parses each option once.
Result<float> param_option(const PluginDescriptor& plugin, const std::string& key,
                           const std::string& text);

// The error for --param `key` that no technique of the scene declares, named by `first` (the
// first material's plugin).
Status undeclared_param_option(const PluginDescriptor& first, const std::string& key,
                               const std::string& text);

}  // namespace relief
