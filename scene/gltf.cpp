// glTF 2.0 input with the RELIEF_relief_mapping material extension: load_gltf (see gltf.h and
// docs/scene-format.md). The file is read as a regular file, its GLB header and buffer URIs are
// checked, then tinygltf parses the container (JSON, GLB chunks, buffers, data URIs) through
// file-system callbacks that open nothing outside the scene folder rule; images decode through
// scene/image_io. The Reader (gltf_internal.h; its parts in gltf_read_*.cpp) checks every value,
// and an error names the file and the JSON pointer of the offending value. Output: gltf_write.cpp.
#include "scene/gltf.h"

#include <tiny_gltf.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "rasterizer/safe_file.h"
#include "scene/gltf_decode.h"
#include "scene/gltf_internal.h"
#include "scene/gltf_validate.h"

namespace relief {
namespace gltf_detail {

bool has_suffix(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
  return true;
}

Result<Scene> Reader::read() {
  scene_.name = fs::path(path_).stem().string();
  RELIEF_RETURN_IF_ERROR(check_required_extensions());
  RELIEF_RETURN_IF_ERROR(read_root_extension());
  for (size_t i = 0; i < m_.materials.size(); ++i) {
    Result<MaterialInfo> mat = read_material(static_cast<int>(i));
    if (!mat.ok()) return mat.status();
    materials_.push_back(std::move(*mat));
  }
  RELIEF_RETURN_IF_ERROR(read_nodes());
  for (const MaterialInfo& mi : materials_) scene_.materials.push_back(mi.material);
  if (default_material_ >= 0) {
    Material d;
    d.name = "default";
    d.technique = "flat";
    scene_.materials.push_back(d);
  }
  RELIEF_RETURN_IF_ERROR(place_cameras());
  RELIEF_RETURN_IF_ERROR(read_animation());
  return std::move(scene_);
}

Status Reader::check_required_extensions() const {
  for (size_t i = 0; i < m_.extensionsRequired.size(); ++i)
    if (!gltf_extension_supported(m_.extensionsRequired[i]))
      return fail("/extensionsRequired/" + std::to_string(i),
                  "required extension '" + m_.extensionsRequired[i] + "' is not supported");
  return {};
}

Status Reader::read_root_extension() {
  Result<json> ext = extension(m_.extensions_json_string, kReliefExtension, "");
  if (!ext.ok()) return ext.status();
  if (ext->is_null()) return {};
  const std::string p = std::string("/extensions/") + kReliefExtension;
  RELIEF_RETURN_IF_ERROR(check_keys(*ext, p, {"ambient", "background"}));
  glm::dvec3 ambient(scene_.ambient);
  glm::dvec4 background(scene_.background);
  RELIEF_RETURN_IF_ERROR(get_vec<3>(*ext, "ambient", p, ambient, 0.0, 1e6));
  RELIEF_RETURN_IF_ERROR(get_vec<4>(*ext, "background", p, background, 0.0, 1e6));
  scene_.ambient = glm::vec3(ambient);
  scene_.background = glm::vec4(background);
  return {};
}

}  // namespace gltf_detail

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using gltf_detail::has_suffix;

std::string one_line(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '\n' || c == '\r') {
      if (!out.empty() && out.back() != ' ') out += "; ";
    } else {
      out += c;
    }
  }
  while (!out.empty() && (out.back() == ' ' || out.back() == ';')) out.pop_back();
  return out;
}

// Keeps the encoded bytes; decoding happens in Reader::texture through OpenImageIO. `user` is
// the model being loaded: tinygltf hands over an image's bufferView bytes without checking that
// the view lies inside its buffer, so that is checked here before anything is read.
bool keep_image_bytes(tinygltf::Image* image, const int index, std::string* err, std::string*, int,
                      int, const unsigned char* bytes, int size, void* user) {
  const auto* model = static_cast<const tinygltf::Model*>(user);
  if (size < 0) {
    if (err) *err = "/images/" + std::to_string(index) + ": negative or huge byte length";
    return false;
  }
  if (model && image->bufferView >= 0) {
    const size_t v = static_cast<size_t>(image->bufferView);
    const bool view_ok = v < model->bufferViews.size();
    const tinygltf::BufferView* view = view_ok ? &model->bufferViews[v] : nullptr;
    const bool buffer_ok =
        view && view->buffer >= 0 && static_cast<size_t>(view->buffer) < model->buffers.size();
    const size_t have =
        buffer_ok ? model->buffers[static_cast<size_t>(view->buffer)].data.size() : 0;
    if (!buffer_ok || view->byteOffset > have || view->byteLength > have - view->byteOffset) {
      if (err)
        *err = "/bufferViews/" + std::to_string(image->bufferView) +
               ": image bytes lie outside their buffer";
      return false;
    }
  }
  // An external file's bytes are not kept: Reader::texture reads it again under the folder
  // rule, so that its errors name the image's JSON pointer.
  if (!image->uri.empty() && image->uri.rfind("data:", 0) != 0) return true;
  image->image.assign(bytes, bytes + size);
  return true;
}

