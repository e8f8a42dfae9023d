#include "plugins/registry.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "rasterizer/safe_file.h"

namespace relief {

void register_builtin_plugins(PluginRegistry& r);

PluginRegistry& PluginRegistry::global() {
  static PluginRegistry* registry = [] {
    auto* r = new PluginRegistry();
    register_builtin_plugins(*r);
    return r;
  }();
  return *registry;
}

const PluginDescriptor* PluginRegistry::find(const std::string& name) const {
  auto it = plugins_.find(name);
  return it == plugins_.end() ? nullptr : it->second;
}

std::vector<const PluginDescriptor*> PluginRegistry::all() const {
  std::vector<const PluginDescriptor*> out;
  for (const auto& [name, p] : plugins_) out.push_back(p);
  return out;
}

namespace {

// Names that land in messages, --param keys and glTF: letters, digits, '_' and '-' only, so an
// error that quotes one stays one printable line.
bool plain_name(const char* n) {
  if (n == nullptr || n[0] == '\0') return false;
  for (const char* c = n; *c; ++c)
    if (!std::isalnum(static_cast<unsigned char>(*c)) && *c != '_' && *c != '-') return false;
  return true;
}
const char* kPlainNameRule = "letters, digits, '_' and '-' only";

// Each parameter: a unique non-empty name, a known type, finite bounds min <= max with the default
// inside (an int: within +-2^24, where floats hold every integer; an enum: non-empty choices, the
// default one of them); each texture slot a unique name.
Status check_schema(const PluginDescriptor& p) {
  const std::string where = std::string("plugin '") + p.name + "'";
  for (int i = 0; i < p.num_params; ++i) {
    const ParamSpec& s = p.params[i];
    const std::string at = where + " parameter " + std::to_string(i);
    if (s.name == nullptr || s.name[0] == '\0') return Status::error(at + " has no name");
    if (!plain_name(s.name)) return Status::error(at + ": a name has " + kPlainNameRule);
    for (int j = 0; j < i; ++j)
      if (std::strcmp(p.params[j].name, s.name) == 0)
        return Status::error(where + " declares parameter '" + s.name + "' twice");
    const std::string named = where + " parameter '" + s.name + "'";
    if (static_cast<int>(s.type) > static_cast<int>(ParamType::kEnum))
      return Status::error(named + " has an unknown type " + std::to_string(int(s.type)));
    if (!std::isfinite(s.default_value) || !std::isfinite(s.min_value) ||
        !std::isfinite(s.max_value) || s.min_value > s.max_value || s.default_value < s.min_value ||
        s.default_value > s.max_value)
      return Status::error(named + ": expected finite min <= default <= max");
    if (s.type == ParamType::kInt && (s.min_value < -16777216.0f || s.max_value > 16777216.0f))
      return Status::error(named + ": an int range must lie in -16777216..16777216");
    if (s.type == ParamType::kEnum) {
      if (s.choices == nullptr || s.choices[0] == '\0')
        return Status::error(named + ": an enum needs choices \"a|b|...\"");
      int n = 1;
      for (const char* c = s.choices; *c; ++c) {
        n += *c == '|';
        if (*c != '|' && !std::isalnum(static_cast<unsigned char>(*c)) && *c != '_' && *c != '-')
          return Status::error(named + ": enum choices have " + kPlainNameRule + ", split by '|'");
      }
      if (s.default_value != std::floor(s.default_value) || s.default_value < 0.0f ||
          s.default_value >= n)
        return Status::error(named + ": the default must index one of the choices");
    }
  }
  for (int i = 0; i < p.num_textures; ++i) {
    const char* n = p.textures[i].name;
    if (n == nullptr || n[0] == '\0')
      return Status::error(where + " texture slot " + std::to_string(i) + " has no name");
    if (!plain_name(n))
      return Status::error(where + " texture slot " + std::to_string(i) + ": a name has " +
                           kPlainNameRule);
    for (int j = 0; j < i; ++j)
      if (std::strcmp(p.textures[j].name, n) == 0)
        return Status::error(where + " declares texture slot '" + n + "' twice");
  }
  return {};
}

}  // namespace

Status PluginRegistry::add(const PluginDescriptor* p) {
  if (p == nullptr) return Status::error("plugin descriptor is null");
  if (p->abi_version != kPluginAbiVersion)
    return Status::error("plugin ABI version " + std::to_string(p->abi_version) + ", expected " +
                         std::to_string(kPluginAbiVersion));
  if (p->name == nullptr || p->name[0] == '\0') return Status::error("plugin has no name");
  if (!plain_name(p->name))
    return Status::error(std::string("plugin name: expected ") + kPlainNameRule);
  if (p->select == nullptr || p->depth_output == nullptr)
    return Status::error(std::string("plugin '") + p->name + "' has no select/depth_output entry");
  if (p->num_params < 0 || p->num_params > kMaxParams || (p->num_params > 0 && !p->params))
    return Status::error(std::string("plugin '") + p->name + "' has a malformed parameter schema");
  if (p->num_textures < 0 || p->num_textures > kMaxTextureSlots ||
      (p->num_textures > 0 && !p->textures))
    return Status::error(std::string("plugin '") + p->name + "' has malformed texture slots");
  RELIEF_RETURN_IF_ERROR(check_schema(*p));
  if (plugins_.count(p->name))
    return Status::error(std::string("a plugin named '") + p->name + "' is already registered");
  plugins_[p->name] = p;
  return {};
}

Status PluginRegistry::load(const std::string& path) {
  // Only a regular file is handed to dlopen (dlopen of a FIFO blocks, of a device reads it); a
  // bare name that is no file here keeps dlopen's library search.
  {
    Result<SafeFd> file = open_regular_file(path);
    const bool search = path.find('/') == std::string::npos && ::access(path.c_str(), F_OK) != 0;
    if (!file.ok() && !search) return file.status();
  }
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* err = dlerror();
    std::string why = err ? err : "unknown error";
    for (char& c : why)
      if (c == '\n' || c == '\r') c = ' ';
    return Status::error(printable(path) + ": cannot load plugin: " + printable(why, 160));
  }
  using Entry = const PluginDescriptor* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, "relief_plugin_entry"));
  if (!entry) {
    dlclose(handle);
    return Status::error(printable(path) + ": not a relief plugin (no relief_plugin_entry symbol)");
  }
  // The handle stays open for the life of the process: descriptors point into it.
  return add(entry()).with_context(printable(path));
}

