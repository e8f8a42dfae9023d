// glTF input, the Reader's checks of JSON values (scene/gltf_internal.h): the objects of the
// extensions it reads (RELIEF_relief_mapping, docs/relief_mapping.schema.json; KHR_*) with known
// keys only, and numbers, integers, booleans and vectors in range. Every error is one line that
// names the file and the JSON pointer of the offending value (scene/gltf.h).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "scene/gltf_internal.h"
#include "scene/gltf_validate.h"

namespace relief::gltf_detail {

// Pointer and text kept on one line and short (names and keys come from the file).
Status Reader::fail(const std::string& pointer, const std::string& what) const {
  return Status::error(path_ + ": " + one_line_text(pointer, 100) + ": " +
                       one_line_text(what, 180));
}

Result<json> Reader::parse_json(const std::string& text) {
  if (text.empty()) return json::object();
  json j = json::parse(text, nullptr, false);
  if (!j.is_discarded() && j.is_null()) return json::object();  // tinygltf: no extensions
  if (j.is_discarded() || !j.is_object()) return Status::error("malformed extension JSON");
  return j;
}

// The object `name` inside an extensions JSON string, or null.
Result<json> Reader::extension(const std::string& extensions_json, const char* name,
                               const std::string& pointer) const {
  Result<json> all = parse_json(extensions_json);
  if (!all.ok()) return fail(pointer + "/extensions", all.status().message());
  auto it = all->find(name);
  if (it == all->end()) return json();
  if (!it->is_object()) return fail(pointer + "/extensions/" + name, "expected an object");
  return *it;
}

Status Reader::check_keys(const json& obj, const std::string& pointer,
                          const std::vector<std::string>& known) const {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (it.key() == "extensions" || it.key() == "extras") continue;
    if (std::find(known.begin(), known.end(), it.key()) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      return fail(pointer + "/" + pointer_token(it.key()),
                  "unknown property (expected one of " + list + ")");
    }
  }
  return {};
}

Status Reader::get_number(const json& obj, const char* key, const std::string& pointer, double& out,
                          double lo, double hi) const {
  auto it = obj.find(key);
  if (it == obj.end()) return {};
  const std::string p = pointer + "/" + key;
  if (!it->is_number()) return fail(p, "expected a number, got " + it->dump());
  const double v = it->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream os;
    os << v << " is outside [" << lo << ", " << hi << "]";
    return fail(p, os.str());
  }
  out = v;
  return {};
}

Status Reader::get_int(const json& obj, const char* key, const std::string& pointer, int& out,
                       int lo, int hi) const {
  auto it = obj.find(key);
  if (it == obj.end()) return {};
  const std::string p = pointer + "/" + key;
  if (!it->is_number_integer() &&
      !(it->is_number_float() && std::floor(it->get<double>()) == it->get<double>()))
    return fail(p, "expected an integer, got " + it->dump());
  const double v = it->get<double>();
  if (v < lo || v > hi)
    return fail(p, it->dump() + " is outside " + std::to_string(lo) + ".." + std::to_string(hi));
  out = static_cast<int>(v);
  return {};
}

Status Reader::get_bool(const json& obj, const char* key, const std::string& pointer,
                        bool& out) const {
  auto it = obj.find(key);
  if (it == obj.end()) return {};
  if (!it->is_boolean())
    return fail(pointer + "/" + key, "expected true or false, got " + it->dump());
  out = it->get<bool>();
  return {};
}

std::string Reader::fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

}  // namespace relief::gltf_detail