// The whole file as bytes: a regular file only (never a FIFO or a device), at most
// kMaxInputFileBytes (rasterizer/safe_file.h).
Result<std::string> read_scene_file(const std::string& path) {
  return read_regular_file(path);
}

// tinygltf reads external buffers and images through these (FsCallbacks): every path it asks
// for is the scene's folder joined with a decoded URI, which must pass the folder rule and name
// a regular file; nothing else is opened (not its fallback to the working directory either).
struct SceneFs {
  SceneFolder folder;
  std::string prefix;  // what tinygltf puts before a URI: "<folder>/", or "" for no folder
  // Decoded URIs (as tinygltf decodes them) that only images use: tinygltf gets one dummy byte
  // for them, as Reader::texture reads and checks each image itself (no file is read twice).
  std::set<std::string> image_only;
  // The URI part of a path tinygltf built; false for one not under the folder (its "." retry).
  bool reference(const std::string& abs, std::string& ref) const {
    if (abs.compare(0, prefix.size(), prefix) != 0) return false;
    ref = abs.substr(prefix.size());
    return true;
  }
  Result<ResolvedUri> resolve(const std::string& abs) const {
    std::string ref;
    if (!reference(abs, ref)) return Status::error("not in the scene's folder");
    return resolve_scene_path(folder, ref);
  }
};

bool fs_exists(const std::string& abs, void* user) {
  const auto* sfs = static_cast<const SceneFs*>(user);
  std::string ref;
  if (sfs->reference(abs, ref) && sfs->image_only.count(ref)) return true;
  Result<ResolvedUri> r = sfs->resolve(abs);
  if (!r.ok()) return false;
  return open_regular_file(r->real).ok();
}

std::string fs_expand(const std::string& path, void*) {
  return path;
}

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& abs,
             void* user) {
  const auto* sfs = static_cast<const SceneFs*>(user);
  std::string ref;
  if (sfs->reference(abs, ref) && sfs->image_only.count(ref)) {
    out->assign(1, 0);
    return true;
  }
  Result<ResolvedUri> r = sfs->resolve(abs);
  if (!r.ok()) {
    if (err) *err = r.status().message();
    return false;
  }
  Result<std::string> bytes = read_regular_file(r->real);
  if (!bytes.ok()) {
    if (err) *err = "cannot read";
    return false;
  }
  out->assign(bytes->begin(), bytes->end());
  return true;
}

bool fs_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err = "writing is not allowed while loading";
  return false;
}

// tinygltf's data: URI headers for buffers (DecodeDataURI).
bool known_data_header(const std::string& h) {
  static const char* known[] = {"data:application/octet-stream;base64,",
                                "data:application/gltf-buffer;base64,",
                                "data:image/jpeg;base64,",
                                "data:image/png;base64,",
                                "data:image/bmp;base64,",
                                "data:image/gif;base64,",
                                "data:text/plain;base64,"};
  for (const char* k : known)
    if (h == k) return true;
  return false;
}

// The byte count a base64 payload decodes to; -1 when it is not base64.
long long base64_size(std::string_view b64) {
  size_t n = b64.size();
  size_t pad = 0;
  while (n > 0 && b64[n - 1] == '=' && pad < 2) --n, ++pad;
  for (size_t i = 0; i < n; ++i) {
    const auto c = static_cast<unsigned char>(b64[i]);
    if (!std::isalnum(c) && c != '+' && c != '/') return -1;
  }
  if ((n + pad) % 4 != 0 && pad != 0) return -1;
  return static_cast<long long>(n * 6 / 8);
}

