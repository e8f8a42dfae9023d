// libFuzzer target: the plugin parameter schema. The input describes a PluginDescriptor as an
// external plugin could hand it over (parameter names, types, defaults, ranges, enum choices,
// texture slots: any bytes, nulls included) plus name=value overrides; PluginRegistry::add must
// accept it or refuse it with one line, and for an accepted schema resolve_params and
// describe_params must work and resolve only values inside the schema.
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "plugins/registry.h"

namespace {

struct Reader {
  const uint8_t* p;
  size_t n;
  uint8_t byte() {
    if (!n) return 0;
    --n;
    return *p++;
  }
  float real() {
    float f = 0.0f;
    const size_t k = n < 4 ? n : 4;
    std::memcpy(&f, p, k);
    p += k;
    n -= k;
    return f;
  }
  std::string text() {
    const size_t len = byte() % 12;
    std::string s;
    for (size_t i = 0; i < len && n; ++i) s.push_back(static_cast<char>(byte()));
    return s;
  }
};

relief::ShadeFn select_none(relief::EffectMask) {
  return nullptr;
}
relief::DepthOutput depth_none(relief::EffectMask) {
  return relief::DepthOutput::kNone;
}

void one_line(const std::string& m) {
  if (m.find('\n') != std::string::npos) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Reader r{data, size};
  const int num_params = static_cast<int>(r.byte() % 40) - 2;  // -2..37: bad counts too
  const int num_textures = static_cast<int>(r.byte() % 12) - 1;
  std::vector<std::string> names, choices;
  std::vector<relief::ParamSpec> params(40);
  std::vector<relief::TextureSlotSpec> slots(12);
  names.reserve(80);
  choices.reserve(40);
  for (int i = 0; i < std::max(num_params, 0); ++i) {
    const uint8_t flags = r.byte();
    names.push_back(r.text());
    relief::ParamSpec& s = params[i];
    s.name = (flags & 1) ? nullptr : names.back().c_str();
    s.type = static_cast<relief::ParamType>((flags >> 1) % 5);  // 4: not a valid type
    s.default_value = r.real();
    s.min_value = r.real();
    s.max_value = r.real();
    choices.push_back(r.text());
    s.choices = (flags & 16) ? nullptr : choices.back().c_str();
    s.help = (flags & 32) ? nullptr : "help";
  }
  for (int i = 0; i < std::max(num_textures, 0); ++i) {
    const uint8_t flags = r.byte();
    names.push_back(r.text());
    slots[i] = {(flags & 1) ? nullptr : names.back().c_str(), (flags & 2) != 0, nullptr};
  }
  const std::string plugin_name = r.text();
  relief::PluginDescriptor d{};
  d.abi_version = relief::kPluginAbiVersion;
  d.name = plugin_name.c_str();
  d.description = "fuzz";
  d.params = params.data();
  d.num_params = num_params;
  d.textures = slots.data();
  d.num_textures = num_textures;
  d.select = select_none;
  d.depth_output = depth_none;

  relief::PluginRegistry registry;
  relief::Status s = registry.add(&d);
  if (!s.ok()) {
    one_line(s.message());
    return 0;
  }
  (void)relief::describe_params(d);
  std::map<std::string, float> overrides;
  std::map<std::string, std::string> text;
  while (r.n) {
    const std::string key = r.text();
    if (r.byte() & 1)
      overrides[key] = r.real();
    else
      text[key] = r.text();
  }
  relief::Result<std::vector<float>> v = relief::resolve_params(d, overrides, text);
  if (!v.ok()) {
    one_line(v.status().message());
    return 0;
  }
  for (int k = 0; k < d.num_params; ++k) {
    const relief::ParamSpec& p = d.params[k];
    const float x = (*v)[k];
    if (!(x == x)) __builtin_trap();
    if ((p.type == relief::ParamType::kFloat || p.type == relief::ParamType::kInt) &&
        (x < p.min_value || x > p.max_value))
      __builtin_trap();
  }
  return 0;
}
