// Plugins by name: the built-ins (plugins/builtin_plugins.cpp) and those loaded from shared
// objects.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "base/status.h"
#include "plugins/plugin.h"

namespace relief {

class PluginRegistry {
 public:
  // The process-wide registry, holding the built-ins.
  static PluginRegistry& global();

  const PluginDescriptor* find(const std::string& name) const;
  std::vector<const PluginDescriptor*> all() const;  // sorted by name
  // Loads `path` (dlopen), calls relief_plugin_entry and registers the descriptor. A missing
  // file, a missing entry, a wrong ABI version or a name already taken is an error.
  Status load(const std::string& path);
  Status add(const PluginDescriptor* plugin);

 private:
  std::map<std::string, const PluginDescriptor*> plugins_;
};

// Parameter values in schema order: defaults, then `overrides` (from the scene, by name), then
// `text_overrides` (from the CLI, key=value strings). Unknown names, values that do not parse,
// are out of range or are not one of an enum's choices are errors naming the parameter.
Result<std::vector<float>> resolve_params(const PluginDescriptor& plugin,
                                          const std::map<std::string, float>& overrides,
                                          const std::map<std::string, std::string>& text_overrides);
// One parameter value as a scene file types it (JSON): checked by the same rules as --param text,
// typed: a bool takes true or false (or the numbers 1 and 0, as --param takes "1" and "0"); an
// enum its choice name or the choice's index (0..n-1, as Material::params holds it); an int or
// float a number in the schema's range. Errors (exit 1) name the plugin and the parameter.
struct ParamValue {
  enum class Kind { kNumber, kBool, kText } kind = Kind::kNumber;
  double number = 0.0;
  bool boolean = false;
  std::string text;
};
Result<float> resolve_param_value(const PluginDescriptor& plugin, const std::string& name,
                                  const ParamValue& value);
int param_index(const PluginDescriptor& plugin, const char* name);         // -1 if absent
int texture_slot_index(const PluginDescriptor& plugin, const char* name);  // -1 if absent
// An enum's choices "a|b|c" as {"a", "b", "c"} (empty for nullptr).
std::vector<std::string> split_choices(const char* choices);
// "steps=32 (int, 1..256) ..." one line per parameter, for `relief techniques`.
std::string describe_params(const PluginDescriptor& plugin);

}  // namespace relief
