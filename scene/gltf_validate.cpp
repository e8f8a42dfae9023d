#include "scene/gltf_validate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rasterizer/safe_file.h"
#include "scene/gltf_decode.h"
#include "scene/gltf_extensions.h"
#include "scene/scene.h"

namespace relief {

std::string pointer_token(std::string_view key) {
  std::string out;
  for (char c : key) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::string one_line_text(std::string_view s, size_t max) {
  return printable(s, max, /*escape_backslash=*/false);
}

Status check_json_nesting(std::string_view text, const std::string& path) {
  int depth = 0;
  size_t line = 1, line_start = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;  // the escaped character (a quote or a backslash) is not structure
      else if (c == '"')
        in_string = false;
      continue;
    }
    switch (c) {
      case '"':
        in_string = true;
        break;
      case '\n':
        ++line;
        line_start = i + 1;
        break;
      case '[':
      case '{':
        if (++depth > kMaxJsonNesting)
          return Status::error(path + ": JSON nesting deeper than " +
                               std::to_string(kMaxJsonNesting) + " levels (line " +
                               std::to_string(line) + ", column " +
                               std::to_string(i - line_start + 1) + ")");
        break;
      case ']':
      case '}':
        if (depth > 0) --depth;
        break;
      default:
        break;
    }
  }
  return {};
}

namespace {

using json = nlohmann::json;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kHalfPi = 1.57079632679489661923;
constexpr double kMaxIndex = 2147483647.0;

// A value as a message shows it: scalars as JSON (strings shortened, control bytes escaped).
std::string shown(const json& v) {
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  std::string s = v.dump(-1, ' ', true, json::error_handler_t::replace);
  if (s.size() > 40) s = s.substr(0, 36) + "...";
  return s;
}

std::string num(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

bool integral(const json& v) {
  if (v.is_number_integer()) return true;  // signed or unsigned
  if (!v.is_number_float()) return false;
  const double d = v.get<double>();
  return std::isfinite(d) && std::floor(d) == d;
}

// "2.0" -> (2, 0); false unless the text is ^[0-9]+\.[0-9]+$ (each part at most 9 digits).
bool parse_version(const std::string& s, long& major, long& minor) {
  const size_t dot = s.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == s.size() || dot > 9 ||
      s.size() - dot - 1 > 9)
    return false;
  for (size_t i = 0; i < s.size(); ++i)
    if (i != dot && (s[i] < '0' || s[i] > '9')) return false;
  major = std::stol(s.substr(0, dot));
  minor = std::stol(s.substr(dot + 1));
  return true;
}

int components(const std::string& type) {
  if (type == "SCALAR") return 1;
  if (type == "VEC2") return 2;
  if (type == "VEC3") return 3;
  if (type == "VEC4") return 4;
  if (type == "MAT2") return 4;
  if (type == "MAT3") return 9;
  if (type == "MAT4") return 16;
  return 0;
}

int component_size(int64_t ctype) {
  switch (ctype) {
    case 5120:
    case 5121:
      return 1;
    case 5122:
    case 5123:
      return 2;
    case 5125:
    case 5126:
      return 4;
    default:
      return 0;
  }
}

class Validator {
 public:
  Validator(const json& doc, const std::string& path) : doc_(doc), path_(path) {}

  Status run() {
    if (!doc_.is_object()) return fail("", "expected a JSON object");
    RELIEF_RETURN_IF_ERROR(asset());
    RELIEF_RETURN_IF_ERROR(extensions_lists());
    for (const char* a :
         {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials",
          "meshes", "nodes", "samplers", "scenes", "skins", "textures"})
      RELIEF_RETURN_IF_ERROR(top_array(a));
    RELIEF_RETURN_IF_ERROR(common(doc_, ""));
    RELIEF_RETURN_IF_ERROR(index(doc_, "", "scene", "scenes"));
    RELIEF_RETURN_IF_ERROR(each("buffers", &Validator::buffer));
    RELIEF_RETURN_IF_ERROR(each("bufferViews", &Validator::buffer_view));
    RELIEF_RETURN_IF_ERROR(each("accessors", &Validator::accessor));
    RELIEF_RETURN_IF_ERROR(each("images", &Validator::image));
    RELIEF_RETURN_IF_ERROR(each("samplers", &Validator::sampler));
    RELIEF_RETURN_IF_ERROR(each("textures", &Validator::texture));
    RELIEF_RETURN_IF_ERROR(each("materials", &Validator::material));
    RELIEF_RETURN_IF_ERROR(each("meshes", &Validator::mesh));
    RELIEF_RETURN_IF_ERROR(each("cameras", &Validator::camera));
    RELIEF_RETURN_IF_ERROR(each("skins", &Validator::skin));
    RELIEF_RETURN_IF_ERROR(each("nodes", &Validator::node));
    RELIEF_RETURN_IF_ERROR(each("scenes", &Validator::scene));
    RELIEF_RETURN_IF_ERROR(each("animations", &Validator::animation));
    RELIEF_RETURN_IF_ERROR(lights());
    RELIEF_RETURN_IF_ERROR(hierarchy());
    return draw_counts();
  }

 private:
  using Check = Status (Validator::*)(const json&, const std::string&);

  Status fail(const std::string& pointer, const std::string& what) const {
    return Status::error(path_ + ": " + one_line_text(pointer.empty() ? "/" : pointer, 100) + ": " +
                         one_line_text(what, 180));
  }
  static std::string at(const std::string& p, const std::string& key) {
    return p + "/" + pointer_token(key);
  }
  static std::string at(const std::string& p, size_t i) { return p + "/" + std::to_string(i); }

  const json* array(const char* name) const {
    auto it = doc_.find(name);
    return it != doc_.end() && it->is_array() ? &*it : nullptr;
  }
  size_t count(const char* name) const {
    const json* a = array(name);
    return a ? a->size() : 0;
  }
  const json& item(const char* name, int64_t i) const { return (*array(name))[i]; }

  Status each(const char* name, Check check) {
    const json* a = array(name);
    if (!a) return {};
    for (size_t i = 0; i < a->size(); ++i) {
      const std::string p = at(std::string("/") + name, i);
      RELIEF_RETURN_IF_ERROR(common((*a)[i], p));
      RELIEF_RETURN_IF_ERROR((this->*check)((*a)[i], p));
    }
    return {};
  }

