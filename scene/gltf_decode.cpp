// Compressed and quantized glTF: see gltf_decode.h.
#include "scene/gltf_decode.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <utility>

#include <nlohmann/json.hpp>

#include "rasterizer/safe_file.h"
#include "scene/gltf_validate.h"
#include "scene/scene.h"

namespace relief {

const char* gltf_component_type_name(int c) {
  switch (c) {
    case 5120:
      return "BYTE";
    case 5121:
      return "UNSIGNED_BYTE";
    case 5122:
      return "SHORT";
    case 5123:
      return "UNSIGNED_SHORT";
    case 5125:
      return "UNSIGNED_INT";
    case 5126:
      return "FLOAT";
    default:
      return nullptr;
  }
}
namespace {

using json = nlohmann::json;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125,
              kFloat = 5126;

const char* ctype_name(int c) {
  const char* n = gltf_component_type_name(c);
  return n ? n : "unknown";
}

// The extension object `name` in a tinygltf extensions_json_string; null when absent, a
// non-object is returned as is (the caller refuses it).
json extension_object(const std::string& extensions_json, const char* name) {
  if (extensions_json.empty()) return json();
  const json all = json::parse(extensions_json, nullptr, false);
  if (all.is_discarded() || !all.is_object()) return json();
  auto it = all.find(name);
  return it == all.end() ? json() : *it;
}

class Decoder {
 public:
  Decoder(tinygltf::Model& m, const std::string& shown) : m_(m), shown_(shown) {}

  Status run() {
    const size_t views = m_.bufferViews.size();
    for (size_t i = 0; i < views; ++i) RELIEF_RETURN_IF_ERROR(meshopt_view(static_cast<int>(i)));
    for (size_t mi = 0; mi < m_.meshes.size(); ++mi)
      for (size_t pi = 0; pi < m_.meshes[mi].primitives.size(); ++pi)
        RELIEF_RETURN_IF_ERROR(draco_primitive(static_cast<int>(mi), static_cast<int>(pi)));
    return {};
  }

 private:
  Status fail(const std::string& pointer, const std::string& what) const {
    return Status::error(shown_ + ": " + one_line_text(pointer, 120) + ": " +
                         one_line_text(what, 170));
  }

  // An integer member of `o` in lo..hi: `out` keeps its value when the member is absent and not
  // `required`.
  Status integer(const json& o, const std::string& p, const char* key, bool required, double lo,
                 double hi, uint64_t& out) const {
    auto it = o.find(key);
    if (it == o.end()) return required ? fail(p, std::string("missing '") + key + "'") : Status{};
    if (!it->is_number() || std::floor(it->get<double>()) != it->get<double>() ||
        it->get<double>() < lo || it->get<double>() > hi)
      return fail(p + "/" + key, "expected an integer in " + std::to_string(uint64_t(lo)) + ".." +
                                     std::to_string(uint64_t(hi)) + ", got " +
                                     one_line_text(it->dump(), 40));
    out = static_cast<uint64_t>(it->get<double>());
    return {};
  }

  // Room for `bytes` more decoded bytes (all decoded data together at most a buffer file's limit).
  Status reserve(const std::string& p, uint64_t bytes) {
    if (bytes > kMaxInputFileBytes - decoded_bytes_)
      return fail(p, "decodes to " + std::to_string(bytes) + " bytes, more than the limit of " +
                         std::to_string(kMaxInputFileBytes) + " decoded bytes in a file");
    decoded_bytes_ += bytes;
    return {};
  }

