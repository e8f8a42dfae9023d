// glTF 2.0 input with the RELIEF_relief_mapping material extension (see gltf.h and
// docs/scene-format.md; the output is gltf_write.cpp). tinygltf parses the container (JSON, GLB
// chunks, buffers, data URIs); images decode through scene/image_io; every value is checked here
// and an error names the file and the JSON pointer of the offending value.
#include "scene/gltf.h"

#include <tiny_gltf.h>
#include <unistd.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "bake/normal_map.h"
#include "plugins/registry.h"
#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "scene/animation.h"
#include "scene/gltf_decode.h"
#include "scene/gltf_internal.h"
#include "scene/gltf_validate.h"
#include "scene/image_io.h"
#include "scene/mesh_prep.h"

namespace relief {
namespace gltf_detail {

bool has_suffix(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - n + i])) != suffix[i]) return false;
  return true;
}

// The normal map load_gltf derives from a relief material's depth map when the file gives none:
// the material's depth_scale (else its technique's default) and wrapping when both axes repeat.
Texture derived_normal_map(const Material& mat, const Texture& depth) {
  float depth_scale = 0.05f;
  if (auto it = mat.params.find("depth_scale"); it != mat.params.end()) {
    depth_scale = it->second;
  } else if (const PluginDescriptor* p = PluginRegistry::global().find(mat.technique)) {
    const int i = param_index(*p, "depth_scale");
    if (i >= 0) depth_scale = p->params[i].default_value;
  }
  const bool wrap = mat.sampler.wrap_u == Wrap::kRepeat && mat.sampler.wrap_v == Wrap::kRepeat;
  return normal_map_from_depth(depth, depth_scale, wrap);
}

}  // namespace gltf_detail

namespace {

using namespace gltf_detail;  // the constants and helpers writing shares (gltf_internal.h)
using json = nlohmann::json;

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

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return "SCALAR";
    case TINYGLTF_TYPE_VEC2:
      return "VEC2";
    case TINYGLTF_TYPE_VEC3:
      return "VEC3";
    case TINYGLTF_TYPE_VEC4:
      return "VEC4";
    case TINYGLTF_TYPE_MAT2:
      return "MAT2";
    case TINYGLTF_TYPE_MAT3:
      return "MAT3";
    case TINYGLTF_TYPE_MAT4:
      return "MAT4";
    default:
      return "an unknown type";
  }
}
const char* component_name(int c) {
  const char* n = gltf_component_type_name(c);
  return n ? n : "an unknown component type";
}
// A texture transform (KHR_texture_transform): uv' = T(offset) R(rotation) S(scale) uv.
struct UvTransform {
  glm::dvec2 offset{0.0};
  glm::dvec2 scale{1.0};
  double rotation = 0.0;
  bool operator==(const UvTransform&) const = default;
  int tex_coord = 0;  // the TEXCOORD_n it reads (textureInfo's, or the extension's override)
  glm::vec2 apply(glm::vec2 uv) const {
    const double c = std::cos(rotation), s = std::sin(rotation);
    const double u = scale.x * uv.x, v = scale.y * uv.y;
    return glm::vec2(static_cast<float>(c * u + s * v + offset.x),
                     static_cast<float>(-s * u + c * v + offset.y));
  }
  // The linear part (columns) and offset of apply.
  glm::dmat2 linear() const {
    const double c = std::cos(rotation), s = std::sin(rotation);
    return glm::dmat2(glm::dvec2(c * scale.x, -s * scale.x), glm::dvec2(s * scale.y, c * scale.y));
  }
};

// The UvMap (plugins/plugin.h) from the uv varying (the main texture's transformed TEXCOORD_0)
// to the coordinates of a texture with transform t: t composed with the inverse of `main` on
// TEXCOORD_0, t itself on TEXCOORD_1.
UvMap relative_uv_map(const UvTransform& t, const UvTransform& main) {
  UvMap m;
  if (t.tex_coord == 0 && t.offset == main.offset && t.scale == main.scale &&
      t.rotation == main.rotation)
    return m;
  glm::dmat2 l = t.linear();
  glm::dvec2 o = t.offset;
  if (t.tex_coord == 0) {
    const glm::dmat2 inv = glm::inverse(main.linear());
    l = l * inv;
    o = t.offset - l * main.offset;
  }
  m.col0 = glm::vec2(l[0]);
  m.col1 = glm::vec2(l[1]);
  m.offset = glm::vec2(o);
  m.set = t.tex_coord;
  m.identity = m.set == 0 && m.col0 == glm::vec2(1, 0) && m.col1 == glm::vec2(0, 1) &&
               m.offset == glm::vec2(0.0f);
  return m;
}

// A texture reference (textureInfo) wherever it appears.
struct TexRef {
  std::string pointer;  // JSON pointer of the textureInfo object
  int index = -1;
  int tex_coord = 0;
  json transform;  // KHR_texture_transform object, or null
};

enum class TexUse { kColor, kLinear, kDepth, kHeight, kCone };

struct PrimitiveKey {
  int mesh, primitive;
  auto operator<=>(const PrimitiveKey&) const = default;
};

class Reader {
 public:
  // `model` has passed validate_gltf_text (schema, hierarchy, draw limits) in load_gltf.
  Reader(std::string path, tinygltf::Model& model) : path_(std::move(path)), m_(model) {}