int param_index(const PluginDescriptor& plugin, const char* name) {
  for (int i = 0; i < plugin.num_params; ++i)
    if (std::strcmp(plugin.params[i].name, name) == 0) return i;
  return -1;
}

int texture_slot_index(const PluginDescriptor& plugin, const char* name) {
  for (int i = 0; i < plugin.num_textures; ++i)
    if (std::strcmp(plugin.textures[i].name, name) == 0) return i;
  return -1;
}

std::vector<std::string> split_choices(const char* choices) {
  std::vector<std::string> out;
  if (!choices) return out;
  std::stringstream ss(choices);
  std::string item;
  while (std::getline(ss, item, '|')) out.push_back(item);
  return out;
}

namespace {

// User text as it goes into a message: control characters escaped, so the message stays one line.
std::string printable(const std::string& t) {
  std::string out;
  for (unsigned char c : t) {
    if (c >= 0x20 && c != 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char kHex[] = "0123456789abcdef";
      out += c == '\n' ? std::string("\\n") : std::string("\\x") + kHex[c >> 4] + kHex[c & 15];
    }
  }
  return out;
}

std::string range_text(const ParamSpec& p) {
  std::ostringstream os;
  switch (p.type) {
    case ParamType::kBool:
      return "true|false";
    case ParamType::kEnum:
      return p.choices ? p.choices : "";
    case ParamType::kInt:
      os << static_cast<long>(p.min_value) << ".." << static_cast<long>(p.max_value);
      break;
    case ParamType::kFloat:
      os << p.min_value << ".." << p.max_value;
      break;
  }
  return os.str();
}

Status check_value(const PluginDescriptor& plugin, const ParamSpec& p, float v) {
  const std::string where = std::string(plugin.name) + " parameter '" + p.name + "'";
  if (!std::isfinite(v)) return Status::error(where + ": value must be finite");
  if (p.type == ParamType::kInt && v != std::floor(v))
    return Status::error(where + ": expected an integer in " + range_text(p));
  if ((p.type == ParamType::kInt || p.type == ParamType::kFloat) &&
      (v < p.min_value || v > p.max_value)) {
    std::ostringstream os;
    os << where << ": " << v << " is outside " << range_text(p);
    return Status::error(os.str());
  }
  if (p.type == ParamType::kBool && v != 0.0f && v != 1.0f) {
    std::ostringstream os;
    os << where << ": expected true or false, got " << v;
    return Status::error(os.str());
  }
  if (p.type == ParamType::kEnum) {
    const size_t n = split_choices(p.choices).size();
    if (v != std::floor(v) || v < 0.0f || v >= static_cast<float>(n)) {
      std::ostringstream os;
      os << where << ": expected one of " << range_text(p) << " (or its index 0.." << n - 1
         << "), got " << v;
      return Status::error(os.str());
    }
  }
  return {};
}

Result<float> parse_value(const PluginDescriptor& plugin, const ParamSpec& p,
                          const std::string& text) {
  const std::string where = std::string(plugin.name) + " parameter '" + p.name + "'";
  if (p.type == ParamType::kBool) {
    if (text == "true" || text == "1" || text == "on") return 1.0f;
    if (text == "false" || text == "0" || text == "off") return 0.0f;
    return Status::usage(where + ": expected true or false, got '" + printable(text) + "'");
  }
  if (p.type == ParamType::kEnum) {
    const auto choices = split_choices(p.choices);
    for (size_t i = 0; i < choices.size(); ++i)
      if (choices[i] == text) return static_cast<float>(i);
    return Status::usage(where + ": expected one of " + range_text(p) + ", got '" +
                         printable(text) + "'");
  }
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    return Status::usage(where + ": expected a number, got '" + printable(text) + "'");
  if (std::isfinite(v) && std::abs(v) > 3.4e38)  // no float holds it (the cast would be undefined)
    return Status::usage(where + ": " + printable(text) + " is outside " + range_text(p));
  Status s = check_value(plugin, p, static_cast<float>(v));
  if (!s.ok()) return Status::usage(s.message());
  return static_cast<float>(v);
}

}  // namespace