  // ---- EXT_meshopt_compression ----
  Status meshopt_view(int index) {
    tinygltf::BufferView& bv = m_.bufferViews[index];
    const json ext = extension_object(bv.extensions_json_string, kMeshoptCompression);
    if (ext.is_null()) return {};
    const std::string p =
        "/bufferViews/" + std::to_string(index) + "/extensions/" + kMeshoptCompression;
    if (!ext.is_object()) return fail(p, "expected an object");
    uint64_t buffer = 0, offset = 0, length = 0, stride = 0, count = 0;
    const double max_index = static_cast<double>(m_.buffers.size()) - 1;
    if (m_.buffers.empty()) return fail(p + "/buffer", "the file has no buffers");
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "buffer", true, 0, max_index, buffer));
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "byteOffset", false, 0, 9007199254740992.0, offset));
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "byteLength", true, 1, 9007199254740992.0, length));
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "byteStride", true, 1, 256, stride));
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "count", true, 1, 9007199254740992.0, count));
    std::string mode = "ATTRIBUTES", filter = "NONE";
    for (auto [key, out] :
         {std::pair<const char*, std::string*>{"mode", &mode}, {"filter", &filter}})
      if (auto it = ext.find(key); it != ext.end()) {
        if (!it->is_string())
          return fail(p + "/" + key, "expected a string, got " + one_line_text(it->dump(), 40));
        *out = it->get<std::string>();
      }
    const bool attributes = mode == "ATTRIBUTES";
    if (!attributes && mode != "TRIANGLES" && mode != "INDICES")
      return fail(p + "/mode",
                  "unknown mode '" + mode + "' (expected ATTRIBUTES, TRIANGLES or INDICES)");
    if (filter != "NONE" && filter != "OCTAHEDRAL" && filter != "QUATERNION" &&
        filter != "EXPONENTIAL")
      return fail(p + "/filter", "unknown filter '" + filter +
                                     "' (expected NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL)");
    if (attributes && stride % 4)
      return fail(p + "/byteStride",
                  "mode ATTRIBUTES needs a multiple of 4, got " + std::to_string(stride));
    if (!attributes && stride != 2 && stride != 4)
      return fail(p + "/byteStride",
                  "mode " + mode + " needs 2 or 4 (index size), got " + std::to_string(stride));
    if (!attributes && filter != "NONE")
      return fail(p + "/filter", "a filter applies only to mode ATTRIBUTES");
    if ((filter == "OCTAHEDRAL" && stride != 4 && stride != 8) ||
        (filter == "QUATERNION" && stride != 8))
      return fail(p + "/byteStride", "filter " + filter + " needs " +
                                         (filter == "QUATERNION" ? "8" : "4 or 8") + ", got " +
                                         std::to_string(stride));
    if (mode == "TRIANGLES" && count % 3)
      return fail(p + "/count", "mode TRIANGLES needs whole triangles, got " +
                                    std::to_string(count) + " indices");
    // The decoded size, checked against the view and the limits before anything is allocated.
    const uint64_t limit = attributes ? kMaxSceneVertices : 3 * kMaxSceneTriangles;
    if (count > limit)
      return fail(p + "/count", std::to_string(count) + (attributes ? " vertices" : " indices") +
                                    ", more than the limit of " + std::to_string(limit));
    const uint64_t size = count * stride;
    if (size != bv.byteLength)
      return fail(p, std::to_string(count) + " elements of " + std::to_string(stride) +
                         " bytes decode to " + std::to_string(size) +
                         " bytes; the buffer view's byteLength is " +
                         std::to_string(bv.byteLength));
    const std::vector<unsigned char>& src = m_.buffers[buffer].data;
    if (offset > src.size() || length > src.size() - offset)
      return fail(p, "bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
                         " exceed buffer " + std::to_string(buffer) + " (" +
                         std::to_string(src.size()) + " bytes" +
                         (src.size() <= 1 ? ", a fallback buffer has none" : "") + ")");
    RELIEF_RETURN_IF_ERROR(reserve(p, size));
    std::vector<unsigned char> out(size);
    const unsigned char* in = src.data() + offset;
    int rc = 0;
    if (attributes)
      rc = meshopt_decodeVertexBuffer(out.data(), count, stride, in, length);
    else if (mode == "TRIANGLES")
      rc = meshopt_decodeIndexBuffer(out.data(), count, stride, in, length);
    else
      rc = meshopt_decodeIndexSequence(out.data(), count, stride, in, length);
    if (rc != 0)
      return fail(p, "the " + mode + " stream does not decode (meshoptimizer error " +
                         std::to_string(rc) + "; truncated or corrupt)");
    if (filter == "OCTAHEDRAL") meshopt_decodeFilterOct(out.data(), count, stride);
    if (filter == "QUATERNION") meshopt_decodeFilterQuat(out.data(), count, stride);
    if (filter == "EXPONENTIAL") meshopt_decodeFilterExp(out.data(), count, stride);
    tinygltf::Buffer decoded;
    decoded.data = std::move(out);
    m_.buffers.push_back(std::move(decoded));
    bv.buffer = static_cast<int>(m_.buffers.size()) - 1;
    bv.byteOffset = 0;
    return {};
  }

  // ---- KHR_draco_mesh_compression ----
  template <typename T>
  static bool convert(const draco::PointAttribute& a, const draco::Mesh& mesh, int comps,
                      unsigned char* out) {
    for (draco::PointIndex i(0); i < mesh.num_points(); ++i) {
      T v[4] = {};
      if (!a.ConvertValue<T>(a.mapped_index(i), static_cast<int8_t>(comps), v)) return false;
      std::memcpy(out + static_cast<size_t>(i.value()) * comps * sizeof(T), v, comps * sizeof(T));
    }
    return true;
  }

  // Appends `bytes` as a new buffer and buffer view; its index.
  int add_view(std::vector<unsigned char> bytes) {
    tinygltf::Buffer b;
    b.data = std::move(bytes);
    tinygltf::BufferView v;
    v.buffer = static_cast<int>(m_.buffers.size());
    v.byteOffset = 0;
    v.byteLength = b.data.size();
    m_.buffers.push_back(std::move(b));
    m_.bufferViews.push_back(v);
    return static_cast<int>(m_.bufferViews.size()) - 1;
  }

  Status draco_primitive(int mesh_index, int prim_index) {
    tinygltf::Primitive& prim = m_.meshes[mesh_index].primitives[prim_index];
    const json ext = extension_object(prim.extensions_json_string, kDracoCompression);
    if (ext.is_null()) return {};
    const std::string pp =
        "/meshes/" + std::to_string(mesh_index) + "/primitives/" + std::to_string(prim_index);
    const std::string p = pp + "/extensions/" + kDracoCompression;
    if (!ext.is_object()) return fail(p, "expected an object");
    if (m_.bufferViews.empty()) return fail(p + "/bufferView", "the file has no buffer views");
    uint64_t view = 0;
    RELIEF_RETURN_IF_ERROR(integer(ext, p, "bufferView", true, 0,
                                   static_cast<double>(m_.bufferViews.size()) - 1, view));
    auto attrs = ext.find("attributes");
    if (attrs == ext.end() || !attrs->is_object() || attrs->empty())
      return fail(p + "/attributes", "expected an object of attribute ids");
    if (prim.mode >= 0 && prim.mode != TINYGLTF_MODE_TRIANGLES)
      return fail(pp + "/mode", "a Draco primitive must be TRIANGLES");
    if (prim.indices < 0) return fail(pp, "a Draco primitive needs 'indices'");
    const tinygltf::BufferView& bv = m_.bufferViews[view];
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()))
      return fail(p + "/bufferView", "buffer view " + std::to_string(view) + " has no buffer");
    const std::vector<unsigned char>& src = m_.buffers[bv.buffer].data;
    if (bv.byteOffset > src.size() || bv.byteLength > src.size() - bv.byteOffset)
      return fail(p + "/bufferView", "buffer view " + std::to_string(view) +
                                         " lies outside its buffer (" + std::to_string(src.size()) +
                                         " bytes)");
    // The accessors' counts were checked against the limits (validate_gltf_text); the stream
    // must agree with them before anything of its size is copied.
    const tinygltf::Accessor& ia = m_.accessors[prim.indices];
    draco::DecoderBuffer in;
    in.Init(reinterpret_cast<const char*>(src.data() + bv.byteOffset), bv.byteLength);
    auto type = draco::Decoder::GetEncodedGeometryType(&in);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH)
      return fail(p + "/bufferView", "not a Draco triangle mesh stream (truncated or corrupt)");
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&in);
    if (!decoded.ok() || !decoded.value())
      return fail(
          p + "/bufferView",
          "the Draco stream does not decode (" +
              (decoded.ok() ? std::string("no mesh") : decoded.status().error_msg_string()) + ")");
    const draco::Mesh& mesh = *decoded.value();
    const uint64_t faces = mesh.num_faces();
    if (3 * faces != ia.count)
      return fail(pp + "/indices", "accessor " + std::to_string(prim.indices) + " has " +
                                       std::to_string(ia.count) + " indices, the Draco stream " +
                                       std::to_string(3 * faces));
    RELIEF_RETURN_IF_ERROR(draco_attributes(prim, *attrs, p, pp, view, mesh));
    return draco_indices(prim, pp, view, mesh);
  }

  // The stream's attributes that `attrs` (the extension's attribute ids) names, each into its
  // accessor: checked against it, converted to its component type, in a new buffer view.
  Status draco_attributes(const tinygltf::Primitive& prim, const json& attrs, const std::string& p,
                          const std::string& pp, uint64_t view, const draco::Mesh& mesh) {
    const uint64_t points = mesh.num_points();
    for (auto it = attrs.begin(); it != attrs.end(); ++it) {
      const std::string ap = p + "/attributes/" + pointer_token(it.key());
      if (!it->is_number_integer() || it->get<int64_t>() < 0)
        return fail(ap, "expected an attribute id, got " + one_line_text(it->dump(), 40));
      auto acc = prim.attributes.find(it.key());
      if (acc == prim.attributes.end())
        return fail(ap, "the primitive has no attribute " + it.key());
      if (acc->second < 0 || acc->second >= static_cast<int>(m_.accessors.size()))
        return fail(pp + "/attributes/" + pointer_token(it.key()), "accessor does not exist");
      const draco::PointAttribute* a =
          mesh.GetAttributeByUniqueId(static_cast<uint32_t>(it->get<int64_t>()));
      if (!a) return fail(ap, "the Draco stream has no attribute " + it->dump());
      tinygltf::Accessor& acc_out = m_.accessors[acc->second];
      const int comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc_out.type));
      const int csize =
          tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc_out.componentType));
      const std::string accp = "/accessors/" + std::to_string(acc->second);
      if (comps <= 0 || comps > 4 || csize <= 0)
        return fail(accp, "a Draco attribute needs a SCALAR or VEC2..VEC4 accessor");
      if (acc_out.count != points)
        return fail(accp + "/count", std::to_string(acc_out.count) +
                                         " elements, the Draco stream has " +
                                         std::to_string(points) + " points");
      if (comps != a->num_components())
        return fail(accp + "/type", std::to_string(comps) +
                                        " components, the Draco attribute has " +
                                        std::to_string(a->num_components()));
      const auto key = std::make_pair(static_cast<int>(view), it->get<int64_t>());
      if (auto d = decoded_.find(acc->second); d != decoded_.end()) {
        if (d->second == key) continue;  // the same stream's attribute, decoded already
        return fail(accp, "accessor is shared by Draco primitives with different data");
      }
      const uint64_t bytes = points * comps * csize;
      RELIEF_RETURN_IF_ERROR(reserve(ap, bytes));
      std::vector<unsigned char> out(bytes);
      bool ok = false;
      switch (acc_out.componentType) {
        case kFloat:
          ok = convert<float>(*a, mesh, comps, out.data());
          break;
        case kByte:
          ok = convert<int8_t>(*a, mesh, comps, out.data());
          break;
        case kUByte:
          ok = convert<uint8_t>(*a, mesh, comps, out.data());
          break;
        case kShort:
          ok = convert<int16_t>(*a, mesh, comps, out.data());
          break;
        case kUShort:
          ok = convert<uint16_t>(*a, mesh, comps, out.data());
          break;
        case kUInt:
          ok = convert<uint32_t>(*a, mesh, comps, out.data());
          break;
      }
      if (!ok)
        return fail(ap, std::string("the Draco attribute does not convert to ") +
                            ctype_name(acc_out.componentType));
      acc_out.bufferView = add_view(std::move(out));
      acc_out.byteOffset = 0;
      acc_out.sparse.isSparse = false;
      decoded_[acc->second] = key;
    }
    return {};
  }

  // The stream's triangles as the primitive's UNSIGNED_INT indices, in a new buffer view.
  Status draco_indices(const tinygltf::Primitive& prim, const std::string& pp, uint64_t view,
                       const draco::Mesh& mesh) {
    const uint64_t faces = mesh.num_faces();
    if (auto d = decoded_.find(prim.indices); d != decoded_.end()) {
      if (d->second == std::make_pair(static_cast<int>(view), int64_t{-1})) return {};
      return fail(pp + "/indices", "accessor is shared by Draco primitives with different data");
    }
    RELIEF_RETURN_IF_ERROR(reserve(pp + "/indices", faces * 12));
    std::vector<unsigned char> idx(faces * 12);
    for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
      for (int c = 0; c < 3; ++c) {
        const uint32_t v = mesh.face(f)[c].value();
        std::memcpy(idx.data() + (static_cast<size_t>(f.value()) * 3 + c) * 4, &v, 4);
      }
    tinygltf::Accessor& ia_out = m_.accessors[prim.indices];
    ia_out.bufferView = add_view(std::move(idx));
    ia_out.byteOffset = 0;
    ia_out.componentType = kUInt;
    ia_out.sparse.isSparse = false;
    decoded_[prim.indices] = std::make_pair(static_cast<int>(view), int64_t{-1});
    return {};
  }

  tinygltf::Model& m_;
  const std::string& shown_;
  uint64_t decoded_bytes_ = 0;
  std::map<int, std::pair<int, int64_t>> decoded_;  // accessor -> (Draco view, attribute id)
};

}  // namespace