// Every buffer's URI, checked before tinygltf reads any (so its messages, which echo whole URIs
// and the sizes of the files they reach, are never needed): a data: URI must decode to
// byteLength bytes; an external file must pass the folder rule, be a regular file and hold
// byteLength bytes (the file's size is printed only when it lies in the scene's folder).
// A URI decoded as tinygltf does (dlib::urldecode: '+' is a space).
std::string tinygltf_decoded(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      const int hi = hex(uri[i + 1]), lo = hex(uri[i + 2]);
      if (hi < 0 || lo < 0) return {};  // not worth matching: tinygltf reads it as usual
      out += static_cast<char>(hi * 16 + lo);
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// The decoded external URIs of images that no buffer shares (SceneFs::image_only).
std::set<std::string> image_only_uris(const json& doc) {
  std::set<std::string> images, buffers;
  for (const char* key : {"images", "buffers"}) {
    const auto it = doc.find(key);
    if (it == doc.end() || !it->is_array()) continue;
    for (const json& e : *it) {
      if (!e.is_object()) continue;
      const auto u = e.find("uri");
      if (u == e.end() || !u->is_string()) continue;
      const std::string& uri = u->get_ref<const std::string&>();
      if (uri.rfind("data:", 0) == 0) continue;
      (std::strcmp(key, "images") == 0 ? images : buffers).insert(tinygltf_decoded(uri));
    }
  }
  images.erase(std::string());
  for (const std::string& b : buffers) images.erase(b);
  return images;
}

Status check_buffers(const std::string& shown, const std::string& json_text,
                     const SceneFolder& folder, std::set<std::string>* image_only) {
  const json doc = json::parse(json_text, nullptr, false);
  if (doc.is_discarded() || !doc.is_object()) return Status();  // tinygltf says why
  *image_only = image_only_uris(doc);
  const auto it = doc.find("buffers");
  if (it == doc.end() || !it->is_array()) return Status();
  for (size_t i = 0; i < it->size(); ++i) {
    const json& b = (*it)[i];
    if (!b.is_object()) continue;
    const auto u = b.find("uri");
    if (u == b.end() || !u->is_string()) continue;
    const std::string& uri = u->get_ref<const std::string&>();
    const std::string bp = shown + ": /buffers/" + std::to_string(i) + "/uri: ";
    const auto l = b.find("byteLength");
    const bool has_length = l != b.end() && l->is_number_unsigned();
    const unsigned long long length = has_length ? l->get<unsigned long long>() : 0;
    if (uri.rfind("data:", 0) == 0) {
      const size_t comma = uri.find(',');
      if (comma == std::string::npos || !known_data_header(uri.substr(0, comma + 1)))
        return Status::error(bp +
                             "unsupported data URI (expected "
                             "data:application/octet-stream;base64,...)");
      const long long n = base64_size(std::string_view(uri).substr(comma + 1));
      if (n < 0) return Status::error(bp + "data URI is not valid base64");
      if (has_length && static_cast<unsigned long long>(n) != length)
        return Status::error(bp + "data URI holds " + std::to_string(n) + " bytes, byteLength is " +
                             std::to_string(length));
      continue;
    }
    Result<ResolvedUri> r = resolve_scene_uri(folder, uri);
    if (!r.ok()) return Status::error(bp + r.status().message());
    uint64_t size = 0;
    Result<SafeFd> fd = open_regular_file(r->real, &size);
    if (!fd.ok()) {
      std::string msg = fd.status().message();
      const std::string real = printable(r->real) + ": ";
      if (msg.rfind(real, 0) == 0) msg = printable(r->path) + ": " + msg.substr(real.size());
      return Status::error(bp + msg);
    }
    if (has_length && size != length) {
      if (r->inside)
        return Status::error(bp + printable(r->path) + ": file is " + std::to_string(size) +
                             " bytes, byteLength is " + std::to_string(length));
      return Status::error(bp + printable(r->path) + ": file size differs from byteLength " +
                           std::to_string(length));
    }
  }
  return Status();
}

// tinygltf's error text made one line under 300 characters: data: URIs cut short, control
// bytes escaped.
std::string tinygltf_message(const std::string& err) {
  std::string s = one_line(err);
  for (size_t at = s.find("data:"); at != std::string::npos; at = s.find("data:", at + 1)) {
    size_t end = at;
    while (end < s.size() && s[end] != ' ' && s[end] != '\'' && s[end] != '"') ++end;
    if (end - at > 40) s.replace(at + 40, end - at - 40, "...");
  }
  return printable(s, 200);
}

// The JSON chunk of a GLB whose 12-byte header has been checked; empty when there is none.
std::string glb_json_chunk(const std::string& bytes) {
  if (bytes.size() < 20) return {};
  uint32_t length = 0, type = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  std::memcpy(&type, bytes.data() + 16, 4);
  if (type != 0x4E4F534Au || length > bytes.size() - 20) return {};
  return bytes.substr(20, length);
}

}  // namespace