Result<std::vector<float>> resolve_params(const PluginDescriptor& plugin,
                                          const std::map<std::string, float>& overrides,
                                          const std::map<std::string, std::string>& text) {
  std::vector<float> values(plugin.num_params);
  for (int i = 0; i < plugin.num_params; ++i) values[i] = plugin.params[i].default_value;
  for (const auto& [name, v] : overrides) {
    const int i = param_index(plugin, name.c_str());
    if (i < 0)
      return Status::error(std::string(plugin.name) + " has no parameter '" + printable(name) +
                           "'");
    RELIEF_RETURN_IF_ERROR(check_value(plugin, plugin.params[i], v));
    values[i] = v;
  }
  for (const auto& [name, t] : text) {
    const int i = param_index(plugin, name.c_str());
    if (i < 0)
      return Status::usage(std::string(plugin.name) + " has no parameter '" + printable(name) +
                           "' (see `relief techniques`)");
    Result<float> v = parse_value(plugin, plugin.params[i], t);
    if (!v.ok()) return v.status();
    values[i] = *v;
  }
  return values;
}

Result<float> resolve_param_value(const PluginDescriptor& plugin, const std::string& name,
                                  const ParamValue& value) {
  const int i = param_index(plugin, name.c_str());
  if (i < 0)
    return Status::error(std::string(plugin.name) + " has no parameter '" + printable(name) + "'");
  const ParamSpec& p = plugin.params[i];
  const std::string where = std::string(plugin.name) + " parameter '" + p.name + "'";
  std::ostringstream shown;
  switch (value.kind) {
    case ParamValue::Kind::kNumber:
      shown << value.number;
      break;
    case ParamValue::Kind::kBool:
      shown << (value.boolean ? "true" : "false");
      break;
    case ParamValue::Kind::kText:
      shown << '"' << printable(value.text.substr(0, 60)) << (value.text.size() > 60 ? "..." : "")
            << '"';
      break;
  }
  if (p.type == ParamType::kBool) {
    if (value.kind == ParamValue::Kind::kBool) return value.boolean ? 1.0f : 0.0f;
    if (value.kind == ParamValue::Kind::kNumber && (value.number == 0.0 || value.number == 1.0))
      return static_cast<float>(value.number);
    return Status::error(where + ": expected true or false, got " + shown.str());
  }
  if (p.type == ParamType::kEnum) {
    const auto choices = split_choices(p.choices);
    if (value.kind == ParamValue::Kind::kText)
      for (size_t c = 0; c < choices.size(); ++c)
        if (choices[c] == value.text) return static_cast<float>(c);
    if (value.kind == ParamValue::Kind::kNumber && value.number == std::floor(value.number) &&
        value.number >= 0.0 && value.number < static_cast<double>(choices.size()))
      return static_cast<float>(value.number);
    return Status::error(where + ": expected one of " + range_text(p) + " (or its index 0.." +
                         std::to_string(choices.size() - 1) + "), got " + shown.str());
  }
  if (value.kind != ParamValue::Kind::kNumber)
    return Status::error(where + ": expected a number, got " + shown.str());
  if (!std::isfinite(value.number) || std::abs(value.number) > 3.4e38)
    return Status::error(where + ": " + shown.str() + " is outside " + range_text(p));
  const float v = static_cast<float>(value.number);
  RELIEF_RETURN_IF_ERROR(check_value(plugin, p, v));
  return v;
}

std::string describe_params(const PluginDescriptor& plugin) {
  std::ostringstream os;
  for (int i = 0; i < plugin.num_params; ++i) {
    const ParamSpec& p = plugin.params[i];
    os << "    " << p.name << " = ";
    if (p.type == ParamType::kEnum) {
      const auto c = split_choices(p.choices);
      const size_t d = static_cast<size_t>(p.default_value);
      os << (d < c.size() ? c[d] : "?");
    } else if (p.type == ParamType::kBool) {
      os << (p.default_value != 0.0f ? "true" : "false");
    } else {
      os << p.default_value;
    }
    const char* type = p.type == ParamType::kFloat  ? "float"
                       : p.type == ParamType::kInt  ? "int"
                       : p.type == ParamType::kBool ? "bool"
                                                    : "enum";
    os << "  (" << type << ", " << range_text(p) << ")  " << (p.help ? p.help : "") << "\n";
  }
  return os.str();
}

}  // namespace relief
