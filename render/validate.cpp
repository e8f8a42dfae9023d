// The one validator of techniques and parameters (render/validate.h).
#include "render/validate.h"

#include <mutex>
#include <tuple>
#include <utility>

#include "plugins/registry.h"
#include "scene/gltf_validate.h"

namespace relief {
namespace {

// "<file>: <pointer>: <what>", as the glTF loader's messages are (scene/gltf_read_json.cpp).
Status file_error(const ValueOrigin& at, const std::string& what) {
  return Status::error(at.file + ": " + one_line_text(at.pointer, 100) + ": " +
                       one_line_text(what, 180));
}

// The plugin a parameter is typed by: the material's technique when it declares it, else the
// first technique (by name) that does.
const PluginDescriptor* declaring_plugin(const PluginDescriptor& own, const std::string& name) {
  if (param_index(own, name.c_str()) >= 0) return &own;
  for (const PluginDescriptor* p : PluginRegistry::global().all())
    if (param_index(*p, name.c_str()) >= 0) return p;
  return nullptr;
}

// A file's parameters into Material::params: those of "params" typed by their declaring
// technique's schema (in name order), then every value checked against that schema's range.
Status resolve_file_params(const PluginDescriptor& plugin, Material& m) {
  const MaterialSource& src = m.source;
  for (const auto& [name, f] : src.params) {
    if (f.top_level) {
      m.params[name] = static_cast<float>(f.number);
      continue;
    }
    const ValueOrigin at = ValueOrigin::in_file(src.file, f.pointer);
    const PluginDescriptor* by = declaring_plugin(plugin, name);
    if (!by) return file_error(at, "no technique has a parameter '" + name + "'");
    ParamValue pv;
    pv.kind = f.kind == FileParam::Kind::kBool   ? ParamValue::Kind::kBool
              : f.kind == FileParam::Kind::kText ? ParamValue::Kind::kText
                                                 : ParamValue::Kind::kNumber;
    pv.number = f.number;
    pv.boolean = f.boolean;
    pv.text = f.text;
    Result<float> v = resolve_param_value(*by, name, pv);
    if (!v.ok()) return file_error(at, v.status().message());
    m.params[name] = *v;
  }
  for (const auto& [name, f] : src.params) {
    const ValueOrigin at = ValueOrigin::in_file(src.file, f.pointer);
    const PluginDescriptor* by = declaring_plugin(plugin, name);
    if (!by) return file_error(at, "no technique has a parameter '" + name + "'");
    Result<std::vector<float>> r = resolve_params(*by, {{name, m.params.at(name)}}, {});
    if (!r.ok()) return file_error(at, r.status().message());
  }
  return {};
}

// A cone map given without cone_kind takes the slot of the cone map the technique reads.
Status name_cone_slot(const PluginDescriptor& plugin, Material& m) {
  MaterialSource& src = m.source;
  if (!src.cone_texture) return {};
  std::string kind;
  for (int i = 0; i < plugin.num_textures && kind.empty(); ++i)
    if (std::string(plugin.textures[i].name).rfind("cone_", 0) == 0)
      kind = plugin.textures[i].name + 5;
  if (kind.empty())
    return file_error(ValueOrigin::in_file(src.file, src.cone_pointer),
                      "technique " + m.technique + " reads no cone map: give cone_kind");
  m.textures["cone_" + kind] = std::move(src.cone_texture);
  return {};
}

// The slots a file can fill and nothing derives (cone maps are baked by the renderer) that the
// technique requires; the normal map counts as given when it comes from the depth map.
Status check_required_textures(const PluginDescriptor& plugin, const Material& m) {
  for (int s = 0; s < plugin.num_textures; ++s) {
    const TextureSlotSpec& slot = plugin.textures[s];
    const std::string name = slot.name;
    if (name != "base_color" && name != "normal" && name != "depth") continue;
    if (!slot.required || m.textures.count(name)) continue;
    if (name == "normal" && m.normal_from_depth && m.textures.count("depth")) continue;
    const std::string where = name == "base_color" ? "pbrMetallicRoughness/baseColorTexture"
                              : name == "normal"   ? "normalTexture"
                                                   : name + "_texture";
    return file_error(
        ValueOrigin::in_file(m.source.file, m.source.slots_pointer),
        "technique " + m.technique + " needs a '" + name + "' texture (" + where + ")");
  }
  return {};
}

std::mutex g_options_mutex;
std::map<std::tuple<const PluginDescriptor*, std::string, std::string>, Result<float>>&
parsed_options() {
  static auto* m =
      new std::map<std::tuple<const PluginDescriptor*, std::string, std::string>, Result<float>>();
  return *m;
}

}  // namespace

Result<const PluginDescriptor*> find_technique(const std::string& name, const ValueOrigin& origin) {
  const PluginRegistry& registry = PluginRegistry::global();
  if (const PluginDescriptor* p = registry.find(name)) return p;
  switch (origin.kind) {
    case ValueOrigin::Kind::kOption:
      return Status::usage("unknown technique '" + name + "' (see `relief techniques`)");
    case ValueOrigin::Kind::kMaterial:
      return Status::error("material '" + origin.material + "': unknown technique '" + name + "'");
    case ValueOrigin::Kind::kFile:
      break;
  }
  std::string known;
  for (const PluginDescriptor* p : registry.all())
    known += (known.empty() ? "" : ", ") + std::string(p->name);
  return file_error(origin, "unknown technique '" + name + "' (known: " + known + ")");
}

Status validate_material(Material& m) {
  if (!m.source.pending()) return {};
  const MaterialSource& src = m.source;
  // A technique the loader chose (no RELIEF_relief_mapping) is the planner's to find.
  const PluginDescriptor* plugin = PluginRegistry::global().find(m.technique);
  if (!src.technique_pointer.empty()) {
    Result<const PluginDescriptor*> p =
        find_technique(m.technique, ValueOrigin::in_file(src.file, src.technique_pointer));
    if (!p.ok()) return p.status();
    plugin = *p;
  }
  if (plugin) {
    RELIEF_RETURN_IF_ERROR(name_cone_slot(*plugin, m));
    RELIEF_RETURN_IF_ERROR(resolve_file_params(*plugin, m));
    RELIEF_RETURN_IF_ERROR(check_required_textures(*plugin, m));
  }
  m.source = MaterialSource{};
  return {};
}

Status validate_scene(Scene& scene) {
  for (Material& m : scene.materials) RELIEF_RETURN_IF_ERROR(validate_material(m));
  return {};
}

Result<Scene> load_scene(const std::string& path, const GltfLoadOptions& options) {
  GltfLoadOptions o = options;
  o.validate = validate_scene;
  return load_gltf(path, o);
}

Result<float> param_option(const PluginDescriptor& plugin, const std::string& key,
                           const std::string& text) {
  std::lock_guard<std::mutex> lock(g_options_mutex);
  auto k = std::make_tuple(&plugin, key, text);
  if (auto hit = parsed_options().find(k); hit != parsed_options().end()) return hit->second;
  Result<std::vector<float>> r = resolve_params(plugin, {}, {{key, text}});
  Result<float> v =
      r.ok() ? Result<float>((*r)[param_index(plugin, key.c_str())]) : Result<float>(r.status());
  parsed_options().emplace(std::move(k), v);
  return v;
}

Result<std::vector<float>> material_param_values(const PluginDescriptor& plugin, const Material& m,
                                                 const std::map<std::string, std::string>& options,
                                                 std::map<std::string, bool>& used) {
  // Parameters the plugin does not declare belong to other techniques.
  std::map<std::string, float> own;
  for (const auto& [k, v] : m.params)
    if (param_index(plugin, k.c_str()) >= 0) own[k] = v;
  Result<std::vector<float>> values = resolve_params(plugin, own, {});
  if (!values.ok()) return values.status().with_context("material '" + m.name + "'");
  for (const auto& [k, text] : options) {
    const int i = param_index(plugin, k.c_str());
    if (i < 0) continue;
    used[k] = true;
    Result<float> v = param_option(plugin, k, text);
    if (!v.ok()) return v.status().with_context("material '" + m.name + "'");
    (*values)[i] = *v;
  }
  return values;
}

Status undeclared_param_option(const PluginDescriptor& first, const std::string& key,
                               const std::string& text) {
  Result<std::vector<float>> none = resolve_params(first, {}, {{key, text}});
  return Status::usage(none.status().message() + "; no technique in this scene declares it");
}

}  // namespace relief