Result<Scene> load_gltf(const std::string& path, const GltfLoadOptions& options) {
  const std::string shown = printable(path);
  Result<std::string> bytes = read_scene_file(path);
  if (!bytes.ok()) return bytes.status();
  const bool glb = has_suffix(path, ".glb");
  std::string json_text;
  if (glb) {
    // The GLB header (magic, version, total length) first, for a clearer error than tinygltf's.
    uint32_t header[3] = {0, 0, 0};
    if (bytes->size() >= 12) std::memcpy(header, bytes->data(), 12);
    if (bytes->size() < 12 || header[0] != 0x46546C67u)
      return Status::error(shown + ": not a GLB file (no 'glTF' header)");
    if (header[1] != 2)
      return Status::error(shown + ": GLB version " + std::to_string(header[1]) + ", expected 2");
    if (bytes->size() < header[2])
      return Status::error(shown + ": truncated GLB: the header gives " +
                           std::to_string(header[2]) + " bytes, the file has " +
                           std::to_string(bytes->size()));
    json_text = glb_json_chunk(*bytes);
  } else {
    json_text = *bytes;
  }
  if (bytes->size() > std::numeric_limits<unsigned int>::max())
    return Status::error(shown + ": file is larger than 4 GiB");
  SceneFs scene_fs;
  scene_fs.folder.dir = fs::path(path).parent_path().string();
  scene_fs.folder.allow_outside = options.allow_outside_scene_dir;
  RELIEF_RETURN_IF_ERROR(check_buffers(shown, json_text, scene_fs.folder, &scene_fs.image_only));
  // The schema, hierarchy and draw limits on the JSON as written, before tinygltf (which recurses
  // on deep JSON and drops or defaults what it dislikes) reads it (scene/gltf_validate.h).
  RELIEF_RETURN_IF_ERROR(validate_gltf_text(json_text, shown));
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  const std::string base_dir = scene_fs.folder.dir;
  scene_fs.prefix = base_dir.empty() ? "" : (base_dir.back() == '/' ? base_dir : base_dir + "/");
  tinygltf::FsCallbacks callbacks{fs_exists, fs_expand, fs_read, fs_write, &scene_fs};
  loader.SetFsCallbacks(callbacks);
  loader.SetImageLoader(keep_image_bytes, &model);
  loader.SetStoreOriginalJSONForExtrasAndExtensions(true);
  std::string err, warn;
  // Compressed data tinygltf cannot read is hidden from it, then decoded (gltf_decode.h).
  std::string rewritten;
  if (std::optional<std::string> j = tinygltf_json(json_text))
    rewritten = glb ? glb_with_json(*bytes, *j) : std::move(*j);
  const std::string& handed = rewritten.empty() ? *bytes : rewritten;
  if (handed.size() > std::numeric_limits<unsigned int>::max())
    return Status::error(shown + ": file is larger than 4 GiB");
  const auto length = static_cast<unsigned int>(handed.size());
  bool ok = false;
  if (glb)
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn,
                                     reinterpret_cast<const unsigned char*>(handed.data()), length,
                                     base_dir);
  else
    ok = loader.LoadASCIIFromString(&model, &err, &warn, handed.data(), length, base_dir);
  if (!ok)
    return Status::error(shown + ": " + (err.empty() ? "cannot parse" : tinygltf_message(err)));
  RELIEF_RETURN_IF_ERROR(decode_compressed(model, shown));
  gltf_detail::Reader reader(path, model);
  reader.set_scene_folder(scene_fs.folder);
  Result<Scene> scene = reader.read();
  if (!scene.ok()) return scene;
  if (options.validate) RELIEF_RETURN_IF_ERROR(options.validate(*scene));
  // What relief ignores (scene/gltf_extensions.h): printed only for a scene that loads, so an
  // error stays the only line; --strict makes the first one the error.
  const json doc = json::parse(json_text, nullptr, false);
  std::vector<GltfIgnored> ignored = find_ignored_features(doc);
  for (const GltfIgnored& g : ignored)
    if (g.warn && (g.refused || options.strict))
      return Status::error(ignored_line(shown, g) + (g.refused ? "" : " (--strict)"));
  if (options.ignored) {
    *options.ignored = std::move(ignored);
  } else {
    for (const GltfIgnored& g : ignored)
      if (g.warn) std::fprintf(stderr, "relief: warning: %s\n", ignored_line(shown, g).c_str());
  }
  return scene;
}

}  // namespace relief