std::vector<int> attribute_component_types(std::string_view semantic, bool morph_target,
                                           bool quantized) {
  const bool texcoord = semantic.rfind("TEXCOORD_", 0) == 0;
  if (morph_target) {
    if (semantic != "POSITION" && semantic != "NORMAL" && semantic != "TANGENT" && !texcoord)
      return {};
    if (!quantized) return {kFloat};
    if (texcoord) return {kFloat, kByte, -kByte, -kUByte, kShort, -kShort, -kUShort};
    return {kFloat, -kByte, -kShort};
  }
  if (semantic == "POSITION")
    return quantized ? std::vector<int>{kFloat, kByte,   -kByte,  kUByte,  -kUByte,
                                        kShort, -kShort, kUShort, -kUShort}
                     : std::vector<int>{kFloat};
  if (semantic == "NORMAL" || semantic == "TANGENT")
    return quantized ? std::vector<int>{kFloat, -kByte, -kShort} : std::vector<int>{kFloat};
  if (texcoord)
    return quantized ? std::vector<int>{kFloat, kByte,   -kByte,  kUByte,  -kUByte,
                                        kShort, -kShort, kUShort, -kUShort}
                     : std::vector<int>{kFloat, -kUByte, -kUShort};
  return {};
}

std::string component_types_text(const std::vector<int>& ctypes) {
  std::string s;
  for (int c : ctypes)
    s +=
        (s.empty() ? "" : ", ") + std::string(c < 0 ? "normalized " : "") + ctype_name(std::abs(c));
  return s;
}