  // A top-level array: an array of objects.
  Status top_array(const char* name) const {
    auto it = doc_.find(name);
    if (it == doc_.end()) return {};
    const std::string p = std::string("/") + name;
    if (!it->is_array()) return fail(p, "expected an array, got " + shown(*it));
    for (size_t i = 0; i < it->size(); ++i)
      if (!(*it)[i].is_object())
        return fail(at(p, i), "expected an object, got " + shown((*it)[i]));
    return {};
  }

  // name: a string; extensions: an object of objects.
  Status common(const json& o, const std::string& p) const {
    RELIEF_RETURN_IF_ERROR(string(o, p, "name"));
    auto it = o.find("extensions");
    if (it == o.end()) return {};
    if (!it->is_object()) return fail(at(p, "extensions"), "expected an object, got " + shown(*it));
    for (auto e = it->begin(); e != it->end(); ++e)
      if (!e->is_object())
        return fail(at(at(p, "extensions"), e.key()), "expected an object, got " + shown(*e));
    return {};
  }

  const json* find(const json& o, const char* key) const {
    auto it = o.find(key);
    return it == o.end() ? nullptr : &*it;
  }
  Status require(const json& o, const std::string& p, const char* key) const {
    if (!o.contains(key)) return fail(p, std::string("missing '") + key + "'");
    return {};
  }