  Result<Scene> read() {
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

 private:
  struct MaterialInfo {
    Material material;
    bool bake_uv = false;   // a rotated texture transform, applied to the primitives' uvs
    UvTransform uv;         // the main texture's (the uv varying's)
    std::string needs_uv1;  // pointer of a textureInfo reading TEXCOORD_1, empty if none
  };
  struct CameraNode {
    int camera, node, order;
    glm::dmat4 world;
  };

  // Pointer and text kept on one line and short (names and keys come from the file).
  Status fail(const std::string& pointer, const std::string& what) const {
    return Status::error(path_ + ": " + one_line_text(pointer, 100) + ": " +
                         one_line_text(what, 180));
  }

  // ---- JSON helpers for extension objects ----
  static Result<json> parse_json(const std::string& text) {
    if (text.empty()) return json::object();
    json j = json::parse(text, nullptr, false);
    if (!j.is_discarded() && j.is_null()) return json::object();  // tinygltf: no extensions
    if (j.is_discarded() || !j.is_object()) return Status::error("malformed extension JSON");
    return j;
  }
  // The object `name` inside an extensions JSON string, or null.
  Result<json> extension(const std::string& extensions_json, const char* name,
                         const std::string& pointer) const {
    Result<json> all = parse_json(extensions_json);
    if (!all.ok()) return fail(pointer + "/extensions", all.status().message());
    auto it = all->find(name);
    if (it == all->end()) return json();
    if (!it->is_object()) return fail(pointer + "/extensions/" + name, "expected an object");
    return *it;
  }
  Status check_keys(const json& obj, const std::string& pointer,
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
  Status get_number(const json& obj, const char* key, const std::string& pointer, double& out,
                    double lo = -std::numeric_limits<double>::infinity(),
                    double hi = std::numeric_limits<double>::infinity()) const {
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
  Status get_int(const json& obj, const char* key, const std::string& pointer, int& out, int lo,
                 int hi) const {
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
  Status get_bool(const json& obj, const char* key, const std::string& pointer, bool& out) const {
    auto it = obj.find(key);
    if (it == obj.end()) return {};
    if (!it->is_boolean())
      return fail(pointer + "/" + key, "expected true or false, got " + it->dump());
    out = it->get<bool>();
    return {};
  }
  template <int N>
  Status get_vec(const json& obj, const char* key, const std::string& pointer,
                 glm::vec<N, double>& out, double lo, double hi) const {
    auto it = obj.find(key);
    if (it == obj.end()) return {};
    const std::string p = pointer + "/" + key;
    if (!it->is_array() || it->size() != N)
      return fail(p, "expected an array of " + std::to_string(N) + " numbers");
    for (int i = 0; i < N; ++i) {
      const json& x = (*it)[i];
      if (!x.is_number() || !std::isfinite(x.get<double>()) || x.get<double>() < lo ||
          x.get<double>() > hi)
        return fail(p + "/" + std::to_string(i),
                    "expected a number in [" + fmt(lo) + ", " + fmt(hi) + "], got " + x.dump());
      out[i] = x.get<double>();
    }
    return {};
  }
  static std::string fmt(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

  // ---- top level ----
  Status check_required_extensions() const {
    for (size_t i = 0; i < m_.extensionsRequired.size(); ++i)
      if (!gltf_extension_supported(m_.extensionsRequired[i]))
        return fail("/extensionsRequired/" + std::to_string(i),
                    "required extension '" + m_.extensionsRequired[i] + "' is not supported");
    return {};
  }

  Status read_root_extension() {
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

  // ---- textures ----
  // A float texture's exact texels (`relief export`, docs/scene-format.md, "Float textures"):
  // the texture's RELIEF_relief_mapping {texels: buffer view, format, width, height}; null when
  // the texture has none (its image is then decoded as usual).
  Result<TexturePtr> exact_texels(const TexRef& r, TexUse use, bool mipmapped) {
    const std::string tp = "/textures/" + std::to_string(r.index);
    Result<json> ext = extension(m_.textures[r.index].extensions_json_string, kReliefExtension, tp);
    if (!ext.ok()) return ext.status();
    if (ext->is_null()) return TexturePtr();
    const auto key = std::make_tuple(-1 - r.index, static_cast<int>(use), mipmapped);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    const std::string ep = tp + "/extensions/" + kReliefExtension;
    RELIEF_RETURN_IF_ERROR(check_keys(*ext, ep, {"texels", "format", "width", "height"}));
    for (const char* k : {"texels", "format", "width", "height"})
      if (!ext->contains(k)) return fail(ep, std::string("missing '") + k + "'");
    int view = -1, w = 0, h = 0;
    RELIEF_RETURN_IF_ERROR(get_int(*ext, "texels", ep, view, 0, 1 << 30));
    RELIEF_RETURN_IF_ERROR(get_int(*ext, "width", ep, w, 1, kMaxImageSide));
    RELIEF_RETURN_IF_ERROR(get_int(*ext, "height", ep, h, 1, kMaxImageSide));
    if (static_cast<long long>(w) * h > kMaxTextureTexels)
      return fail(ep, std::to_string(w) + "x" + std::to_string(h) + " is more than " +
                          std::to_string(kMaxTextureTexels) + " texels");
    const json& f = (*ext)["format"];
    TexFormat format = TexFormat::kR32F;
    if (f == "R32F")
      format = TexFormat::kR32F;
    else if (f == "R16F")
      format = TexFormat::kR16F;
    else if (f == "RGBA16F")
      format = TexFormat::kRGBA16F;
    else
      return fail(ep + "/format", "expected R32F, R16F or RGBA16F, got " + f.dump());
    if (use == TexUse::kHeight)
      return fail(ep, "exact texels hold depth: depth_is_height does not apply to them");
    if (view >= static_cast<int>(m_.bufferViews.size()))
      return fail(ep + "/texels", "buffer view " + std::to_string(view) + " does not exist");
    const tinygltf::BufferView& bv = m_.bufferViews[view];
    const size_t bytes = static_cast<size_t>(w) * h * format_bytes_per_texel(format);
    if (bv.byteLength != bytes)
      return fail(ep + "/texels", "buffer view " + std::to_string(view) + " has " +
                                      std::to_string(bv.byteLength) + " bytes, " +
                                      std::to_string(w) + "x" + std::to_string(h) + " " +
                                      format_name(format) + " needs " + std::to_string(bytes));
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()) ||
        bv.byteOffset + bv.byteLength > m_.buffers[bv.buffer].data.size())
      return fail(ep + "/texels",
                  "buffer view " + std::to_string(view) + " lies outside its buffer");
    const uint8_t* src = m_.buffers[bv.buffer].data.data() + bv.byteOffset;
    // every value finite: a float's exponent below all ones, a half's (bits 10-14) likewise
    const size_t value_bytes = format == TexFormat::kR32F ? 4 : 2;
    for (size_t i = 0; i < bytes; i += value_bytes) {
      bool finite;
      if (value_bytes == 4) {
        float v;
        std::memcpy(&v, src + i, 4);
        finite = std::isfinite(v);
      } else {
        uint16_t h16;
        std::memcpy(&h16, src + i, 2);
        finite = (h16 & 0x7C00u) != 0x7C00u;
      }
      if (!finite)
        return fail(ep + "/texels", "value " + std::to_string(i / value_bytes) + " is not finite");
    }
    Texture t(format, w, h, src, use == TexUse::kColor ? ColorSpace::kSRGB : ColorSpace::kLinear);
    if (mipmapped) t.generate_mips(use == TexUse::kCone ? MipReduce::kMin : MipReduce::kAverage);
    TexturePtr ptr = std::make_shared<Texture>(std::move(t));
    textures_[key] = ptr;
    return ptr;
  }

  Result<TexRef> tex_ref_from_json(const json& j, const std::string& pointer) const {
    if (!j.is_object()) return fail(pointer, "expected a textureInfo object");
    RELIEF_RETURN_IF_ERROR(check_keys(j, pointer, {"index", "texCoord"}));
    TexRef r;
    r.pointer = pointer;
    if (!j.contains("index")) return fail(pointer, "missing 'index'");
    RELIEF_RETURN_IF_ERROR(get_int(j, "index", pointer, r.index, 0, 1 << 30));
    RELIEF_RETURN_IF_ERROR(get_int(j, "texCoord", pointer, r.tex_coord, 0, 1 << 30));
    if (j.contains("extensions") && j["extensions"].is_object() &&
        j["extensions"].contains(kTextureTransform))
      r.transform = j["extensions"][kTextureTransform];
    return r;
  }
  Result<TexRef> tex_ref(int index, int tex_coord, const std::string& extensions_json,
                         const std::string& pointer) const {
    TexRef r;
    r.pointer = pointer;
    r.index = index;
    r.tex_coord = tex_coord;
    Result<json> t = extension(extensions_json, kTextureTransform, pointer);
    if (!t.ok()) return t.status();
    r.transform = *t;
    return r;
  }

  Result<UvTransform> uv_transform(const TexRef& r) const {
    UvTransform t;
    int tex_coord = r.tex_coord;
    if (!r.transform.is_null()) {
      const std::string p = r.pointer + "/extensions/" + kTextureTransform;
      if (!r.transform.is_object()) return fail(p, "expected an object");
      RELIEF_RETURN_IF_ERROR(
          check_keys(r.transform, p, {"offset", "rotation", "scale", "texCoord"}));
      RELIEF_RETURN_IF_ERROR(get_vec<2>(r.transform, "offset", p, t.offset, -1e9, 1e9));
      RELIEF_RETURN_IF_ERROR(get_vec<2>(r.transform, "scale", p, t.scale, -1e9, 1e9));
      RELIEF_RETURN_IF_ERROR(get_number(r.transform, "rotation", p, t.rotation, -1e9, 1e9));
      RELIEF_RETURN_IF_ERROR(get_int(r.transform, "texCoord", p, tex_coord, 0, 1 << 30));
      if (t.scale.x == 0.0 || t.scale.y == 0.0) return fail(p + "/scale", "scale must not be 0");
    }
    if (tex_coord > 1)
      return fail(r.pointer + (r.transform.is_object() && r.transform.contains("texCoord")
                                   ? std::string("/extensions/") + kTextureTransform + "/texCoord"
                                   : std::string("/texCoord")),
                  "TEXCOORD_" + std::to_string(tex_coord) +
                      " is not supported (only TEXCOORD_0 and TEXCOORD_1)");
    t.tex_coord = tex_coord;
    return t;
  }

  Result<SamplerState> sampler_of(const TexRef& r, bool& mipmapped) const {
    const tinygltf::Texture& tex = m_.textures[r.index];
    SamplerState s;
    mipmapped = true;
    if (tex.sampler < 0) return s;
    const std::string p = "/textures/" + std::to_string(r.index) + "/sampler";
    if (tex.sampler >= static_cast<int>(m_.samplers.size()))
      return fail(p, "sampler " + std::to_string(tex.sampler) + " does not exist");
    const tinygltf::Sampler& smp = m_.samplers[tex.sampler];
    const std::string sp = "/samplers/" + std::to_string(tex.sampler);
    // Our filters are GL's minification modes; magnification follows (nearest for kNearest).
    switch (smp.minFilter) {
      case -1:
        break;
      case kNearest:
        s.filter = Filter::kNearest;
        mipmapped = false;
        break;
      case kLinear:
        s.filter = Filter::kBilinear;
        mipmapped = false;
        break;
      case kNearestMipNearest:
        s.filter = Filter::kNearest;
        break;
      case kLinearMipNearest:
        s.filter = Filter::kBilinear;
        break;
      case kNearestMipLinear:
      case kLinearMipLinear:
        s.filter = Filter::kTrilinear;
        break;
      default:
        return fail(sp + "/minFilter", "unknown filter " + std::to_string(smp.minFilter));
    }
    if (smp.minFilter == -1 && smp.magFilter == kNearest) s.filter = Filter::kNearest;
    if (smp.magFilter != -1 && smp.magFilter != kNearest && smp.magFilter != kLinear)
      return fail(sp + "/magFilter", "unknown filter " + std::to_string(smp.magFilter));
    auto wrap = [&](int w, const char* key, Wrap& out) -> Status {
      switch (w) {
        case kRepeat:
          out = Wrap::kRepeat;
          return {};
        case kClampToEdge:
          out = Wrap::kClamp;
          return {};
        case kMirroredRepeat:
          out = Wrap::kMirror;
          return {};
        default:
          return fail(sp + "/" + key, "unknown wrap mode " + std::to_string(w));
      }
    };
    RELIEF_RETURN_IF_ERROR(wrap(smp.wrapS, "wrapS", s.wrap_u));
    RELIEF_RETURN_IF_ERROR(wrap(smp.wrapT, "wrapT", s.wrap_v));
    return s;
  }

  // Decodes image `index` for `use` (cached: one texture per image, use and mip choice).
  Result<TexturePtr> texture(const TexRef& r, TexUse use, bool mipmapped) {
    if (Result<TexturePtr> t = exact_texels(r, use, mipmapped); !t.ok() || *t) return t;
    // EXT_texture_webp's source when the texture has one, else the core source (its fallback).
    std::string sp;
    const int source = texture_source(m_, r.index, &sp);
    if (source < 0 || source >= static_cast<int>(m_.images.size()))
      return fail(sp, source < 0 ? "texture has no source image"
                                 : "image " + std::to_string(source) + " does not exist");
    const auto key = std::make_tuple(source, static_cast<int>(use), mipmapped);
    if (auto it = textures_.find(key); it != textures_.end()) return it->second;
    const tinygltf::Image& img = m_.images[source];
    const std::string ip = "/images/" + std::to_string(source);
    TextureLoadOptions opt;
    opt.color_space = use == TexUse::kColor ? ColorSpace::kSRGB : ColorSpace::kLinear;
    opt.first_channel_only = use == TexUse::kDepth || use == TexUse::kHeight;
    opt.height_to_depth = use == TexUse::kHeight;
    opt.unit_range = opt.first_channel_only;
    Result<Texture> t = Status::error("no image");
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) {
      // An external file: resolved in the scene's folder (safe_file.h), only a regular file is
      // read, then decoded from memory; errors name the path as the scene gives it.
      Result<ResolvedUri> file = resolve_scene_uri(folder_, img.uri);
      if (!file.ok()) return fail(ip + "/uri", file.status().message());
      Result<std::string> bytes = read_regular_file(file->real);
      if (!bytes.ok()) return fail(ip + "/uri", renamed(bytes.status().message(), *file));
      t = load_texture_from_memory(std::move(*bytes), printable(file->path), opt);
      if (!t.ok()) return fail(ip + "/uri", t.status().message());
    } else {
      t = decode_in_memory(img, opt);
      if (!t.ok())
        return fail(ip + (img.bufferView >= 0 ? "/bufferView" : "/uri"), t.status().message());
    }
    if (mipmapped) t->generate_mips(use == TexUse::kCone ? MipReduce::kMin : MipReduce::kAverage);
    TexturePtr ptr = std::make_shared<Texture>(std::move(*t));
    textures_[key] = ptr;
    return ptr;
  }

 public:
  // Where the scene's URIs resolve (load_gltf sets it from its options).
  void set_scene_folder(SceneFolder folder) { folder_ = std::move(folder); }

 private:
  SceneFolder folder_;

  // A message about `file.real` (symlinks resolved) made to name `file.path`, as the scene does.
  static std::string renamed(const std::string& message, const ResolvedUri& file) {
    const std::string real = printable(file.real) + ": ";
    if (message.rfind(real, 0) != 0) return message;
    return printable(file.path) + ": " + message.substr(real.size());
  }

  // Embedded images (GLB buffer views, data URIs), decoded from memory (nothing is written).
  static Result<Texture> decode_in_memory(const tinygltf::Image& img,
                                          const TextureLoadOptions& opt) {
    const std::vector<unsigned char>& bytes = img.image;
    if (bytes.empty()) return Status::error("image data is empty");
    const bool png = bytes.size() >= 8 && std::memcmp(bytes.data(), "\x89PNG\r\n\x1a\n", 8) == 0;
    const bool jpeg = bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
    const bool webp = bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 &&
                      std::memcmp(bytes.data() + 8, "WEBP", 4) == 0;  // EXT_texture_webp
    if (!png && !jpeg && !webp)
      return Status::error("embedded image is neither PNG, JPEG nor WebP");
    return load_texture_from_memory(std::string(bytes.begin(), bytes.end()), "embedded image", opt);
  }

  // ---- materials ----
  Result<MaterialInfo> read_material(int index) {
    const tinygltf::Material& gm = m_.materials[index];
    const std::string mp = "/materials/" + std::to_string(index);
    MaterialInfo info;
    Material& mat = info.material;
    mat.name = gm.name.empty() ? "material" + std::to_string(index) : gm.name;
    mat.double_sided = gm.doubleSided;
    // alphaMode (validated: OPAQUE, MASK or BLEND) and alphaCutoff (MASK only, >= 0)
    mat.alpha_mode = gm.alphaMode == "MASK"    ? AlphaMode::kMask
                     : gm.alphaMode == "BLEND" ? AlphaMode::kBlend
                                               : AlphaMode::kOpaque;
    mat.alpha_cutoff = static_cast<float>(gm.alphaCutoff);
    const auto& bcf = gm.pbrMetallicRoughness.baseColorFactor;
    if (bcf.size() == 4) {
      for (int i = 0; i < 4; ++i) {
        if (!std::isfinite(bcf[i]) || bcf[i] < 0.0 || bcf[i] > 1.0)
          return fail(mp + "/pbrMetallicRoughness/baseColorFactor/" + std::to_string(i),
                      "expected a number in [0, 1]");
        mat.base_color[i] = static_cast<float>(bcf[i]);
      }
    }
    // (slot, reference, use)
    struct Slot {
      std::string name;
      TexRef ref;
      TexUse use;
    };
    std::vector<Slot> slots;
    const auto& bct = gm.pbrMetallicRoughness.baseColorTexture;
    if (bct.index >= 0) {
      Result<TexRef> r = tex_ref(bct.index, bct.texCoord, bct.extensions_json_string,
                                 mp + "/pbrMetallicRoughness/baseColorTexture");
      if (!r.ok()) return r.status();
      slots.push_back({"base_color", *r, TexUse::kColor});
    }
    if (gm.normalTexture.index >= 0) {
      const std::string p = mp + "/normalTexture";
      if (!std::isfinite(gm.normalTexture.scale) || std::abs(gm.normalTexture.scale) > 1e6)
        return fail(p + "/scale", "expected a finite number, got " + fmt(gm.normalTexture.scale));
      mat.normal_scale = static_cast<float>(gm.normalTexture.scale);
      Result<TexRef> r = tex_ref(gm.normalTexture.index, gm.normalTexture.texCoord,
                                 gm.normalTexture.extensions_json_string, p);
      if (!r.ok()) return r.status();
      slots.push_back({"normal", *r, TexUse::kLinear});
    }
    // Emissive, occlusion and unlit (plugins/surface.h finish_surface).
    if (gm.emissiveFactor.size() == 3) {
      for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(gm.emissiveFactor[i]) || gm.emissiveFactor[i] < 0.0 ||
            gm.emissiveFactor[i] > 1.0)
          return fail(mp + "/emissiveFactor/" + std::to_string(i), "expected a number in [0, 1]");
        mat.emissive[i] = static_cast<float>(gm.emissiveFactor[i]);
      }
    }
    if (gm.emissiveTexture.index >= 0) {
      Result<TexRef> r =
          tex_ref(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                  gm.emissiveTexture.extensions_json_string, mp + "/emissiveTexture");
      if (!r.ok()) return r.status();
      slots.push_back({"emissive", *r, TexUse::kColor});
    }
    if (gm.occlusionTexture.index >= 0) {
      const std::string p = mp + "/occlusionTexture";
      const double st = gm.occlusionTexture.strength;
      if (!std::isfinite(st) || st < 0.0 || st > 1.0)
        return fail(p + "/strength", "expected a number in [0, 1], got " + fmt(st));
      mat.occlusion_strength = static_cast<float>(st);
      Result<TexRef> r = tex_ref(gm.occlusionTexture.index, gm.occlusionTexture.texCoord,
                                 gm.occlusionTexture.extensions_json_string, p);
      if (!r.ok()) return r.status();
      slots.push_back({"occlusion", *r, TexUse::kLinear});
    }
    {
      Result<json> es = extension(gm.extensions_json_string, kEmissiveStrength, mp);
      if (!es.ok()) return es.status();
      if (!es->is_null()) {
        const std::string p = mp + "/extensions/" + kEmissiveStrength;
        RELIEF_RETURN_IF_ERROR(check_keys(*es, p, {"emissiveStrength"}));
        double strength = 1.0;
        RELIEF_RETURN_IF_ERROR(get_number(*es, "emissiveStrength", p, strength, 0.0, 1e6));
        mat.emissive_strength = static_cast<float>(strength);
      }
      Result<json> unlit = extension(gm.extensions_json_string, kUnlit, mp);
      if (!unlit.ok()) return unlit.status();
      if (!unlit->is_null()) {
        RELIEF_RETURN_IF_ERROR(check_keys(*unlit, mp + "/extensions/" + kUnlit, {}));
        mat.unlit = true;
      }
    }

    Result<json> ext = extension(gm.extensions_json_string, kReliefExtension, mp);
    if (!ext.ok()) return ext.status();
    const std::string ep = mp + "/extensions/" + kReliefExtension;
    bool normal_from_depth = true;
    int max_aniso = 0;
    std::map<std::string, std::string> param_pointer;  // parameter -> JSON pointer
    if (ext->is_null()) {
      mat.technique = gm.normalTexture.index >= 0 ? "normal" : "flat";
    } else {
      const json& e = *ext;
      RELIEF_RETURN_IF_ERROR(check_keys(
          e, ep,
          {"technique",      "depth_texture",   "depth_is_height",    "normal_from_depth",
           "cone_texture",   "cone_kind",       "depth_scale",        "steps",
           "binary_steps",   "self_shadow",     "depth_write",        "silhouette",
           "casts_shadow",   "receives_shadow", "specular",           "shininess",
           "max_anisotropy", "params",          "depth_back_texture", "normal_back_texture"}));
      mat.technique = "relief";
      if (e.contains("technique")) {
        if (!e["technique"].is_string() || e["technique"].get<std::string>().empty())
          return fail(ep + "/technique", "expected a technique name, got " + e["technique"].dump());
        mat.technique = e["technique"].get<std::string>();
      }
      if (!PluginRegistry::global().find(mat.technique)) {
        std::string known;
        for (const PluginDescriptor* p : PluginRegistry::global().all())
          known += (known.empty() ? "" : ", ") + std::string(p->name);
        return fail(ep + "/technique",
                    "unknown technique '" + mat.technique + "' (known: " + known + ")");
      }
      bool depth_is_height = false;
      RELIEF_RETURN_IF_ERROR(get_bool(e, "depth_is_height", ep, depth_is_height));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "normal_from_depth", ep, normal_from_depth));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "self_shadow", ep, mat.self_shadow));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "depth_write", ep, mat.depth_write));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "silhouette", ep, mat.silhouette));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "casts_shadow", ep, mat.casts_shadow));
      RELIEF_RETURN_IF_ERROR(get_bool(e, "receives_shadow", ep, mat.receives_shadow));
      double specular = mat.specular, shininess = mat.shininess;
      RELIEF_RETURN_IF_ERROR(get_number(e, "specular", ep, specular, 0.0, 1e6));
      RELIEF_RETURN_IF_ERROR(get_number(e, "shininess", ep, shininess, 0.0, 1e6));
      mat.specular = static_cast<float>(specular);
      mat.shininess = static_cast<float>(shininess);
      RELIEF_RETURN_IF_ERROR(get_int(e, "max_anisotropy", ep, max_aniso, 1, 16));
      if (e.contains("depth_texture")) {
        Result<TexRef> r = tex_ref_from_json(e["depth_texture"], ep + "/depth_texture");
        if (!r.ok()) return r.status();
        slots.push_back({"depth", *r, depth_is_height ? TexUse::kHeight : TexUse::kDepth});
      }
      // relief_dual's back layer: where the object ends (its depth) and its normals.
      if (e.contains("depth_back_texture")) {
        Result<TexRef> r = tex_ref_from_json(e["depth_back_texture"], ep + "/depth_back_texture");
        if (!r.ok()) return r.status();
        slots.push_back({"depth_back", *r, depth_is_height ? TexUse::kHeight : TexUse::kDepth});
      }
      if (e.contains("normal_back_texture")) {
        Result<TexRef> r = tex_ref_from_json(e["normal_back_texture"], ep + "/normal_back_texture");
        if (!r.ok()) return r.status();
        slots.push_back({"normal_back", *r, TexUse::kLinear});
      }
      if (e.contains("cone_texture")) {
        Result<TexRef> r = tex_ref_from_json(e["cone_texture"], ep + "/cone_texture");
        if (!r.ok()) return r.status();
        // The slot is cone_<kind>: cone_kind, else the kind the technique reads.
        std::string kind;
        if (e.contains("cone_kind")) {
          const json& k = e["cone_kind"];
          if (!k.is_string() || (k != "conservative" && k != "quad" && k != "relaxed"))
            return fail(ep + "/cone_kind",
                        "expected conservative, quad or relaxed, got " + k.dump());
          kind = k.get<std::string>();
        } else if (const PluginDescriptor* p = PluginRegistry::global().find(mat.technique)) {
          for (int i = 0; i < p->num_textures && kind.empty(); ++i)
            if (std::string(p->textures[i].name).rfind("cone_", 0) == 0)
              kind = p->textures[i].name + 5;
        }
        if (kind.empty())
          return fail(ep + "/cone_texture",
                      "technique " + mat.technique + " reads no cone map: give cone_kind");
        slots.push_back({"cone_" + kind, *r, TexUse::kCone});
      }
      // Plugin parameters: the three common ones at the top level, any other in "params".
      int steps = 0, binary_steps = 0;
      double depth_scale = 0.0;
      if (e.contains("steps")) {
        RELIEF_RETURN_IF_ERROR(get_int(e, "steps", ep, steps, 1, 1 << 20));
        mat.params["steps"] = static_cast<float>(steps);
        param_pointer["steps"] = ep + "/steps";
      }
      if (e.contains("binary_steps")) {
        RELIEF_RETURN_IF_ERROR(get_int(e, "binary_steps", ep, binary_steps, 0, 1 << 20));
        mat.params["binary_steps"] = static_cast<float>(binary_steps);
        param_pointer["binary_steps"] = ep + "/binary_steps";
      }
      if (e.contains("depth_scale")) {
        RELIEF_RETURN_IF_ERROR(get_number(e, "depth_scale", ep, depth_scale, 0.0, 1e6));
        mat.params["depth_scale"] = static_cast<float>(depth_scale);
        param_pointer["depth_scale"] = ep + "/depth_scale";
      }
      if (e.contains("params")) {
        const json& ps = e["params"];
        const std::string pp = ep + "/params";
        if (!ps.is_object()) return fail(pp, "expected an object of parameter values");
        for (auto it = ps.begin(); it != ps.end(); ++it) {
          const std::string p = pp + "/" + pointer_token(it.key());
          if (param_pointer.count(it.key()))
            return fail(p, "given twice (also at " + param_pointer[it.key()] + ")");
          // Typed as the declaring technique's schema says, by the rules --param applies.
          ParamValue pv;
          if (it->is_boolean()) {
            pv.kind = ParamValue::Kind::kBool;
            pv.boolean = it->get<bool>();
          } else if (it->is_number()) {
            pv.number = it->get<double>();
          } else if (it->is_string()) {
            pv.kind = ParamValue::Kind::kText;
            pv.text = it->get<std::string>();
          } else {
            const char* got = it->is_array() ? "an array" : it->is_object() ? "an object" : "null";
            return fail(p,
                        std::string("expected a number, a boolean or a choice name, got ") + got);
          }
          const PluginDescriptor* by = declaring_plugin(mat.technique, it.key());
          if (!by) return fail(p, "no technique has a parameter '" + it.key() + "'");
          Result<float> v = resolve_param_value(*by, it.key(), pv);
          if (!v.ok()) return fail(p, v.status().message());
          mat.params[it.key()] = *v;
          param_pointer[it.key()] = p;
        }
      }
      RELIEF_RETURN_IF_ERROR(check_params(mat, param_pointer));
    }

    // Textures: one sampler per material; a texture transform per texture. The uv varying is
    // the main texture's transformed TEXCOORD_0 (the depth map's, else the base colour's, else
    // the first's); every other texture maps from it (relative_uv_map).
    std::vector<UvTransform> transforms;
    for (const Slot& s : slots) {
      if (s.ref.index < 0 || s.ref.index >= static_cast<int>(m_.textures.size()))
        return fail(s.ref.pointer + "/index",
                    "texture " + std::to_string(s.ref.index) + " does not exist");
      Result<UvTransform> t = uv_transform(s.ref);
      if (!t.ok()) return t.status();
      transforms.push_back(*t);
    }
    int main_slot = -1;
    for (const char* name : {"depth", "base_color"})
      for (size_t i = 0; i < slots.size() && main_slot < 0; ++i)
        if (slots[i].name == name && transforms[i].tex_coord == 0) main_slot = static_cast<int>(i);
    for (size_t i = 0; i < slots.size() && main_slot < 0; ++i)
      if (transforms[i].tex_coord == 0) main_slot = static_cast<int>(i);
    if (main_slot >= 0) info.uv = transforms[main_slot];
    const TexRef* first = nullptr;
    for (size_t i = 0; i < slots.size(); ++i) {
      const Slot& s = slots[i];
      const UvTransform* t = &transforms[i];
      // The relief searches trace in the uv varying's space: the depth and cone maps must be in it.
      if ((s.name == "depth" || s.use == TexUse::kCone) && (t->tex_coord != 0 || !(*t == info.uv)))
        return fail(s.ref.pointer, std::string("the depth and cone maps need TEXCOORD_0 and the ") +
                                       "same texture transform (relief traces in their uv space)");
      // Another texture on TEXCOORD_0 maps from the main one through its inverse: a singular
      // main transform (a zero scale) has none.
      const glm::dmat2 main_linear = info.uv.linear();
      if (t->tex_coord == 0 && !(*t == info.uv) &&
          !(std::fabs(glm::determinant(main_linear)) > 1e-12))
        return fail(slots[main_slot].ref.pointer,
                    "KHR_texture_transform scale is singular (zero), so another texture's own "
                    "transform cannot be mapped from it");
      const UvMap map = relative_uv_map(*t, info.uv);
      if (t->tex_coord == 1) info.needs_uv1 = s.ref.pointer;
      if (s.name == "emissive")
        mat.emissive_uv = map;
      else if (s.name == "occlusion")
        mat.occlusion_uv = map;
      else if (!map.identity)
        mat.uv_maps[s.name] = map;
      bool mipmapped = true;
      Result<SamplerState> smp = sampler_of(s.ref, mipmapped);
      if (!smp.ok()) return smp.status();
      if (!first) {
        first = &s.ref;
        mat.sampler = *smp;
      } else {
        const SamplerState& a = mat.sampler;
        if (a.filter != smp->filter || a.wrap_u != smp->wrap_u || a.wrap_v != smp->wrap_v)
          return fail(s.ref.pointer, std::string("sampler differs from that of ") + first->pointer +
                                         " (relief uses one sampler per material)");
      }
      Result<TexturePtr> tex = texture(s.ref, s.use, mipmapped);
      if (!tex.ok()) return tex.status();
      if (s.name == "emissive")
        mat.emissive_texture = *tex;
      else if (s.name == "occlusion")
        mat.occlusion_texture = *tex;
      else
        mat.textures[s.name] = *tex;
    }
    if (max_aniso > 1) {
      mat.sampler.filter = Filter::kAnisotropic;
      mat.sampler.max_aniso = max_aniso;
    }
    if (info.uv.rotation != 0.0) {
      info.bake_uv = true;  // applied to the uvs of every primitive that uses the material
    } else {
      mat.uv_scale = glm::vec2(info.uv.scale);
      mat.uv_offset = glm::vec2(info.uv.offset);
    }
    // The normal map a relief material needs, derived from its depth map when none is given.
    if (mat.textures.count("depth") && !mat.textures.count("normal") && normal_from_depth) {
      mat.textures["normal"] =
          std::make_shared<Texture>(derived_normal_map(mat, *mat.textures["depth"]));
    }
    // Texture slots the technique requires.
    const PluginDescriptor* plugin = PluginRegistry::global().find(mat.technique);
    for (int s = 0; plugin && s < plugin->num_textures; ++s) {
      const TextureSlotSpec& slot = plugin->textures[s];
      const std::string name = slot.name;
      // Slots a file can fill and nothing derives (cone maps are baked by the renderer).
      if (name != "base_color" && name != "normal" && name != "depth") continue;
      if (!slot.required || mat.textures.count(slot.name)) continue;
      const std::string where = name == "base_color" ? "pbrMetallicRoughness/baseColorTexture"
                                : name == "normal"   ? "normalTexture"
                                                     : name + "_texture";
      return fail(ext->is_null() ? mp : ep,
                  "technique " + mat.technique + " needs a '" + name + "' texture (" + where + ")");
    }
    return info;
  }

  // Each parameter is checked by the material's technique when it declares it, otherwise by a
  // technique that does (parameters of other techniques apply when --technique switches).
  static const PluginDescriptor* declaring_plugin(const std::string& technique,
                                                  const std::string& name) {
    const PluginRegistry& reg = PluginRegistry::global();
    if (const PluginDescriptor* own = reg.find(technique);
        own && param_index(*own, name.c_str()) >= 0)
      return own;
    for (const PluginDescriptor* p : reg.all())
      if (param_index(*p, name.c_str()) >= 0) return p;
    return nullptr;
  }
  Status check_params(const Material& mat,
                      const std::map<std::string, std::string>& pointers) const {
    for (const auto& [name, value] : mat.params) {
      const PluginDescriptor* by = declaring_plugin(mat.technique, name);
      const std::string& where = pointers.at(name);
      if (!by) return fail(where, "no technique has a parameter '" + name + "'");
      Result<std::vector<float>> r = resolve_params(*by, {{name, value}}, {});
      if (!r.ok()) return fail(where, r.status().message());
    }
    return {};
  }

  // ---- accessors ----
  struct View {
    const uint8_t* data = nullptr;
    size_t stride = 0;
    size_t count = 0;
    int comps = 0;
    int ctype = 0;
    bool normalized = false;
  };

  Result<View> view(int index, const std::string& where) const {
    if (index < 0 || index >= static_cast<int>(m_.accessors.size()))
      return fail(where, "accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = m_.accessors[index];
    const std::string ap = "/accessors/" + std::to_string(index);
    if (a.sparse.isSparse) return fail(ap + "/sparse", "sparse accessors are not supported");
    if (a.count == 0) return fail(ap + "/count", "accessor has no elements");
    View v;
    v.count = a.count;
    v.comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    v.ctype = a.componentType;
    v.normalized = a.normalized;
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    if (v.comps <= 0) return fail(ap + "/type", "unknown accessor type");
    if (csize <= 0) return fail(ap + "/componentType", "unknown component type");
    const size_t elem = static_cast<size_t>(v.comps) * csize;
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m_.bufferViews.size()))
      return fail(ap + "/bufferView",
                  "buffer view " + std::to_string(a.bufferView) + " does not exist");
    const tinygltf::BufferView& bv = m_.bufferViews[a.bufferView];
    const std::string bp = "/bufferViews/" + std::to_string(a.bufferView);
    if (bv.buffer < 0 || bv.buffer >= static_cast<int>(m_.buffers.size()))
      return fail(bp + "/buffer", "buffer " + std::to_string(bv.buffer) + " does not exist");
    const tinygltf::Buffer& buf = m_.buffers[bv.buffer];
    if (bv.byteOffset > buf.data.size() || bv.byteLength > buf.data.size() - bv.byteOffset)
      return fail(bp, "bytes " + std::to_string(bv.byteOffset) + ".." +
                          std::to_string(bv.byteOffset + bv.byteLength) + " exceed buffer " +
                          std::to_string(bv.buffer) + " (" + std::to_string(buf.data.size()) +
                          " bytes)");
    v.stride = bv.byteStride ? bv.byteStride : elem;
    if (v.stride < elem)
      return fail(bp + "/byteStride", "stride " + std::to_string(v.stride) +
                                          " is smaller than an element (" + std::to_string(elem) +
                                          " bytes)");
    const size_t need = a.byteOffset + v.stride * (a.count - 1) + elem;
    if (a.byteOffset > bv.byteLength || need > bv.byteLength)
      return fail(ap, std::to_string(a.count) + " elements of " + std::to_string(elem) +
                          " bytes at offset " + std::to_string(a.byteOffset) + " need " +
                          std::to_string(need) + " bytes; buffer view " +
                          std::to_string(a.bufferView) + " has " + std::to_string(bv.byteLength));
    v.data = buf.data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  static float component(const uint8_t* p, int ctype, bool normalized) {
    switch (ctype) {
      case kFloat: {
        float f;
        std::memcpy(&f, p, 4);
        return f;
      }
      case kUByte:
        return normalized ? p[0] / 255.0f : p[0];
      case kUShort: {
        uint16_t u;
        std::memcpy(&u, p, 2);
        return normalized ? u / 65535.0f : u;
      }
      case kByte: {
        const int8_t b = static_cast<int8_t>(p[0]);
        return normalized ? std::max(b / 127.0f, -1.0f) : b;
      }
      case kShort: {
        int16_t u;
        std::memcpy(&u, p, 2);
        return normalized ? std::max(u / 32767.0f, -1.0f) : u;
      }
      default:
        return 0.0f;
    }
  }

  // Reads a float attribute: VEC<comps> of FLOAT (or normalised unsigned bytes / shorts where
  // allowed), every value finite. POSITION, NORMAL, TANGENT and TEXCOORD_n (the last token of
  // `where`) take the component types glTF lists for them, KHR_mesh_quantization's too when the
  // file uses it (gltf_decode.h); quantized normals and tangents are renormalized.
  template <int N>
  Status read_attr(int index, const std::string& where, bool allow_normalized,
                   std::vector<glm::vec<N, float>>& out) const {
    Result<View> v = view(index, where);
    if (!v.ok()) return v.status();
    const std::string semantic = where.substr(where.rfind('/') + 1);
    const bool target = where.find("/targets/") != std::string::npos;
    const std::vector<int> allowed =
        attribute_component_types(semantic, target, uses_extension(kMeshQuantization));
    const int signed_ctype = v->normalized ? -v->ctype : v->ctype;
    const bool ok_ctype =
        allowed.empty() ? !(v->ctype != kFloat && !(allow_normalized && v->normalized &&
                                                    (v->ctype == kUByte || v->ctype == kUShort)))
                        : std::find(allowed.begin(), allowed.end(), signed_ctype) != allowed.end();
    if (!ok_ctype || v->comps != N || m_.accessors[index].type != N)
      return fail(where,
                  "accessor " + std::to_string(index) + " is " +
                      type_name(m_.accessors[index].type) + " of " +
                      (v->normalized ? "normalized " : "") + component_name(v->ctype) +
                      ", expected VEC" + std::to_string(N) + " of " +
                      (allowed.empty()
                           ? std::string("FLOAT") +
                                 (allow_normalized ? " (or normalized UNSIGNED_BYTE/SHORT)" : "")
                           : component_types_text(allowed)) +
                      (!allowed.empty() && !uses_extension(kMeshQuantization)
                           ? " (other types need KHR_mesh_quantization)"
                           : ""));
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v->ctype));
    out.resize(v->count);
    for (size_t i = 0; i < v->count; ++i) {
      const uint8_t* e = v->data + i * v->stride;
      for (int c = 0; c < N; ++c) {
        const float f = component(e + c * csize, v->ctype, v->normalized);
        if (!std::isfinite(f))
          return fail(where, "element " + std::to_string(i) + " is not finite (" +
                                 (std::isnan(f) ? "NaN" : "Inf") + ")");
        out[i][c] = f;
      }
    }
    if constexpr (N >= 3) {
      if (v->ctype != kFloat && !target && (semantic == "NORMAL" || semantic == "TANGENT"))
        for (glm::vec<N, float>& e : out) {
          const float len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
          if (len > 0.0f)
            for (int c = 0; c < 3; ++c) e[c] /= len;
        }
    }
    return {};
  }
  bool uses_extension(const char* name) const {
    return std::find(m_.extensionsUsed.begin(), m_.extensionsUsed.end(), name) !=
           m_.extensionsUsed.end();
  }

  Status read_indices(int index, const std::string& where, std::vector<uint32_t>& out) const {
    Result<View> v = view(index, where);
    if (!v.ok()) return v.status();
    if (v->comps != 1 || (v->ctype != kUByte && v->ctype != kUShort && v->ctype != kUInt))
      return fail(where, "accessor " + std::to_string(index) + " is " +
                             type_name(m_.accessors[index].type) + " of " +
                             component_name(v->ctype) +
                             ", expected SCALAR of UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    out.resize(v->count);
    for (size_t i = 0; i < v->count; ++i) {
      const uint8_t* e = v->data + i * v->stride;
      if (v->ctype == kUByte) {
        out[i] = e[0];
      } else if (v->ctype == kUShort) {
        uint16_t u;
        std::memcpy(&u, e, 2);
        out[i] = u;
      } else {
        std::memcpy(&out[i], e, 4);
      }
    }
    return {};
  }

  // A primitive's mesh: shared by the nodes that use it, except on a node with a skin or morph
  // targets (`deform_node` >= 0), which gets its own mesh and a Deformer.
  Result<int> primitive_mesh(int mesh, int prim, int material_index, int deform_node = -1) {
    const PrimitiveKey key{mesh, prim};
    if (deform_node < 0)
      if (auto it = meshes_.find(key); it != meshes_.end()) return it->second;
    const tinygltf::Primitive& p = m_.meshes[mesh].primitives[prim];
    const std::string pp =
        "/meshes/" + std::to_string(mesh) + "/primitives/" + std::to_string(prim);
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES) {
      static const char* names[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                    "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
      return fail(pp + "/mode",
                  std::string("mode ") +
                      (mode >= 0 && mode <= 6 ? names[mode] : std::to_string(mode).c_str()) +
                      " is not supported (only TRIANGLES)");
    }
    Mesh out;
    out.name = m_.meshes[mesh].name.empty() ? "mesh" + std::to_string(mesh) : m_.meshes[mesh].name;
    if (m_.meshes[mesh].primitives.size() > 1) out.name += "/" + std::to_string(prim);
    const std::string ap = pp + "/attributes";
    auto attr = [&](const char* name) {
      auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    if (attr("POSITION") < 0) return fail(ap, "no POSITION attribute");
    RELIEF_RETURN_IF_ERROR(read_attr<3>(attr("POSITION"), ap + "/POSITION", false, out.positions));
    const size_t n = out.positions.size();
    auto same_count = [&](const char* name, size_t count) -> Status {
      if (count == n) return {};
      return fail(ap + "/" + name, "accessor " + std::to_string(attr(name)) + " has " +
                                       std::to_string(count) + " elements, POSITION has " +
                                       std::to_string(n));
    };
    if (attr("NORMAL") >= 0) {
      RELIEF_RETURN_IF_ERROR(read_attr<3>(attr("NORMAL"), ap + "/NORMAL", false, out.normals));
      RELIEF_RETURN_IF_ERROR(same_count("NORMAL", out.normals.size()));
    }
    if (attr("TEXCOORD_0") >= 0) {
      RELIEF_RETURN_IF_ERROR(read_attr<2>(attr("TEXCOORD_0"), ap + "/TEXCOORD_0", true, out.uvs));
      RELIEF_RETURN_IF_ERROR(same_count("TEXCOORD_0", out.uvs.size()));
    }
    if (attr("TEXCOORD_1") >= 0) {
      RELIEF_RETURN_IF_ERROR(read_attr<2>(attr("TEXCOORD_1"), ap + "/TEXCOORD_1", true, out.uvs1));
      RELIEF_RETURN_IF_ERROR(same_count("TEXCOORD_1", out.uvs1.size()));
    }
    if (material_index >= 0 && !materials_[material_index].needs_uv1.empty() && out.uvs1.empty())
      return fail(
          ap, "no TEXCOORD_1 attribute, which " + materials_[material_index].needs_uv1 + " reads");
    if (attr("COLOR_0") >= 0) {
      const int ci = attr("COLOR_0");
      const std::string cp = ap + "/COLOR_0";
      if (ci < static_cast<int>(m_.accessors.size()) && m_.accessors[ci].type == 3) {
        std::vector<glm::vec3> rgb;
        RELIEF_RETURN_IF_ERROR(read_attr<3>(ci, cp, true, rgb));
        out.colors.reserve(rgb.size());
        for (const glm::vec3& c : rgb) out.colors.push_back(glm::vec4(c, 1.0f));
      } else {
        RELIEF_RETURN_IF_ERROR(read_attr<4>(ci, cp, true, out.colors));
      }
      RELIEF_RETURN_IF_ERROR(same_count("COLOR_0", out.colors.size()));
    }
    if (attr("TANGENT") >= 0) {
      RELIEF_RETURN_IF_ERROR(read_attr<4>(attr("TANGENT"), ap + "/TANGENT", false, out.tangents));
      RELIEF_RETURN_IF_ERROR(same_count("TANGENT", out.tangents.size()));
      // glTF's bitangent w * cross(N, T) points to the image top (-v); ours points along +v
      for (glm::vec4& t : out.tangents) t.w = -t.w;
    }
    if (p.indices >= 0) {
      RELIEF_RETURN_IF_ERROR(read_indices(p.indices, pp + "/indices", out.indices));
      if (out.indices.size() % 3)
        return fail(pp + "/indices",
                    std::to_string(out.indices.size()) + " indices do not make whole triangles");
      for (uint32_t i : out.indices)
        if (i >= n)
          return fail(pp + "/indices", "index " + std::to_string(i) + " out of range (" +
                                           std::to_string(n) + " vertices)");
    } else {
      if (n % 3)
        return fail(ap + "/POSITION",
                    std::to_string(n) + " vertices without indices do not make whole triangles");
      out.indices.resize(n);
      for (size_t i = 0; i < n; ++i) out.indices[i] = static_cast<uint32_t>(i);
    }
    if (material_index >= 0 && materials_[material_index].bake_uv) {
      for (glm::vec2& uv : out.uvs) uv = materials_[material_index].uv.apply(uv);
      out.tangents.clear();  // the frame follows the rotated uv
    }
    prepare_mesh(out);
    if (deform_node >= 0 && out.positions.size() != n)
      return fail(pp + "/attributes",
                  "a skinned or morphed mesh whose uv mirrors (tangent handedness split by "
                  "mesh preparation) needs a TANGENT attribute");
    scene_.meshes.push_back(out);
    const int id = static_cast<int>(scene_.meshes.size()) - 1;
    if (deform_node < 0) {
      meshes_[key] = id;
      return id;
    }
    Deformer d;
    d.mesh = id;
    d.node = deform_node;
    d.skin = m_.nodes[deform_node].skin;
    d.rest = std::move(out);
    RELIEF_RETURN_IF_ERROR(read_deformation(p, pp, d));
    deformers_.push_back(std::move(d));
    return id;
  }

  // Morph targets and skin attributes of a deformed primitive (glTF 3.7.2.2, 3.7.3).
  Status read_deformation(const tinygltf::Primitive& p, const std::string& pp, Deformer& d) const {
    const size_t n = d.rest.positions.size();
    for (size_t t = 0; t < p.targets.size(); ++t) {
      MorphTarget mt;
      const std::string tp = pp + "/targets/" + std::to_string(t);
      for (const auto& [name, index] : p.targets[t]) {
        std::vector<glm::vec3>* dst = name == "POSITION"  ? &mt.positions
                                      : name == "NORMAL"  ? &mt.normals
                                      : name == "TANGENT" ? &mt.tangents
                                                          : nullptr;
        if (!dst)
          return fail(tp + "/" + name,
                      "morph target attribute not supported (POSITION, NORMAL, TANGENT)");
        RELIEF_RETURN_IF_ERROR(read_attr<3>(index, tp + "/" + name, false, *dst));
        if (dst->size() != n)
          return fail(tp + "/" + name, "accessor " + std::to_string(index) + " has " +
                                           std::to_string(dst->size()) +
                                           " elements, POSITION has " + std::to_string(n));
      }
      d.targets.push_back(std::move(mt));
    }
    const std::string ap = pp + "/attributes";
    for (const char* extra : {"JOINTS_1", "WEIGHTS_1"})
      if (p.attributes.count(extra))
        return fail(ap + "/" + extra, "at most four joint influences are supported (JOINTS_0)");
    if (d.skin < 0) return {};
    const auto j = p.attributes.find("JOINTS_0"), w = p.attributes.find("WEIGHTS_0");
    if (j == p.attributes.end() || w == p.attributes.end())
      return fail(ap, "a skinned mesh needs JOINTS_0 and WEIGHTS_0");
    const size_t joint_count = m_.skins[d.skin].joints.size();
    std::vector<float> joints;
    RELIEF_RETURN_IF_ERROR(
        read_floats(j->second, ap + "/JOINTS_0", TINYGLTF_TYPE_VEC4, {kUByte, kUShort}, joints));
    std::vector<float> weights;
    RELIEF_RETURN_IF_ERROR(read_floats(w->second, ap + "/WEIGHTS_0", TINYGLTF_TYPE_VEC4,
                                       {kFloat, -kUByte, -kUShort}, weights));
    if (joints.size() != 4 * n || weights.size() != 4 * n)
      return fail(ap + (joints.size() != 4 * n ? "/JOINTS_0" : "/WEIGHTS_0"),
                  "expected " + std::to_string(n) + " elements, as POSITION");
    d.joints.resize(n);
    d.weights.resize(n);
    for (size_t v = 0; v < n; ++v)
      for (int c = 0; c < 4; ++c) {
        const float jf = joints[4 * v + c], wf = weights[4 * v + c];
        if (wf < 0.0f)
          return fail(ap + "/WEIGHTS_0", "element " + std::to_string(v) + " has a negative weight");
        if (wf > 0.0f && jf >= joint_count)
          return fail(ap + "/JOINTS_0", "element " + std::to_string(v) + " names joint " +
                                            std::to_string(static_cast<long>(jf)) +
                                            " (the skin has " + std::to_string(joint_count) + ")");
        d.joints[v][c] = static_cast<uint16_t>(wf > 0.0f ? jf : 0.0f);
        d.weights[v][c] = wf;
      }
    return {};
  }

  // Reads every component of an accessor of `type` as float. `ctypes` lists the accepted
  // component types: positive as stored (integers as their value), negative normalised.
  Status read_floats(int index, const std::string& where, int type, std::vector<int> ctypes,
                     std::vector<float>& out) const {
    Result<View> v = view(index, where);
    if (!v.ok()) return v.status();
    const bool ok_ctype =
        std::find(ctypes.begin(), ctypes.end(), v->normalized ? -v->ctype : v->ctype) !=
            ctypes.end() ||
        (v->ctype == kFloat && std::find(ctypes.begin(), ctypes.end(), kFloat) != ctypes.end());
    if (m_.accessors[index].type != type || !ok_ctype) {
      std::string list;
      for (int c : ctypes)
        list += (list.empty() ? "" : ", ") + std::string(c < 0 ? "normalized " : "") +
                component_name(std::abs(c));
      return fail(where, "accessor " + std::to_string(index) + " is " +
                             type_name(m_.accessors[index].type) + " of " +
                             component_name(v->ctype) + (v->normalized ? " (normalized)" : "") +
                             ", expected " + type_name(type) + " of " + list);
    }
    const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(v->ctype));
    out.resize(v->count * v->comps);
    for (size_t i = 0; i < v->count; ++i)
      for (int c = 0; c < v->comps; ++c) {
        const float f = component(v->data + i * v->stride + c * csize, v->ctype, v->normalized);
        if (!std::isfinite(f))
          return fail(where, "element " + std::to_string(i) + " is not finite");
        out[i * v->comps + c] = f;
      }
    return {};
  }

  // ---- nodes ----
  Result<glm::dmat4> local_matrix(int index) const {
    const tinygltf::Node& n = m_.nodes[index];
    const std::string np = "/nodes/" + std::to_string(index);
    auto finite = [&](const std::vector<double>& v, const char* key, size_t size) -> Status {
      if (!v.empty() && v.size() != size)
        return fail(np + "/" + key, "expected " + std::to_string(size) + " numbers");
      for (size_t i = 0; i < v.size(); ++i)
        if (!std::isfinite(v[i]))
          return fail(np + "/" + key + "/" + std::to_string(i), "not finite");
      return {};
    };
    RELIEF_RETURN_IF_ERROR(finite(n.matrix, "matrix", 16));
    RELIEF_RETURN_IF_ERROR(finite(n.translation, "translation", 3));
    RELIEF_RETURN_IF_ERROR(finite(n.rotation, "rotation", 4));
    RELIEF_RETURN_IF_ERROR(finite(n.scale, "scale", 3));
    if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
    glm::dmat4 m(1.0);
    if (n.translation.size() == 3)
      m = glm::translate(m, glm::dvec3(n.translation[0], n.translation[1], n.translation[2]));
    if (n.rotation.size() == 4) {
      const glm::dquat q(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      if (glm::length(q) < 1e-6) return fail(np + "/rotation", "quaternion has zero length");
      m = m * glm::mat4_cast(glm::normalize(q));
    }
    if (n.scale.size() == 3) m = glm::scale(m, glm::dvec3(n.scale[0], n.scale[1], n.scale[2]));
    return m;
  }

  Status read_nodes() {
    if (m_.scenes.empty()) {
      if (!m_.nodes.empty()) return fail("/scenes", "the file has nodes but no scene");
      return {};
    }
    const int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
    if (si >= static_cast<int>(m_.scenes.size()))
      return fail("/scene", "scene " + std::to_string(si) + " does not exist");
    std::vector<bool> seen(m_.nodes.size(), false);
    int order = 0;
    node_parent_.assign(m_.nodes.size(), -1);
    // Depth first with an explicit stack (a file may nest thousands of nodes), children pushed
    // in reverse so that nodes are visited in the order a recursive walk would take.
    struct Visit {
      int index, parent_index, depth;
      glm::dmat4 parent;
      std::string ref;  // JSON pointer of the reference to the node
    };
    std::vector<Visit> stack;
    const auto& roots = m_.scenes[si].nodes;
    for (size_t r = roots.size(); r-- > 0;)
      stack.push_back({roots[r], -1, 1, glm::dmat4(1.0),
                       "/scenes/" + std::to_string(si) + "/nodes/" + std::to_string(r)});
    while (!stack.empty()) {
      Visit v = std::move(stack.back());
      stack.pop_back();
      const int index = v.index;
      if (index < 0 || index >= static_cast<int>(m_.nodes.size()))
        return fail(v.ref, "node " + std::to_string(index) + " does not exist");
      const std::string np = "/nodes/" + std::to_string(index);
      if (seen[index])
        return fail(v.ref,
                    "node " + std::to_string(index) + " is reached twice (a cycle or two parents)");
      if (v.depth > kMaxNodeDepth)
        return fail(np, "node is " + std::to_string(v.depth) +
                            " levels deep in the hierarchy, more than the limit of " +
                            std::to_string(kMaxNodeDepth));
      seen[index] = true;
      const tinygltf::Node& n = m_.nodes[index];
      Result<glm::dmat4> local = local_matrix(index);
      if (!local.ok()) return local.status();
      const glm::dmat4 world = v.parent * *local;
      if (n.skin >= 0 && n.skin >= static_cast<int>(m_.skins.size()))
        return fail(np + "/skin", "skin " + std::to_string(n.skin) + " does not exist");
      if (n.skin >= 0 && n.mesh < 0) return fail(np + "/skin", "a skin needs a mesh on its node");
      node_parent_[index] = v.parent_index;
      if (n.mesh >= 0) {
        if (n.mesh >= static_cast<int>(m_.meshes.size()))
          return fail(np + "/mesh", "mesh " + std::to_string(n.mesh) + " does not exist");
        const auto& prims = m_.meshes[n.mesh].primitives;
        if (prims.empty())
          return fail("/meshes/" + std::to_string(n.mesh) + "/primitives",
                      "a mesh needs at least one primitive");
        for (size_t k = 0; k < prims.size(); ++k) {
          int mat = prims[k].material;
          if (mat >= static_cast<int>(materials_.size()))
            return fail("/meshes/" + std::to_string(n.mesh) + "/primitives/" + std::to_string(k) +
                            "/material",
                        "material " + std::to_string(mat) + " does not exist");
          const bool deformed = n.skin >= 0 || !prims[k].targets.empty();
          Result<int> mesh =
              primitive_mesh(n.mesh, static_cast<int>(k), mat, deformed ? index : -1);
          if (!mesh.ok()) return mesh.status();
          if (mat < 0) {
            if (default_material_ < 0) default_material_ = static_cast<int>(materials_.size());
            mat = default_material_;
          }
          if (scene_.instances.size() >= kMaxSceneInstances)
            return fail("/scenes/" + std::to_string(si),
                        "more than " + std::to_string(kMaxSceneInstances) +
                            " mesh instances (node and primitive pairs), the limit");
          instance_nodes_.push_back({index, static_cast<int>(scene_.instances.size())});
          scene_.instances.push_back({*mesh, mat, glm::mat4(world)});
        }
      }
      if (n.camera >= 0) {
        if (n.camera >= static_cast<int>(m_.cameras.size()))
          return fail(np + "/camera", "camera " + std::to_string(n.camera) + " does not exist");
        camera_nodes_.push_back({n.camera, index, order++, world});
      }
      RELIEF_RETURN_IF_ERROR(read_node_light(index, world));
      for (size_t c = n.children.size(); c-- > 0;)
        stack.push_back(
            {n.children[c], index, v.depth + 1, world, np + "/children/" + std::to_string(c)});
    }
    return {};
  }

  // ---- lights ----
  Status read_node_light(int node, const glm::dmat4& world) {
    const std::string np = "/nodes/" + std::to_string(node);
    Result<json> ext = extension(m_.nodes[node].extensions_json_string, kLightsPunctual, np);
    if (!ext.ok()) return ext.status();
    if (ext->is_null()) return {};
    const std::string ep = np + "/extensions/" + kLightsPunctual;
    int li = -1;
    if (!ext->contains("light")) return fail(ep, "missing 'light'");
    RELIEF_RETURN_IF_ERROR(get_int(*ext, "light", ep, li, 0, 1 << 30));
    if (li >= static_cast<int>(m_.lights.size()))
      return fail(ep + "/light", "light " + std::to_string(li) + " does not exist");
    const tinygltf::Light& gl = m_.lights[li];
    glm::dvec3 direction_hint(0.0);
    const std::string lp =
        std::string("/extensions/") + kLightsPunctual + "/lights/" + std::to_string(li);
    Light l;
    l.name = gl.name.empty() ? "light" + std::to_string(li) : gl.name;
    if (gl.type == "directional")
      l.type = LightType::kDirectional;
    else if (gl.type == "point")
      l.type = LightType::kPoint;
    else if (gl.type == "spot")
      l.type = LightType::kSpot;
    else
      return fail(lp + "/type",
                  "unknown light type '" + gl.type + "' (directional, point or spot)");
    if (!gl.color.empty()) {
      if (gl.color.size() != 3) return fail(lp + "/color", "expected 3 numbers");
      for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(gl.color[i]) || gl.color[i] < 0.0)
          return fail(lp + "/color/" + std::to_string(i), "expected a number >= 0");
        l.color[i] = static_cast<float>(gl.color[i]);
      }
    }
    if (!std::isfinite(gl.intensity) || gl.intensity < 0.0)
      return fail(lp + "/intensity", "expected a number >= 0");
    l.intensity = static_cast<float>(gl.intensity);
    if (!std::isfinite(gl.range) || gl.range < 0.0)
      return fail(lp + "/range", "expected a number > 0");
    l.range = static_cast<float>(gl.range);
    if (l.type == LightType::kSpot) {
      const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
      if (!(outer > 0.0 && outer <= kPi / 2))
        return fail(lp + "/spot/outerConeAngle", "expected an angle in (0, pi/2]");
      if (!(inner >= 0.0 && inner < outer))
        return fail(lp + "/spot/innerConeAngle", "expected an angle in [0, outerConeAngle)");
      l.inner_cone_deg = static_cast<float>(inner * 180.0 / kPi);
      l.outer_cone_deg = static_cast<float>(outer * 180.0 / kPi);
    }
    Result<json> rext = extension(gl.extensions_json_string, kReliefExtension, lp);
    if (!rext.ok()) return rext.status();
    if (!rext->is_null()) {
      const std::string rp = lp + "/extensions/" + kReliefExtension;
      RELIEF_RETURN_IF_ERROR(check_keys(
          *rext, rp, {"casts_shadows", "shadow_resolution", "direction", "color", "intensity"}));
      RELIEF_RETURN_IF_ERROR(get_bool(*rext, "casts_shadows", rp, l.casts_shadows));
      RELIEF_RETURN_IF_ERROR(
          get_int(*rext, "shadow_resolution", rp, l.shadow_resolution, 16, 16384));
      RELIEF_RETURN_IF_ERROR(get_vec<3>(*rext, "direction", rp, direction_hint, -2.0, 2.0));
      // The colour and intensity as relief had them (glTF's colour lies in [0, 1]), kept while
      // their product is the file's.
      glm::dvec3 color(-1.0);
      double intensity = -1.0;
      RELIEF_RETURN_IF_ERROR(get_vec<3>(*rext, "color", rp, color, 0.0, 1e30));
      RELIEF_RETURN_IF_ERROR(get_number(*rext, "intensity", rp, intensity, 0.0, 1e30));
      if (color.x >= 0.0 && intensity >= 0.0) {
        const glm::dvec3 want = glm::dvec3(l.color) * double(l.intensity);
        const glm::dvec3 got = color * intensity;
        if (glm::length(got - want) <= 1e-6 * glm::length(want)) {
          l.color = glm::vec3(color);
          l.intensity = static_cast<float>(intensity);
        }
      }
    }
    l.position = glm::vec3(world * glm::dvec4(0, 0, 0, 1));
    l.direction = glm::vec3(glm::normalize(glm::dmat3(world) * glm::dvec3(0, 0, -1)));
    // Our export's exact direction bits, kept while the node still points that way.
    if (glm::length(direction_hint) > 0.0 &&
        glm::dot(glm::normalize(direction_hint), glm::normalize(glm::dvec3(l.direction))) >
            1.0 - 1e-9)
      l.direction = glm::vec3(direction_hint);
    light_nodes_.push_back({node, static_cast<int>(scene_.lights.size())});
    scene_.lights.push_back(l);
    return {};
  }

  // ---- cameras ----
  // Our export's exact target and up (the camera node's RELIEF_relief_mapping), kept while the
  // node still looks that way (view direction and roll within 1e-9 of the node's).
  Status camera_hint(const CameraNode& cn, Camera& c) const {
    const std::string np = "/nodes/" + std::to_string(cn.node);
    Result<json> ext = extension(m_.nodes[cn.node].extensions_json_string, kReliefExtension, np);
    if (!ext.ok()) return ext.status();
    if (ext->is_null()) return {};
    const std::string ep = np + "/extensions/" + kReliefExtension;
    RELIEF_RETURN_IF_ERROR(check_keys(*ext, ep, {"target", "up"}));
    glm::dvec3 target(c.target), up(c.up);
    RELIEF_RETURN_IF_ERROR(get_vec<3>(*ext, "target", ep, target, -1e30, 1e30));
    RELIEF_RETURN_IF_ERROR(get_vec<3>(*ext, "up", ep, up, -1e30, 1e30));
    const glm::dmat3 rot(cn.world);
    const glm::dvec3 fwd = glm::normalize(rot * glm::dvec3(0, 0, -1));
    const glm::dvec3 node_side = glm::normalize(glm::cross(fwd, rot * glm::dvec3(0, 1, 0)));
    const glm::dvec3 to = glm::dvec3(glm::vec3(target)) - glm::dvec3(c.position);
    const glm::dvec3 side = glm::cross(fwd, glm::dvec3(glm::vec3(up)));
    if (glm::length(to) > 0.0 && glm::length(side) > 0.0 &&
        glm::dot(glm::normalize(to), fwd) > 1.0 - 1e-9 &&
        glm::dot(glm::normalize(side), node_side) > 1.0 - 1e-9) {
      c.target = glm::vec3(target);
      c.up = glm::vec3(up);
    }
    return {};
  }

  Status place_cameras() {
    glm::dvec3 lo, hi;
    scene_bounds(scene_, lo, hi);
    const glm::dvec3 centre = (lo + hi) * 0.5;
    centre_ = centre;
    const double radius = std::max(glm::length(hi - lo) * 0.5, 1e-3);
    if (camera_nodes_.empty()) {
      scene_.cameras.push_back(default_camera(centre, radius));
      return {};
    }
    std::stable_sort(camera_nodes_.begin(), camera_nodes_.end(),
                     [](const CameraNode& a, const CameraNode& b) { return a.camera < b.camera; });
    for (const CameraNode& cn : camera_nodes_) {
      const tinygltf::Camera& gc = m_.cameras[cn.camera];
      const std::string cp = "/cameras/" + std::to_string(cn.camera);
      Camera c;
      c.name = !gc.name.empty()                  ? gc.name
               : !m_.nodes[cn.node].name.empty() ? m_.nodes[cn.node].name
                                                 : "camera" + std::to_string(cn.camera);
      double znear = 0.0, zfar = 0.0;
      if (gc.type == "perspective") {
        const auto& p = gc.perspective;
        if (!(std::isfinite(p.yfov) && p.yfov > 0.0 && p.yfov < kPi))
          return fail(cp + "/perspective/yfov", "expected an angle in (0, pi)");
        c.yfov_deg = static_cast<float>(p.yfov * 180.0 / kPi);
        znear = p.znear;
        zfar = p.zfar;
        if (!(std::isfinite(znear) && znear > 0.0))
          return fail(cp + "/perspective/znear", "expected a number > 0");
      } else if (gc.type == "orthographic") {
        const auto& o = gc.orthographic;
        if (!(std::isfinite(o.ymag) && o.ymag > 0.0))
          return fail(cp + "/orthographic/ymag", "expected a number > 0");
        c.orthographic = true;
        c.ortho_half_height = static_cast<float>(o.ymag);
        znear = o.znear;
        zfar = o.zfar;
        if (!(std::isfinite(znear) && znear >= 0.0))
          return fail(cp + "/orthographic/znear", "expected a number >= 0");
        if (!(zfar > 0.0)) return fail(cp + "/orthographic/zfar", "expected a number > 0");
      } else {
        return fail(cp + "/type", "unknown camera type '" + gc.type + "'");
      }
      const glm::dvec3 pos(cn.world * glm::dvec4(0, 0, 0, 1));
      if (zfar == 0.0) {  // infinite perspective: reach past the farthest corner of the bounds
        double far = 0.0;
        for (int k = 0; k < 8; ++k) {
          const glm::dvec3 corner((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y,
                                  (k & 4) ? hi.z : lo.z);
          far = std::max(far, glm::length(corner - pos));
        }
        zfar = std::max(far * 1.5, znear * 2.0);
      }
      if (!(std::isfinite(zfar) && zfar > znear))
        return fail(cp + (c.orthographic ? "/orthographic" : "/perspective") + "/zfar",
                    "expected a number > znear");
      c.znear = static_cast<float>(znear);
      c.zfar = static_cast<float>(zfar);
      orient_camera(c, cn.world, centre);
      RELIEF_RETURN_IF_ERROR(camera_hint(cn, c));
      camera_nodes_bound_.push_back({cn.node, static_cast<int>(scene_.cameras.size())});
      scene_.cameras.push_back(c);
    }
    return {};
  }

  // No camera in the file: look at the centre of the bounds from +z, 30 degrees above the
  // horizon, far enough for the bounding sphere to fit a 45-degree vertical field of view.
  static Camera default_camera(const glm::dvec3& centre, double radius) {
    Camera c;
    c.name = "default";
    c.yfov_deg = 45.0f;
    const double dist = radius / std::sin(22.5 * kPi / 180.0);
    const glm::dvec3 dir(0.0, std::sin(kPi / 6), std::cos(kPi / 6));
    c.position = glm::vec3(centre + dir * dist);
    c.target = glm::vec3(centre);
    c.up = glm::vec3(0, 1, 0);
    c.znear = static_cast<float>(dist * 0.01);
    c.zfar = static_cast<float>(dist + 2.0 * radius);
    return c;
  }

  // ---- animations, skins, morph weights ----
  // Builds Scene::animation when the file has animations, skins or morph targets, and poses the
  // scene at time 0 of the first animation.
  Status read_animation() {
    if (m_.animations.empty() && deformers_.empty()) return {};
    auto anim = std::make_shared<SceneAnimation>();
    anim->centre = centre_;
    anim->instances = instance_nodes_;
    anim->cameras = camera_nodes_bound_;
    anim->lights = light_nodes_;
    for (size_t i = 0; i < m_.nodes.size(); ++i) {
      const tinygltf::Node& n = m_.nodes[i];
      AnimNode an;
      an.name = n.name;
      an.parent = node_parent_[i];
      an.has_matrix = n.matrix.size() == 16;
      if (an.has_matrix) an.matrix = glm::make_mat4(n.matrix.data());
      if (n.translation.size() == 3)
        an.translation = glm::dvec3(n.translation[0], n.translation[1], n.translation[2]);
      if (n.rotation.size() == 4)
        an.rotation = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      if (n.scale.size() == 3) an.scale = glm::dvec3(n.scale[0], n.scale[1], n.scale[2]);
      RELIEF_RETURN_IF_ERROR(node_weights(static_cast<int>(i), an.weights));
      anim->nodes.push_back(std::move(an));
    }
    for (size_t s = 0; s < m_.skins.size(); ++s) {
      const tinygltf::Skin& gs = m_.skins[s];
      const std::string sp = "/skins/" + std::to_string(s);
      Skin skin;
      for (size_t j = 0; j < gs.joints.size(); ++j) {
        if (gs.joints[j] < 0 || gs.joints[j] >= static_cast<int>(m_.nodes.size()))
          return fail(sp + "/joints/" + std::to_string(j),
                      "node " + std::to_string(gs.joints[j]) + " does not exist");
        skin.joints.push_back(gs.joints[j]);
      }
      if (skin.joints.empty()) return fail(sp + "/joints", "a skin needs at least one joint");
      skin.inverse_bind.assign(skin.joints.size(), glm::dmat4(1.0));
      if (gs.inverseBindMatrices >= 0) {
        std::vector<float> m;
        RELIEF_RETURN_IF_ERROR(read_floats(gs.inverseBindMatrices, sp + "/inverseBindMatrices",
                                           TINYGLTF_TYPE_MAT4, {kFloat}, m));
        if (m.size() < 16 * skin.joints.size())
          return fail(sp + "/inverseBindMatrices",
                      "has " + std::to_string(m.size() / 16) + " matrices for " +
                          std::to_string(skin.joints.size()) + " joints");
        for (size_t j = 0; j < skin.joints.size(); ++j)
          skin.inverse_bind[j] = glm::dmat4(glm::make_mat4(&m[16 * j]));
      }
      anim->skins.push_back(std::move(skin));
    }
    for (size_t a = 0; a < m_.animations.size(); ++a) {
      Result<AnimationClip> clip = read_clip(static_cast<int>(a), *anim);
      if (!clip.ok()) return clip.status();
      anim->clips.push_back(std::move(*clip));
    }
    anim->deformers = deformers_;
    pose_scene(*anim, PoseOptions{}, 0.0, scene_);
    scene_.animation = std::move(anim);
    return {};
  }

  // The morph weights of node i's mesh: the node's, else the mesh's, else zeros.
  Status node_weights(int i, std::vector<float>& out) const {
    const tinygltf::Node& n = m_.nodes[i];
    if (n.mesh < 0 || n.mesh >= static_cast<int>(m_.meshes.size())) return {};
    const tinygltf::Mesh& mesh = m_.meshes[n.mesh];
    const size_t targets = mesh.primitives.empty() ? 0 : mesh.primitives[0].targets.size();
    for (size_t k = 1; k < mesh.primitives.size(); ++k)
      if (mesh.primitives[k].targets.size() != targets)
        return fail(
            "/meshes/" + std::to_string(n.mesh) + "/primitives/" + std::to_string(k) + "/targets",
            "every primitive of a mesh needs the same number of morph targets");
    const bool own = !n.weights.empty();
    const std::vector<double>& w = own ? n.weights : mesh.weights;
    const std::string wp = own ? "/nodes/" + std::to_string(i) + "/weights"
                               : "/meshes/" + std::to_string(n.mesh) + "/weights";
    if (!w.empty() && w.size() != targets)
      return fail(wp, std::to_string(w.size()) + " weights for " + std::to_string(targets) +
                          " morph targets");
    out.assign(targets, 0.0f);
    for (size_t k = 0; k < w.size(); ++k) {
      if (!std::isfinite(w[k])) return fail(wp + "/" + std::to_string(k), "not finite");
      out[k] = static_cast<float>(w[k]);
    }
    return {};
  }

  Result<AnimationClip> read_clip(int index, const SceneAnimation& anim) const {
    const tinygltf::Animation& ga = m_.animations[index];
    const std::string ap = "/animations/" + std::to_string(index);
    AnimationClip clip;
    clip.name = ga.name.empty() ? "animation" + std::to_string(index) : ga.name;
    // Samplers are read for the channels that use them (their width depends on the path).
    std::vector<int> width(ga.samplers.size(), -1);
    std::vector<AnimPath> path(ga.samplers.size(), AnimPath::kTranslation);
    for (size_t c = 0; c < ga.channels.size(); ++c) {
      const tinygltf::AnimationChannel& gc = ga.channels[c];
      const std::string cp = ap + "/channels/" + std::to_string(c);
      // KHR_animation_pointer's channels (path "pointer", no node): ignored with a warning line
      // (scene/gltf_extensions.h), the rest of the animation plays.
      if (gc.target_path == "pointer" && gc.target_node < 0) continue;
      AnimationChannel ch;
      ch.node = gc.target_node;
      ch.sampler = gc.sampler;
      if (gc.sampler < 0 || gc.sampler >= static_cast<int>(ga.samplers.size()))
        return fail(cp + "/sampler", "sampler " + std::to_string(gc.sampler) + " does not exist");
      if (ch.node < 0 || ch.node >= static_cast<int>(m_.nodes.size()))
        return fail(cp + "/target/node", "node " + std::to_string(ch.node) + " does not exist");
      int w = 3;
      if (gc.target_path == "translation") {
        ch.path = AnimPath::kTranslation;
      } else if (gc.target_path == "rotation") {
        ch.path = AnimPath::kRotation;
        w = 4;
      } else if (gc.target_path == "scale") {
        ch.path = AnimPath::kScale;
      } else if (gc.target_path == "weights") {
        ch.path = AnimPath::kWeights;
        w = static_cast<int>(anim.nodes[ch.node].weights.size());
        if (w == 0)
          return fail(cp + "/target/path",
                      "node " + std::to_string(ch.node) + " has no mesh with morph targets");
      } else {
        return fail(cp + "/target/path", "unknown path '" + gc.target_path +
                                             "' (translation, rotation, scale, weights)");
      }
      if (ch.path != AnimPath::kWeights && anim.nodes[ch.node].has_matrix)
        return fail(cp + "/target/node",
                    "node " + std::to_string(ch.node) + " has a matrix and cannot be animated");
      if (width[ch.sampler] >= 0 && width[ch.sampler] != w)
        return fail(cp + "/sampler", "sampler shared by channels of different widths");
      width[ch.sampler] = w;
      path[ch.sampler] = ch.path;
      clip.channels.push_back(ch);
    }
    for (size_t i = 0; i < ga.samplers.size(); ++i) {
      const tinygltf::AnimationSampler& gs = ga.samplers[i];
      const std::string sp = ap + "/samplers/" + std::to_string(i);
      AnimationSampler s;
      if (width[i] < 0) {  // no channel uses it
        clip.samplers.push_back(s);
        continue;
      }
      s.width = width[i];
      if (gs.interpolation.empty() || gs.interpolation == "LINEAR")
        s.interpolation = Interpolation::kLinear;
      else if (gs.interpolation == "STEP")
        s.interpolation = Interpolation::kStep;
      else if (gs.interpolation == "CUBICSPLINE")
        s.interpolation = Interpolation::kCubicSpline;
      else
        return fail(sp + "/interpolation",
                    "unknown interpolation '" + gs.interpolation + "' (LINEAR, STEP, CUBICSPLINE)");
      RELIEF_RETURN_IF_ERROR(
          read_floats(gs.input, sp + "/input", TINYGLTF_TYPE_SCALAR, {kFloat}, s.times));
      for (size_t k = 0; k < s.times.size(); ++k)
        if (s.times[k] < 0.0f || (k > 0 && !(s.times[k] > s.times[k - 1])))
          return fail(sp + "/input", "key times must be >= 0 and strictly increasing (key " +
                                         std::to_string(k) + ")");
      const bool rot = path[i] == AnimPath::kRotation;
      const int type = path[i] == AnimPath::kWeights ? TINYGLTF_TYPE_SCALAR
                       : rot                         ? TINYGLTF_TYPE_VEC4
                                                     : TINYGLTF_TYPE_VEC3;
      std::vector<int> ctypes = {kFloat};
      if (rot) ctypes = {kFloat, -kByte, -kUByte, -kShort, -kUShort};
      RELIEF_RETURN_IF_ERROR(read_floats(gs.output, sp + "/output", type, ctypes, s.values));
      const size_t per_key =
          static_cast<size_t>(s.width) * (s.interpolation == Interpolation::kCubicSpline ? 3 : 1);
      if (s.values.size() != s.times.size() * per_key)
        return fail(sp + "/output", std::to_string(s.values.size()) + " values for " +
                                        std::to_string(s.times.size()) + " keys, expected " +
                                        std::to_string(s.times.size() * per_key));
      clip.duration = std::max(clip.duration, static_cast<double>(s.times.back()));
      clip.samplers.push_back(std::move(s));
    }
    return clip;
  }

  std::string path_;
  tinygltf::Model& m_;
  Scene scene_;
  std::vector<MaterialInfo> materials_;
  int default_material_ = -1;
  std::map<PrimitiveKey, int> meshes_;
  std::map<std::tuple<int, int, bool>, TexturePtr> textures_;
  std::vector<CameraNode> camera_nodes_;
  // Animation: parents, which node each instance, camera and light follows, deformed meshes.
  std::vector<int> node_parent_;
  std::vector<NodeBinding> instance_nodes_, camera_nodes_bound_, light_nodes_;
  std::vector<Deformer> deformers_;
  glm::dvec3 centre_{0.0};
};

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

}  // namespace

namespace {

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
  Reader reader(path, model);
  reader.set_scene_folder(scene_fs.folder);
  Result<Scene> scene = reader.read();
  if (!scene.ok()) return scene;
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