std::optional<std::string> tinygltf_json(const std::string& json_text) {
  if (json_text.find(kMeshoptCompression) == std::string::npos &&
      json_text.find(kDracoCompression) == std::string::npos &&
      json_text.find("data:image/webp") == std::string::npos)
    return std::nullopt;
  json doc = json::parse(json_text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return std::nullopt;
  bool changed = false;
  auto ext_of = [](const json& o, const char* name) -> const json* {
    auto e = o.find("extensions");
    if (e == o.end() || !e->is_object()) return nullptr;
    auto x = e->find(name);
    return x == e->end() || !x->is_object() ? nullptr : &*x;
  };
  if (auto b = doc.find("buffers"); b != doc.end() && b->is_array())
    for (json& buf : *b) {
      const json* ext = buf.is_object() ? ext_of(buf, kMeshoptCompression) : nullptr;
      if (!ext || buf.contains("uri")) continue;
      const auto f = ext->find("fallback");
      if (f == ext->end() || !f->is_boolean() || !f->get<bool>()) continue;
      buf["uri"] = "data:application/octet-stream;base64,AA==";  // tinygltf refuses no bytes
      buf["byteLength"] = 1;
      changed = true;
    }
  auto accessors = doc.find("accessors");
  if (auto ms = doc.find("meshes");
      ms != doc.end() && ms->is_array() && accessors != doc.end() && accessors->is_array())
    for (json& mesh : *ms) {
      auto prims = mesh.is_object() ? mesh.find("primitives") : mesh.end();
      if (!mesh.is_object() || prims == mesh.end() || !prims->is_array()) continue;
      for (json& pr : *prims) {
        const json* ext = pr.is_object() ? ext_of(pr, kDracoCompression) : nullptr;
        if (!ext || !pr.contains("indices") || !pr["indices"].is_number_unsigned()) continue;
        const size_t ai = pr["indices"].get<size_t>();
        if (ai >= accessors->size() || !(*accessors)[ai].is_object()) continue;
        json& a = (*accessors)[ai];
        if (a.contains("bufferView") || !ext->contains("bufferView")) continue;
        a["bufferView"] = (*ext)["bufferView"];  // replaced by decode_compressed
        changed = true;
      }
    }
  if (auto im = doc.find("images"); im != doc.end() && im->is_array())
    for (json& img : *im) {
      if (!img.is_object() || !img.contains("uri") || !img["uri"].is_string()) continue;
      const std::string& uri = img["uri"].get_ref<const std::string&>();
      static const std::string webp = "data:image/webp;base64,";
      if (uri.rfind(webp, 0) != 0) continue;
      // tinygltf decodes only some data URI headers; the bytes are sniffed when decoded.
      img["uri"] = "data:application/octet-stream;base64," + uri.substr(webp.size());
      changed = true;
    }
  if (!changed) return std::nullopt;
  return doc.dump();
}

std::string glb_with_json(const std::string& glb, const std::string& json_text) {
  uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  std::string chunk = json_text;
  while (chunk.size() % 4) chunk += ' ';
  uint32_t declared = 0;  // the header's total length (trailing bytes past it stay unread)
  std::memcpy(&declared, glb.data() + 8, 4);
  const size_t end = std::min<size_t>(glb.size(), std::max<size_t>(declared, 20 + json_length));
  const std::string rest = glb.substr(20 + json_length, end - 20 - json_length);
  std::string out(20, '\0');
  const uint32_t magic = 0x46546C67u, version = 2, type = 0x4E4F534Au;
  const uint32_t total = static_cast<uint32_t>(20 + chunk.size() + rest.size());
  const uint32_t length = static_cast<uint32_t>(chunk.size());
  std::memcpy(out.data(), &magic, 4);
  std::memcpy(out.data() + 4, &version, 4);
  std::memcpy(out.data() + 8, &total, 4);
  std::memcpy(out.data() + 12, &length, 4);
  std::memcpy(out.data() + 16, &type, 4);
  return out + chunk + rest;
}

Status decode_compressed(tinygltf::Model& model, const std::string& shown) {
  return Decoder(model, shown).run();
}

int texture_source(const tinygltf::Model& model, int texture, std::string* pointer) {
  const tinygltf::Texture& t = model.textures[texture];
  const std::string tp = "/textures/" + std::to_string(texture);
  const json ext = extension_object(t.extensions_json_string, kTextureWebp);
  if (ext.is_object()) {
    auto s = ext.find("source");
    if (s != ext.end() && s->is_number_integer()) {
      if (pointer) *pointer = tp + "/extensions/" + kTextureWebp + "/source";
      const int64_t v = s->get<int64_t>();
      return v < 0 || v > std::numeric_limits<int>::max() ? std::numeric_limits<int>::max()
                                                          : static_cast<int>(v);
    }
  }
  if (pointer) *pointer = tp + "/source";
  return t.source;
}

}  // namespace relief