  Status integer(const json& o, const std::string& p, const char* key, double lo, double hi,
                 int64_t* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    const std::string vp = at(p, key);
    const std::string range = hi >= kMaxIndex ? ">= " + num(lo) : "in " + num(lo) + ".." + num(hi);
    if (!integral(*v)) return fail(vp, "expected an integer " + range + ", got " + shown(*v));
    const double d = v->get<double>();
    if (d < lo || d > hi) return fail(vp, "expected an integer " + range + ", got " + shown(*v));
    if (out) *out = static_cast<int64_t>(d);
    return {};
  }
  // An index into the top-level array `into`.
  Status index(const json& o, const std::string& p, const char* key, const char* into,
               int64_t* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    return index_value(*v, at(p, key), into, out);
  }
  Status index_value(const json& v, const std::string& vp, const char* into,
                     int64_t* out = nullptr) const {
    const size_t n = count(into);
    const std::string where = std::string("/") + into;
    if (!integral(v) || v.get<double>() < 0 || v.get<double>() >= static_cast<double>(n))
      return fail(vp, n == 0 ? "expected an index into " + where +
                                   ", which is empty or absent, got " + shown(v)
                             : "expected an index into " + where + " (0.." + std::to_string(n - 1) +
                                   "), got " + shown(v));
    if (out) *out = static_cast<int64_t>(v.get<double>());
    return {};
  }
  // An array of unique indices into `into`, at least one unless `allow_empty`.
  Status indices(const json& o, const std::string& p, const char* key, const char* into,
                 bool allow_empty = false) const {
    const json* v = find(o, key);
    if (!v) return {};
    const std::string vp = at(p, key);
    if (!v->is_array() || (v->empty() && !allow_empty))
      return fail(vp, "expected a non-empty array of indices, got " + shown(*v));
    std::set<int64_t> seen;
    for (size_t i = 0; i < v->size(); ++i) {
      int64_t k = 0;
      RELIEF_RETURN_IF_ERROR(index_value((*v)[i], at(vp, i), into, &k));
      if (!seen.insert(k).second) return fail(at(vp, i), std::to_string(k) + " is listed twice");
    }
    return {};
  }
  Status number(const json& o, const std::string& p, const char* key, double lo, double hi,
                bool lo_open = false, double* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    const std::string vp = at(p, key);
    const std::string range = hi == kInf
                                  ? (lo_open ? "> " : ">= ") + num(lo)
                                  : (lo_open ? "in (" : "in [") + num(lo) + ", " + num(hi) + "]";
    if (!v->is_number()) return fail(vp, "expected a number " + range + ", got " + shown(*v));
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < lo || (lo_open && d == lo) || d > hi)
      return fail(vp, "expected a number " + range + ", got " + shown(*v));
    if (out) *out = d;
    return {};
  }
  Status numbers(const json& o, const std::string& p, const char* key, size_t n, double lo,
                 double hi) const {
    const json* v = find(o, key);
    if (!v) return {};
    const std::string vp = at(p, key);
    if (!v->is_array() || (n > 0 && v->size() != n) || (n == 0 && v->empty()))
      return fail(vp, n > 0 ? "expected an array of " + std::to_string(n) + " numbers"
                            : "expected a non-empty array of numbers");
    for (size_t i = 0; i < v->size(); ++i) {
      const json& x = (*v)[i];
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
          x.get<double>() > hi)
        return fail(at(vp, i), (hi == kInf && lo == -kInf
                                    ? std::string("expected a finite number")
                                    : "expected a number in [" + num(lo) + ", " + num(hi) + "]") +
                                   ", got " + shown(x));
    }
    return {};
  }
  Status boolean(const json& o, const std::string& p, const char* key) const {
    const json* v = find(o, key);
    if (v && !v->is_boolean()) return fail(at(p, key), "expected true or false, got " + shown(*v));
    return {};
  }
  Status string(const json& o, const std::string& p, const char* key,
                std::string* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    if (!v->is_string()) return fail(at(p, key), "expected a string, got " + shown(*v));
    if (out) *out = v->get<std::string>();
    return {};
  }
  Status one_of(const json& o, const std::string& p, const char* key,
                const std::vector<std::string>& values, std::string* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    std::string list;
    for (const auto& s : values) list += (list.empty() ? "" : ", ") + s;
    if (!v->is_string() ||
        std::find(values.begin(), values.end(), v->get<std::string>()) == values.end())
      return fail(at(p, key), "expected one of " + list + ", got " + shown(*v));
    if (out) *out = v->get<std::string>();
    return {};
  }
  Status gl_enum(const json& o, const std::string& p, const char* key, const char* what,
                 const std::vector<int>& values, int64_t* out = nullptr) const {
    const json* v = find(o, key);
    if (!v) return {};
    std::string list;
    for (int x : values) list += (list.empty() ? "" : ", ") + std::to_string(x);
    const bool ok =
        integral(*v) && std::find(values.begin(), values.end(), v->get<double>()) != values.end();
    if (!ok) {
      if (v->is_number_integer())
        return fail(at(p, key),
                    "unknown " + std::string(what) + " " + shown(*v) + " (expected " + list + ")");
      return fail(at(p, key),
                  "expected a " + std::string(what) + " (" + list + "), got " + shown(*v));
    }
    if (out) *out = static_cast<int64_t>(v->get<double>());
    return {};
  }
  Status object(const json& o, const std::string& p, const char* key,
                const json** out = nullptr) const {
    const json* v = find(o, key);
    if (out) *out = nullptr;
    if (!v) return {};
    if (!v->is_object()) return fail(at(p, key), "expected an object, got " + shown(*v));
    RELIEF_RETURN_IF_ERROR(common(*v, at(p, key)));
    if (out) *out = v;
    return {};
  }

  // ---- the parts ----
  Status asset() {
    const json* a = find(doc_, "asset");
    if (!a) return fail("", "missing 'asset' (not a glTF 2.0 file)");
    if (!a->is_object()) return fail("/asset", "expected an object, got " + shown(*a));
    RELIEF_RETURN_IF_ERROR(common(*a, "/asset"));
    for (const char* k : {"copyright", "generator"})
      RELIEF_RETURN_IF_ERROR(string(*a, "/asset", k));
    RELIEF_RETURN_IF_ERROR(require(*a, "/asset", "version"));
    std::string version;
    RELIEF_RETURN_IF_ERROR(string(*a, "/asset", "version", &version));
    long major = 0, minor = 0;
    if (!parse_version(version, major, minor))
      return fail("/asset/version",
                  "expected a version like \"2.0\", got " + shown((*a)["version"]));
    if (major != 2)
      return fail("/asset/version", "glTF " + version + " is not supported (only glTF 2.x)");
    if (a->contains("minVersion")) {
      std::string min;
      RELIEF_RETURN_IF_ERROR(string(*a, "/asset", "minVersion", &min));
      long mmaj = 0, mmin = 0;
      if (!parse_version(min, mmaj, mmin))
        return fail("/asset/minVersion",
                    "expected a version like \"2.0\", got " + shown((*a)["minVersion"]));
      if (mmaj != 2 || mmin > 0)
        return fail("/asset/minVersion", "the file needs glTF " + min + "; relief reads glTF 2.0");
      if (mmaj > major || (mmaj == major && mmin > minor))
        return fail("/asset/minVersion", min + " is later than the version " + version);
    }
    return {};
  }

  Status extensions_lists() {
    std::vector<std::string> used, required;
    for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
      const json* v = find(doc_, key);
      if (!v) continue;
      const std::string p = std::string("/") + key;
      if (!v->is_array()) return fail(p, "expected an array of extension names, got " + shown(*v));
      std::vector<std::string>& out = key[10] == 'U' ? used : required;
      for (size_t i = 0; i < v->size(); ++i) {
        const json& x = (*v)[i];
        if (!x.is_string()) return fail(at(p, i), "expected an extension name, got " + shown(x));
        const std::string name = x.get<std::string>();
        if (std::find(out.begin(), out.end(), name) != out.end())
          return fail(at(p, i), shown(x) + " is listed twice");
        out.push_back(name);
      }
    }
    auto supported = [](const std::string& n) { return gltf_extension_supported(n); };
    for (size_t i = 0; i < required.size(); ++i) {
      const std::string p = at("/extensionsRequired", i);
      if (std::find(used.begin(), used.end(), required[i]) == used.end())
        return fail(p,
                    "required extension " + shown(json(required[i])) + " is not in extensionsUsed");
      if (!supported(required[i]))
        return fail(p, "required extension " + shown(json(required[i])) + " is not supported");
    }
    return {};  // (a used extension relief lacks is a warning once the load succeeds: gltf.cpp)
  }

  Status buffer(const json& b, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(string(b, p, "uri"));
    if (const json* e = extension(b, kMeshoptCompression))
      RELIEF_RETURN_IF_ERROR(boolean(*e, at(at(p, "extensions"), kMeshoptCompression), "fallback"));
    RELIEF_RETURN_IF_ERROR(require(b, p, "byteLength"));
    return integer(b, p, "byteLength", 1, 9007199254740992.0);
  }

  Status buffer_view(const json& v, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(require(v, p, "buffer"));
    int64_t buf = 0, offset = 0, length = 0;
    RELIEF_RETURN_IF_ERROR(index(v, p, "buffer", "buffers", &buf));
    RELIEF_RETURN_IF_ERROR(integer(v, p, "byteOffset", 0, 9007199254740992.0, &offset));
    RELIEF_RETURN_IF_ERROR(require(v, p, "byteLength"));
    RELIEF_RETURN_IF_ERROR(integer(v, p, "byteLength", 1, 9007199254740992.0, &length));
    if (v.contains("byteStride")) {
      int64_t stride = 0;
      RELIEF_RETURN_IF_ERROR(integer(v, p, "byteStride", 4, 252, &stride));
      if (stride % 4)
        return fail(at(p, "byteStride"),
                    "expected a multiple of 4 in 4..252, got " + std::to_string(stride));
    }
    RELIEF_RETURN_IF_ERROR(gl_enum(v, p, "target", "buffer view target", {34962, 34963}));
    RELIEF_RETURN_IF_ERROR(meshopt_view(v, p));
    const double have = item("buffers", buf)["byteLength"].get<double>();
    if (static_cast<double>(offset) + static_cast<double>(length) > have)
      return fail(p, "bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
                         " lie outside their buffer (buffer " + std::to_string(buf) +
                         ", byteLength " + num(have) + ")");
    return {};
  }

  Status accessor(const json& a, const std::string& p) {
    int64_t view = -1, offset = 0, ctype = 0, n = 0;
    RELIEF_RETURN_IF_ERROR(index(a, p, "bufferView", "bufferViews", &view));
    RELIEF_RETURN_IF_ERROR(integer(a, p, "byteOffset", 0, 9007199254740992.0, &offset));
    if (a.contains("byteOffset") && view < 0)
      return fail(at(p, "byteOffset"), "given without a bufferView");
    RELIEF_RETURN_IF_ERROR(require(a, p, "componentType"));
    RELIEF_RETURN_IF_ERROR(gl_enum(a, p, "componentType", "component type",
                                   {5120, 5121, 5122, 5123, 5125, 5126}, &ctype));
    RELIEF_RETURN_IF_ERROR(boolean(a, p, "normalized"));
    if (a.value("normalized", false) == true && (ctype == 5125 || ctype == 5126))
      return fail(at(p, "normalized"), "FLOAT and UNSIGNED_INT accessors cannot be normalized");
    RELIEF_RETURN_IF_ERROR(require(a, p, "count"));
    if (integral(a["count"]) && a["count"].get<double>() < 1)
      return fail(at(p, "count"), "accessor has no elements (count " + shown(a["count"]) + ")");
    RELIEF_RETURN_IF_ERROR(integer(a, p, "count", 1, 9007199254740992.0, &n));
    RELIEF_RETURN_IF_ERROR(require(a, p, "type"));
    std::string type;
    RELIEF_RETURN_IF_ERROR(
        one_of(a, p, "type", {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"}, &type));
    const int comps = components(type);
    RELIEF_RETURN_IF_ERROR(numbers(a, p, "min", comps, -kInf, kInf));
    RELIEF_RETURN_IF_ERROR(numbers(a, p, "max", comps, -kInf, kInf));
    const json* sparse = nullptr;
    RELIEF_RETURN_IF_ERROR(object(a, p, "sparse", &sparse));
    if (sparse) {
      RELIEF_RETURN_IF_ERROR(require(*sparse, at(p, "sparse"), "count"));
      RELIEF_RETURN_IF_ERROR(integer(*sparse, at(p, "sparse"), "count", 1, static_cast<double>(n)));
    }
    if (view < 0) return {};
    // The elements lie inside the buffer view, aligned to their component size.
    const json& bv = item("bufferViews", view);
    const std::string bp = at("/bufferViews", static_cast<size_t>(view));
    const int csize = component_size(ctype);
    const double elem = static_cast<double>(comps) * csize;
    const double stride = bv.contains("byteStride") ? bv["byteStride"].get<double>() : elem;
    const double length = bv["byteLength"].get<double>();
    const double view_offset = bv.value("byteOffset", 0.0);
    if (stride < elem)
      return fail(at(bp, "byteStride"), "stride " + num(stride) + " is smaller than an element (" +
                                            num(elem) + " bytes) of " + p);
    if (offset % csize || static_cast<int64_t>(view_offset) % csize ||
        static_cast<int64_t>(stride) % csize)
      return fail(at(p, "byteOffset"), "elements are not aligned to their " +
                                           std::to_string(csize) + "-byte components");
    const double need = static_cast<double>(offset) + stride * static_cast<double>(n - 1) + elem;
    if (need > length)
      return fail(p, std::to_string(n) + " elements of " + num(elem) + " bytes at offset " +
                         std::to_string(offset) + " need " + num(need) + " bytes; buffer view " +
                         std::to_string(view) + " has " + num(length));
    return {};
  }

  Status image(const json& im, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(string(im, p, "uri"));
    RELIEF_RETURN_IF_ERROR(string(im, p, "mimeType"));
    RELIEF_RETURN_IF_ERROR(index(im, p, "bufferView", "bufferViews"));
    if (im.contains("uri") && im.contains("bufferView"))
      return fail(p, "give either 'uri' or 'bufferView', not both");
    if (im.contains("bufferView") && !im.contains("mimeType"))
      return fail(p, "an image in a buffer view needs a 'mimeType'");
    if (!im.contains("uri") && !im.contains("bufferView"))
      return fail(p, "an image needs a 'uri' or a 'bufferView'");
    return {};
  }

  Status sampler(const json& s, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(gl_enum(s, p, "magFilter", "filter", {9728, 9729}));
    RELIEF_RETURN_IF_ERROR(
        gl_enum(s, p, "minFilter", "filter", {9728, 9729, 9984, 9985, 9986, 9987}));
    RELIEF_RETURN_IF_ERROR(gl_enum(s, p, "wrapS", "wrap mode", {33071, 33648, 10497}));
    return gl_enum(s, p, "wrapT", "wrap mode", {33071, 33648, 10497});
  }

  Status texture(const json& t, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(index(t, p, "sampler", "samplers"));
    if (const json* w = extension(t, kTextureWebp)) {
      const std::string wp = at(at(p, "extensions"), kTextureWebp);
      RELIEF_RETURN_IF_ERROR(require(*w, wp, "source"));
      RELIEF_RETURN_IF_ERROR(index(*w, wp, "source", "images"));
    }
    return index(t, p, "source", "images");
  }

  // ---- compression and quantization (scene/gltf_decode.h) ----
  const json* extension(const json& o, const char* name) const {
    const json* e = find(o, "extensions");
    return e && e->is_object() ? find(*e, name) : nullptr;  // (common() checked it is an object)
  }
  bool used(const char* name) const {
    const json* u = find(doc_, "extensionsUsed");
    if (!u || !u->is_array()) return false;
    for (const json& x : *u)
      if (x.is_string() && x.get_ref<const std::string&>() == name) return true;
    return false;
  }
  // An attribute's accessor has the type and one of the component types glTF lists for its
  // semantic (KHR_mesh_quantization's too when the file uses it).
  Status attribute_type(const std::string& semantic, const json& index_json, bool target,
                        const std::string& p) const {
    const std::vector<int> allowed =
        attribute_component_types(semantic, target, used(kMeshQuantization));
    if (allowed.empty()) return {};
    const int64_t ai = static_cast<int64_t>(index_json.get<double>());
    const json& a = item("accessors", ai);
    const std::string want = semantic == "TANGENT" && !target      ? "VEC4"
                             : semantic.rfind("TEXCOORD_", 0) == 0 ? "VEC2"
                                                                   : "VEC3";
    const int ctype = static_cast<int>(a["componentType"].get<double>());
    const bool normalized = a.value("normalized", false) == true;
    const int signed_ctype = normalized ? -ctype : ctype;
    const std::string have = a["type"].get<std::string>();
    if (have == want && std::find(allowed.begin(), allowed.end(), signed_ctype) != allowed.end())
      return {};
    auto name = [](int c) { return component_types_text({c}); };
    return fail(p,
                "accessor " + std::to_string(ai) + " is " + have + " of " + name(signed_ctype) +
                    ", expected " + want + " of " + component_types_text(allowed) +
                    (used(kMeshQuantization) ? "" : " (other types need KHR_mesh_quantization)"));
  }
  Status meshopt_view(const json& v, const std::string& p) {
    const json* e = extension(v, kMeshoptCompression);
    if (!e) return {};
    const std::string ep = at(at(p, "extensions"), kMeshoptCompression);
    int64_t buf = 0, offset = 0, length = 0;
    RELIEF_RETURN_IF_ERROR(require(*e, ep, "buffer"));
    RELIEF_RETURN_IF_ERROR(index(*e, ep, "buffer", "buffers", &buf));
    RELIEF_RETURN_IF_ERROR(integer(*e, ep, "byteOffset", 0, 9007199254740992.0, &offset));
    for (const char* k : {"byteLength", "byteStride", "count"})
      RELIEF_RETURN_IF_ERROR(require(*e, ep, k));
    RELIEF_RETURN_IF_ERROR(integer(*e, ep, "byteLength", 1, 9007199254740992.0, &length));
    RELIEF_RETURN_IF_ERROR(integer(*e, ep, "byteStride", 1, 256));
    RELIEF_RETURN_IF_ERROR(integer(*e, ep, "count", 1, 9007199254740992.0));
    RELIEF_RETURN_IF_ERROR(one_of(*e, ep, "mode", {"ATTRIBUTES", "TRIANGLES", "INDICES"}));
    RELIEF_RETURN_IF_ERROR(
        one_of(*e, ep, "filter", {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"}));
    const double have = item("buffers", buf)["byteLength"].get<double>();
    if (static_cast<double>(offset) + static_cast<double>(length) > have)
      return fail(ep, "bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
                          " lie outside their buffer (buffer " + std::to_string(buf) +
                          ", byteLength " + num(have) + ")");
    return {};
  }
  Status draco_primitive(const json& pr, const std::string& kp) const {
    const json* e = extension(pr, kDracoCompression);
    if (!e) return {};
    const std::string ep = at(at(kp, "extensions"), kDracoCompression);
    RELIEF_RETURN_IF_ERROR(require(*e, ep, "bufferView"));
    RELIEF_RETURN_IF_ERROR(index(*e, ep, "bufferView", "bufferViews"));
    RELIEF_RETURN_IF_ERROR(require(*e, ep, "attributes"));
    const json& attrs = (*e)["attributes"];
    const std::string ap = at(ep, "attributes");
    if (!attrs.is_object() || attrs.empty())
      return fail(ap, "expected an object of Draco attribute ids, got " + shown(attrs));
    const json& prim_attrs = pr["attributes"];
    for (auto it = attrs.begin(); it != attrs.end(); ++it) {
      if (!integral(*it) || it->get<double>() < 0 || it->get<double>() > kMaxIndex)
        return fail(at(ap, it.key()), "expected a Draco attribute id, got " + shown(*it));
      if (!prim_attrs.contains(it.key()))
        return fail(at(ap, it.key()), "the primitive has no attribute " + shown(json(it.key())));
    }
    if (!pr.contains("indices")) return fail(kp, "a Draco-compressed primitive needs 'indices'");
    return {};
  }

  Status texture_info(const json& o, const std::string& p, const char* key, const char* scale_key,
                      double scale_lo, double scale_hi) {
    const json* t = nullptr;
    RELIEF_RETURN_IF_ERROR(object(o, p, key, &t));
    if (!t) return {};
    const std::string tp = at(p, key);
    RELIEF_RETURN_IF_ERROR(require(*t, tp, "index"));
    RELIEF_RETURN_IF_ERROR(index(*t, tp, "index", "textures"));
    RELIEF_RETURN_IF_ERROR(integer(*t, tp, "texCoord", 0, kMaxIndex));
    if (scale_key) RELIEF_RETURN_IF_ERROR(number(*t, tp, scale_key, scale_lo, scale_hi));
    return {};
  }

  Status material(const json& m, const std::string& p) {
    const json* pbr = nullptr;
    RELIEF_RETURN_IF_ERROR(object(m, p, "pbrMetallicRoughness", &pbr));
    if (pbr) {
      const std::string pp = at(p, "pbrMetallicRoughness");
      RELIEF_RETURN_IF_ERROR(numbers(*pbr, pp, "baseColorFactor", 4, 0.0, 1.0));
      RELIEF_RETURN_IF_ERROR(texture_info(*pbr, pp, "baseColorTexture", nullptr, 0, 0));
      RELIEF_RETURN_IF_ERROR(number(*pbr, pp, "metallicFactor", 0.0, 1.0));
      RELIEF_RETURN_IF_ERROR(number(*pbr, pp, "roughnessFactor", 0.0, 1.0));
      RELIEF_RETURN_IF_ERROR(texture_info(*pbr, pp, "metallicRoughnessTexture", nullptr, 0, 0));
    }
    RELIEF_RETURN_IF_ERROR(texture_info(m, p, "normalTexture", "scale", -kInf, kInf));
    RELIEF_RETURN_IF_ERROR(texture_info(m, p, "occlusionTexture", "strength", 0.0, 1.0));
    RELIEF_RETURN_IF_ERROR(texture_info(m, p, "emissiveTexture", nullptr, 0, 0));
    RELIEF_RETURN_IF_ERROR(numbers(m, p, "emissiveFactor", 3, 0.0, 1.0));
    RELIEF_RETURN_IF_ERROR(one_of(m, p, "alphaMode", {"OPAQUE", "MASK", "BLEND"}));
    RELIEF_RETURN_IF_ERROR(number(m, p, "alphaCutoff", 0.0, kInf));
    return boolean(m, p, "doubleSided");
  }

  Status attributes(const json& o, const std::string& p, bool required) {
    const json* v = find(o, "attributes");
    if (!v) return required ? fail(p, "missing 'attributes'") : Status{};
    return attribute_map(*v, at(p, "attributes"));
  }
  Status attribute_map(const json& v, const std::string& p) {
    if (!v.is_object())
      return fail(p, "expected an object of attribute accessors, got " + shown(v));
    if (v.empty()) return fail(p, "expected at least one attribute");
    for (auto it = v.begin(); it != v.end(); ++it)
      RELIEF_RETURN_IF_ERROR(index_value(*it, at(p, it.key()), "accessors"));
    return {};
  }

  Status mesh(const json& m, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(require(m, p, "primitives"));
    const json& prims = m["primitives"];
    const std::string pp = at(p, "primitives");
    if (!prims.is_array() || prims.empty())
      return fail(pp, "a mesh needs a non-empty array of primitives, got " + shown(prims));
    for (size_t k = 0; k < prims.size(); ++k) {
      const json& pr = prims[k];
      const std::string kp = at(pp, k);
      if (!pr.is_object()) return fail(kp, "expected an object, got " + shown(pr));
      RELIEF_RETURN_IF_ERROR(common(pr, kp));
      RELIEF_RETURN_IF_ERROR(attributes(pr, kp, true));
      for (auto a = pr["attributes"].begin(); a != pr["attributes"].end(); ++a)
        RELIEF_RETURN_IF_ERROR(
            attribute_type(a.key(), *a, false, at(at(kp, "attributes"), a.key())));
      RELIEF_RETURN_IF_ERROR(draco_primitive(pr, kp));
      RELIEF_RETURN_IF_ERROR(index(pr, kp, "indices", "accessors"));
      RELIEF_RETURN_IF_ERROR(index(pr, kp, "material", "materials"));
      RELIEF_RETURN_IF_ERROR(integer(pr, kp, "mode", 0, 6));
      if (const json* t = find(pr, "targets")) {
        if (!t->is_array() || t->empty())
          return fail(at(kp, "targets"), "expected a non-empty array of morph targets");
        for (size_t i = 0; i < t->size(); ++i) {
          RELIEF_RETURN_IF_ERROR(attribute_map((*t)[i], at(at(kp, "targets"), i)));
          for (auto a = (*t)[i].begin(); a != (*t)[i].end(); ++a)
            RELIEF_RETURN_IF_ERROR(
                attribute_type(a.key(), *a, true, at(at(at(kp, "targets"), i), a.key())));
        }
      }
    }
    return numbers(m, p, "weights", 0, -kInf, kInf);
  }

  Status camera(const json& c, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(require(c, p, "type"));
    std::string type;
    RELIEF_RETURN_IF_ERROR(one_of(c, p, "type", {"perspective", "orthographic"}, &type));
    const json* per = nullptr;
    const json* ortho = nullptr;
    RELIEF_RETURN_IF_ERROR(object(c, p, "perspective", &per));
    RELIEF_RETURN_IF_ERROR(object(c, p, "orthographic", &ortho));
    if (type == "perspective") {
      if (!per) return fail(p, "missing 'perspective'");
      const std::string cp = at(p, "perspective");
      RELIEF_RETURN_IF_ERROR(number(*per, cp, "aspectRatio", 0.0, kInf, true));
      RELIEF_RETURN_IF_ERROR(require(*per, cp, "yfov"));
      RELIEF_RETURN_IF_ERROR(number(*per, cp, "yfov", 0.0, kInf, true));
      RELIEF_RETURN_IF_ERROR(require(*per, cp, "znear"));
      double znear = 0.0, zfar = kInf;
      RELIEF_RETURN_IF_ERROR(number(*per, cp, "znear", 0.0, kInf, true, &znear));
      RELIEF_RETURN_IF_ERROR(number(*per, cp, "zfar", 0.0, kInf, true, &zfar));
      if (zfar <= znear) return fail(at(cp, "zfar"), "expected a number > znear");
    } else {
      if (!ortho) return fail(p, "missing 'orthographic'");
      const std::string cp = at(p, "orthographic");
      for (const char* k : {"xmag", "ymag", "zfar", "znear"})
        RELIEF_RETURN_IF_ERROR(require(*ortho, cp, k));
      RELIEF_RETURN_IF_ERROR(number(*ortho, cp, "xmag", -kInf, kInf));
      RELIEF_RETURN_IF_ERROR(number(*ortho, cp, "ymag", -kInf, kInf));
      double znear = 0.0, zfar = 0.0;
      RELIEF_RETURN_IF_ERROR(number(*ortho, cp, "znear", 0.0, kInf, false, &znear));
      RELIEF_RETURN_IF_ERROR(number(*ortho, cp, "zfar", 0.0, kInf, true, &zfar));
      if (zfar <= znear) return fail(at(cp, "zfar"), "expected a number > znear");
    }
    return {};
  }

  Status skin(const json& s, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(index(s, p, "inverseBindMatrices", "accessors"));
    RELIEF_RETURN_IF_ERROR(index(s, p, "skeleton", "nodes"));
    RELIEF_RETURN_IF_ERROR(require(s, p, "joints"));
    if (s["joints"].is_array() && s["joints"].empty())
      return fail(at(p, "joints"), "a skin needs at least one joint");
    return indices(s, p, "joints", "nodes");
  }

  Status node(const json& n, const std::string& p) {
    RELIEF_RETURN_IF_ERROR(index(n, p, "camera", "cameras"));
    RELIEF_RETURN_IF_ERROR(index(n, p, "skin", "skins"));
    RELIEF_RETURN_IF_ERROR(index(n, p, "mesh", "meshes"));
    RELIEF_RETURN_IF_ERROR(indices(n, p, "children", "nodes"));
    if (n.contains("skin") && !n.contains("mesh"))
      return fail(at(p, "skin"), "a skin needs a mesh on its node");
    RELIEF_RETURN_IF_ERROR(numbers(n, p, "translation", 3, -kInf, kInf));
    RELIEF_RETURN_IF_ERROR(numbers(n, p, "rotation", 4, -1.0 - 1e-5, 1.0 + 1e-5));
    RELIEF_RETURN_IF_ERROR(numbers(n, p, "scale", 3, -kInf, kInf));
    RELIEF_RETURN_IF_ERROR(numbers(n, p, "weights", 0, -kInf, kInf));
    if (n.contains("matrix")) {
      RELIEF_RETURN_IF_ERROR(numbers(n, p, "matrix", 16, -kInf, kInf));
      for (const char* k : {"translation", "rotation", "scale"})
        if (n.contains(k))
          return fail(at(p, "matrix"), std::string("given together with '") + k +
                                           "' (a node has a matrix or TRS, not both)");
      const json& m = n["matrix"];  // column-major: m[4 * column + row]
      double e[16];
      for (int i = 0; i < 16; ++i) e[i] = m[i].get<double>();
      if (e[3] != 0.0 || e[7] != 0.0 || e[11] != 0.0 || e[15] != 1.0)
        return fail(at(p, "matrix"), "not affine: the last row is " + num(e[3]) + " " + num(e[7]) +
                                         " " + num(e[11]) + " " + num(e[15]) +
                                         ", expected 0 0 0 1");
      const double det = e[0] * (e[5] * e[10] - e[9] * e[6]) - e[4] * (e[1] * e[10] - e[9] * e[2]) +
                         e[8] * (e[1] * e[6] - e[5] * e[2]);
      double norm = 0.0;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) norm = std::max(norm, std::abs(e[4 * c + r]));
      if (!std::isfinite(det) || std::abs(det) <= 1e-12 * norm * norm * norm || norm == 0.0)
        return fail(at(p, "matrix"), "singular (its 3x3 part has determinant " + num(det) + ")");
    }
    return {};
  }

  // An empty scene is allowed (the schema asks for one node; an empty list is harmless).
  Status scene(const json& s, const std::string& p) {
    return indices(s, p, "nodes", "nodes", true);
  }

  Status animation(const json& a, const std::string& p) {
    for (const char* k : {"channels", "samplers"}) {
      RELIEF_RETURN_IF_ERROR(require(a, p, k));
      if (!a[k].is_array() || a[k].empty())
        return fail(at(p, k), "expected a non-empty array, got " + shown(a[k]));
      for (size_t i = 0; i < a[k].size(); ++i) {
        if (!a[k][i].is_object())
          return fail(at(at(p, k), i), "expected an object, got " + shown(a[k][i]));
        RELIEF_RETURN_IF_ERROR(common(a[k][i], at(at(p, k), i)));
      }
    }
    const json& samplers = a["samplers"];
    for (size_t i = 0; i < samplers.size(); ++i) {
      const std::string sp = at(at(p, "samplers"), i);
      for (const char* k : {"input", "output"}) {
        RELIEF_RETURN_IF_ERROR(require(samplers[i], sp, k));
        RELIEF_RETURN_IF_ERROR(index(samplers[i], sp, k, "accessors"));
      }
      RELIEF_RETURN_IF_ERROR(string(samplers[i], sp, "interpolation"));
    }
    const json& channels = a["channels"];
    for (size_t i = 0; i < channels.size(); ++i) {
      const std::string cp = at(at(p, "channels"), i);
      const json& c = channels[i];
      RELIEF_RETURN_IF_ERROR(require(c, cp, "sampler"));
      const json& s = c["sampler"];
      if (!integral(s) || s.get<double>() < 0 ||
          s.get<double>() >= static_cast<double>(samplers.size()))
        return fail(at(cp, "sampler"), "expected an index into " + at(p, "samplers") + " (0.." +
                                           std::to_string(samplers.size() - 1) + "), got " +
                                           shown(s));
      RELIEF_RETURN_IF_ERROR(require(c, cp, "target"));
      const json* t = nullptr;
      RELIEF_RETURN_IF_ERROR(object(c, cp, "target", &t));
      const std::string tp = at(cp, "target");
      RELIEF_RETURN_IF_ERROR(index(*t, tp, "node", "nodes"));
      RELIEF_RETURN_IF_ERROR(require(*t, tp, "path"));
      RELIEF_RETURN_IF_ERROR(string(*t, tp, "path"));
    }
    return {};
  }

  // KHR_lights_punctual's lights (the node references are read by the loader).
  Status lights() {
    const json* ext = find(doc_, "extensions");
    if (!ext || !ext->contains("KHR_lights_punctual")) return {};
    const json& k = (*ext)["KHR_lights_punctual"];
    const std::string p = "/extensions/KHR_lights_punctual";
    const json* ls = find(k, "lights");
    if (!ls) return {};
    if (!ls->is_array()) return fail(at(p, "lights"), "expected an array, got " + shown(*ls));
    for (size_t i = 0; i < ls->size(); ++i) {
      const json& l = (*ls)[i];
      const std::string lp = at(at(p, "lights"), i);
      if (!l.is_object()) return fail(lp, "expected an object, got " + shown(l));
      RELIEF_RETURN_IF_ERROR(common(l, lp));
      RELIEF_RETURN_IF_ERROR(require(l, lp, "type"));
      RELIEF_RETURN_IF_ERROR(string(l, lp, "type"));
      RELIEF_RETURN_IF_ERROR(numbers(l, lp, "color", 3, 0.0, kInf));
      RELIEF_RETURN_IF_ERROR(number(l, lp, "intensity", 0.0, kInf));
      RELIEF_RETURN_IF_ERROR(number(l, lp, "range", 0.0, kInf, true));
      const json* spot = nullptr;
      RELIEF_RETURN_IF_ERROR(object(l, lp, "spot", &spot));
      if (spot) {
        RELIEF_RETURN_IF_ERROR(number(*spot, at(lp, "spot"), "innerConeAngle", 0.0, kHalfPi));
        RELIEF_RETURN_IF_ERROR(
            number(*spot, at(lp, "spot"), "outerConeAngle", 0.0, kHalfPi + 1e-9, true));
      }
    }
    return {};
  }

  // The nodes form a forest: each node has at most one parent, no node is its own ancestor, no
  // chain is deeper than kMaxNodeDepth, and a scene lists only roots. Iterative throughout.
  Status hierarchy() {
    const size_t n = count("nodes");
    if (n == 0) return {};
    std::vector<int64_t> parent(n, -1);
    std::vector<size_t> parent_slot(n, 0);
    for (size_t i = 0; i < n; ++i) {
      const json* c = find(item("nodes", static_cast<int64_t>(i)), "children");
      if (!c) continue;
      for (size_t k = 0; k < c->size(); ++k) {
        const int64_t child = static_cast<int64_t>((*c)[k].get<double>());
        const std::string cp = at(at(at("/nodes", i), "children"), k);
        if (parent[child] >= 0)
          return fail(cp, "node " + std::to_string(child) + " is already a child of /nodes/" +
                              std::to_string(parent[child]) + " (a node has one parent)");
        if (static_cast<size_t>(child) == i) return fail(cp, "a node cannot be its own child");
        parent[child] = static_cast<int64_t>(i);
        parent_slot[child] = k;
      }
    }
    std::vector<int> depth(n, 0);  // 0: not known yet
    std::vector<char> on_path(n, 0);
    std::vector<int64_t> chain;
    for (size_t i = 0; i < n; ++i) {
      if (depth[i]) continue;
      chain.clear();
      int64_t j = static_cast<int64_t>(i);
      while (j >= 0 && depth[j] == 0 && !on_path[j]) {
        on_path[j] = 1;
        chain.push_back(j);
        j = parent[j];
      }
      if (j >= 0 && on_path[j])
        return fail(
            at(at(at("/nodes", static_cast<size_t>(parent[j])), "children"), parent_slot[j]),
            "node " + std::to_string(j) + " is its own ancestor (a cycle)");
      int d = j >= 0 ? depth[j] : 0;
      for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        depth[*it] = ++d;
        on_path[*it] = 0;
        if (d > kMaxNodeDepth)
          return fail(at("/nodes", static_cast<size_t>(*it)),
                      "node is " + std::to_string(d) +
                          " levels deep in the hierarchy, more than the limit of " +
                          std::to_string(kMaxNodeDepth));
      }
    }
    const json* scenes = array("scenes");
    for (size_t s = 0; scenes && s < scenes->size(); ++s) {
      const json* roots = find((*scenes)[s], "nodes");
      for (size_t r = 0; roots && r < roots->size(); ++r) {
        const int64_t k = static_cast<int64_t>((*roots)[r].get<double>());
        if (parent[k] >= 0)
          return fail(at(at(at("/scenes", s), "nodes"), r),
                      "node " + std::to_string(k) + " is a child of /nodes/" +
                          std::to_string(parent[k]) + ", not a root");
      }
    }
    return {};
  }

  uint64_t accessor_count(const json* index) const {
    if (!index) return 0;
    return static_cast<uint64_t>(
        item("accessors", static_cast<int64_t>(index->get<double>()))["count"].get<double>());
  }

  // Instances, triangles and vertices of the scene load_gltf reads, from the JSON counts alone
  // (each mesh's sums first, so a mesh used by many nodes costs one addition per node). Vertices
  // count the copies loading makes: a shared mesh once, a skinned or morphed one per instance
  // (posed and rest copies and each morph target).
  Status draw_counts() {
    const json* scenes = array("scenes");
    if (!scenes || scenes->empty()) return {};
    const size_t si = doc_.contains("scene") ? static_cast<size_t>(doc_["scene"].get<double>()) : 0;
    const json* roots = find((*scenes)[si], "nodes");
    if (!roots) return {};
    const size_t meshes = count("meshes");
    struct Sums {
      uint64_t prims = 0, triangles = 0, shared = 0, morphed = 0, skinned = 0;
    };
    std::vector<Sums> sums(meshes);
    for (size_t m = 0; m < meshes; ++m)
      for (const json& pr : item("meshes", static_cast<int64_t>(m))["primitives"]) {
        Sums& t = sums[m];
        ++t.prims;
        const json& attrs = pr["attributes"];
        const uint64_t vertices = accessor_count(find(attrs, "POSITION"));
        const json* indices = find(pr, "indices");
        t.triangles += (indices ? accessor_count(indices) : vertices) / 3;
        const json* targets = find(pr, "targets");
        const uint64_t copies = 2 + (targets ? targets->size() : 0);
        t.skinned += vertices * copies;
        if (targets)
          t.morphed += vertices * copies;
        else
          t.shared += vertices;
      }
    uint64_t instances = 0, triangles = 0, vertices = 0;
    std::vector<char> shared_counted(meshes, 0);
    std::vector<int64_t> stack;
    for (const json& r : *roots) stack.push_back(static_cast<int64_t>(r.get<double>()));
    while (!stack.empty()) {
      const json& nd = item("nodes", stack.back());
      stack.pop_back();
      if (const json* c = find(nd, "children"))
        for (const json& k : *c) stack.push_back(static_cast<int64_t>(k.get<double>()));
      if (!nd.contains("mesh")) continue;
      const size_t m = static_cast<size_t>(nd["mesh"].get<double>());
      instances += sums[m].prims;
      triangles += sums[m].triangles;
      if (nd.contains("skin")) {
        vertices += sums[m].skinned;
      } else {
        vertices += sums[m].morphed;
        if (!shared_counted[m]) vertices += sums[m].shared;
        shared_counted[m] = 1;
      }
    }
    const std::string sp = at("/scenes", si);
    if (instances > kMaxSceneInstances)
      return fail(sp, std::to_string(instances) +
                          " mesh instances (node and primitive pairs), more than the limit of " +
                          std::to_string(kMaxSceneInstances));
    if (triangles > kMaxSceneTriangles)
      return fail(sp, std::to_string(triangles) +
                          " triangles to draw (instances counted), more than the limit of " +
                          std::to_string(kMaxSceneTriangles));
    if (vertices > kMaxSceneVertices)
      return fail(sp, std::to_string(vertices) +
                          " vertices to hold (a skinned or morphed instance has its own copies), "
                          "more than the limit of " +
                          std::to_string(kMaxSceneVertices));
    return {};
  }

  const json& doc_;
  const std::string& path_;
};

}  // namespace

Status validate_gltf_document(const json& doc, const std::string& path) {
  return Validator(doc, path).run();
}

Status validate_gltf_text(std::string_view text, const std::string& path) {
  RELIEF_RETURN_IF_ERROR(check_json_nesting(text, path));
  const json doc = json::parse(text.begin(), text.end(), nullptr, false);
  if (doc.is_discarded()) return {};
  return validate_gltf_document(doc, path);
}

}  // namespace relief
