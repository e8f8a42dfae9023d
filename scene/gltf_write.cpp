// glTF 2.0 output with the RELIEF_relief_mapping material extension (save_gltf; see gltf.h and
// docs/scene-format.md): the scene as .gltf (JSON, a .bin buffer and PNG images next to it) or
// .glb (everything embedded), with KHR_texture_transform, KHR_materials_emissive_strength,
// KHR_materials_unlit and KHR_lights_punctual, written so that load_gltf reads back the same
// scene. Every file is staged and renamed into place once all are written.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "rasterizer/output_file.h"
#include "rasterizer/safe_file.h"
#include "scene/animation.h"
#include "scene/gltf.h"
#include "scene/gltf_internal.h"

namespace relief {
namespace {

using namespace gltf_detail;  // the constants and helpers reading shares (gltf_internal.h)
using ojson = nlohmann::ordered_json;

// A float as the shortest decimal that reads back as the same float.
double shortest(float f) {
  char buf[64];
  auto r = std::to_chars(buf, buf + sizeof buf, f);
  return std::strtod(std::string(buf, r.ptr).c_str(), nullptr);
}
ojson vec_json(const float* v, int n) {
  ojson a = ojson::array();
  for (int i = 0; i < n; ++i) a.push_back(shortest(v[i]));
  return a;
}

bool is_float_format(TexFormat f) {
  return f == TexFormat::kR16F || f == TexFormat::kRGBA16F || f == TexFormat::kR32F;
}

// A double-precision quaternion (x, y, z, w) rotating -z onto `dir`.
glm::dquat rotation_to(const glm::dvec3& dir) {
  const glm::dvec3 a(0, 0, -1), b = glm::normalize(dir);
  const double d = glm::dot(a, b);
  if (d < -1.0 + 1e-12) return glm::dquat(0.0, 0.0, 1.0, 0.0);  // half turn about y
  const glm::dvec3 c = glm::cross(a, b);
  return glm::normalize(glm::dquat(1.0 + d, c.x, c.y, c.z));
}
ojson quat_json(const glm::dquat& q) {
  return ojson::array({q.x, q.y, q.z, q.w});
}

class Writer {
 public:
  Writer(const Scene& s, std::string path) : s_(s), path_(std::move(path)) {
    glb_ = has_suffix(path_, ".glb");
    const fs::path p(path_);
    dir_ = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    stem_ = p.stem().string();
  }

  Status write() {
    std::error_code ec;
    if (!fs::is_directory(dir_, ec)) return fail("directory does not exist");
    doc_["asset"] = {{"version", "2.0"}, {"generator", "relief save_gltf"}};
    used_.insert(kReliefExtension);
    RELIEF_RETURN_IF_ERROR(write_materials());
    write_meshes_and_nodes();
    write_cameras();
    write_lights();
    ojson root_ext = ojson::object();
    root_ext["ambient"] = vec_json(&s_.ambient[0], 3);
    root_ext["background"] = vec_json(&s_.background[0], 4);
    doc_["extensions"][kReliefExtension] = root_ext;
    if (!lights_json_.empty()) doc_["extensions"][kLightsPunctual] = {{"lights", lights_json_}};
    ojson scene_nodes = ojson::array();  // the roots
    std::set<size_t> children;
    for (const ojson& n : nodes_)
      if (n.contains("children"))
        for (const ojson& c : n["children"]) children.insert(c.get<size_t>());
    for (size_t i = 0; i < nodes_.size(); ++i)
      if (!children.count(i)) scene_nodes.push_back(i);
    doc_["scene"] = 0;
    doc_["scenes"] = ojson::array({{{"name", s_.name}, {"nodes", scene_nodes}}});
    doc_["nodes"] = nodes_;
    doc_["extensionsUsed"] = ojson(std::vector<std::string>(used_.begin(), used_.end()));
    while (bin_.size() % 4) bin_.push_back(0);
    ojson buffer = {{"byteLength", bin_.size()}};
    if (!glb_) {
      buffer["uri"] = stem_ + ".bin";
      RELIEF_RETURN_IF_ERROR(write_file(stem_ + ".bin", bin_));
    }
    doc_["buffers"] = ojson::array({buffer});
    doc_["bufferViews"] = views_;
    doc_["accessors"] = accessors_;
    std::string text = doc_.dump(glb_ ? -1 : 1);
    if (glb_) {
      while (text.size() % 4) text.push_back(' ');
      std::vector<uint8_t> out;
      auto u32 = [&](uint32_t v) {
        for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
      };
      u32(0x46546C67);  // "glTF"
      u32(2);
      u32(static_cast<uint32_t>(12 + 8 + text.size() + 8 + bin_.size()));
      u32(static_cast<uint32_t>(text.size()));
      u32(0x4E4F534A);  // "JSON"
      out.insert(out.end(), text.begin(), text.end());
      u32(static_cast<uint32_t>(bin_.size()));
      u32(0x004E4942);  // "BIN"
      out.insert(out.end(), bin_.begin(), bin_.end());
      RELIEF_RETURN_IF_ERROR(write_file(fs::path(path_).filename().string(), out));
    } else {
      text += "\n";
      RELIEF_RETURN_IF_ERROR(write_file(fs::path(path_).filename().string(),
                                        std::vector<uint8_t>(text.begin(), text.end())));
    }
    return staged_.commit();  // every file was written in full: rename them all into place
  }

 private:
  Status fail(const std::string& what) const {
    return Status::error(printable(path_) + ": " + what);
  }

  // Stages `name` in the output's folder (checked writes, fsync); renamed by write() at the end.
  Status write_file(const std::string& name, const std::vector<uint8_t>& bytes) {
    const std::string final_path = (fs::path(path_).parent_path() / name).string();
    return staged_.stage(
        final_path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
  }

  size_t add_view(const void* data, size_t bytes, int target) {
    while (bin_.size() % 4) bin_.push_back(0);
    ojson v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}};
    if (target) v["target"] = target;
    const uint8_t* p = static_cast<const uint8_t*>(data);
    bin_.insert(bin_.end(), p, p + bytes);
    views_.push_back(v);
    return views_.size() - 1;
  }
  template <int N>
  size_t add_accessor(const std::vector<glm::vec<N, float>>& v, bool bounds) {
    const size_t view = add_view(v.data(), v.size() * sizeof(v[0]), 34962);
    ojson a = {{"bufferView", view},
               {"componentType", kFloat},
               {"count", v.size()},
               {"type", "VEC" + std::to_string(N)}};
    if (bounds) {
      glm::vec<N, float> lo = v[0], hi = v[0];
      for (const auto& x : v) {
        lo = glm::min(lo, x);
        hi = glm::max(hi, x);
      }
      a["min"] = vec_json(&lo[0], N);
      a["max"] = vec_json(&hi[0], N);
    }
    accessors_.push_back(a);
    return accessors_.size() - 1;
  }

  // Level 0 of an 8-bit or R16 texture as PNG bytes (encoded through OpenImageIO).
  Result<std::vector<uint8_t>> png_bytes(const Texture& t, const std::string& what) {
    int ch = 0;
    OIIO::TypeDesc type = OIIO::TypeDesc::UINT8;
    switch (t.format()) {
      case TexFormat::kR8:
        ch = 1;
        break;
      case TexFormat::kRG8:
        ch = 2;
        break;
      case TexFormat::kRGBA8:
        ch = 4;
        break;
      case TexFormat::kR16:
        ch = 1;
        type = OIIO::TypeDesc::UINT16;
        break;
      default:  // float: a 16-bit preview of [0, 1] (relief reads the exact texels: "texels")
        ch = format_channels(t.format());
        type = OIIO::TypeDesc::UINT16;
        break;
    }
    const std::vector<uint8_t>& src = t.level(0).data;
    const size_t n = static_cast<size_t>(t.width()) * t.height();
    std::vector<uint8_t> px = src;
    if (is_float_format(t.format())) {
      px.assign(n * ch * 2, 0);
      for (int y = 0; y < t.height(); ++y)
        for (int x = 0; x < t.width(); ++x) {
          const glm::vec4 v = t.fetch(0, x, y);
          for (int c = 0; c < ch; ++c) {
            const float f = std::isfinite(v[c]) ? std::clamp(v[c], 0.0f, 1.0f) : 0.0f;
            const auto u = static_cast<uint16_t>(std::lround(f * 65535.0f));
            std::memcpy(&px[((static_cast<size_t>(y) * t.width() + x) * ch + c) * 2], &u, 2);
          }
        }
      if (ch == 4) {  // an opaque alpha channel is left out, as for 8-bit
        bool opaque = true;
        for (size_t i = 0; i < n && opaque; ++i) {
          uint16_t a;
          std::memcpy(&a, &px[(i * 4 + 3) * 2], 2);
          opaque = a == 65535;
        }
        if (opaque) {
          std::vector<uint8_t> rgb(n * 6);
          for (size_t i = 0; i < n; ++i) std::memcpy(&rgb[i * 6], &px[i * 8], 6);
          px = std::move(rgb);
          ch = 3;
        }
      }
    } else if (ch == 4) {  // drop an opaque alpha channel
      bool opaque = true;
      for (size_t i = 0; i < n && opaque; ++i) opaque = src[i * 4 + 3] == 255;
      if (opaque) {
        ch = 3;
        px.resize(n * 3);
        for (size_t i = 0; i < n; ++i)
          for (int c = 0; c < 3; ++c) px[i * 3 + c] = src[i * 4 + c];
      }
    }
    // Encoded in memory: no temporary file, every byte written by write_file's checked writes.
    OIIO::ImageSpec spec(t.width(), t.height(), ch, type);
    spec.attribute("png:compressionLevel", 9);
    std::vector<uint8_t> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create("png");
    bool ok = out && out->supports("ioproxy") && out->set_ioproxy(&proxy) &&
              out->open(stem_ + ".png", spec) && out->write_image(type, px.data());
    if (out) ok = out->close() && ok;
    if (!ok || bytes.empty()) return fail(what + ": cannot encode PNG");
    return bytes;
  }

  Result<int> image_for(const TexturePtr& t, const std::string& label) {
    if (auto it = images_.find(t.get()); it != images_.end()) return it->second;
    Result<std::vector<uint8_t>> png = png_bytes(*t, label);
    if (!png.ok()) return png.status();
    ojson img;
    if (glb_) {
      img["bufferView"] = add_view(png->data(), png->size(), 0);
      img["mimeType"] = "image/png";
    } else {
      std::string base = stem_ + "_" + label;
      for (char& c : base)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '-') c = '_';
      base = base.substr(0, 200);  // a file name stays under NAME_MAX with its temporary's suffix
      // Two labels can sanitise to one name (materials of one name): each file its own name.
      std::string name = base + ".png";
      for (int n = 2; !file_names_.insert(name).second; ++n)
        name = base + "_" + std::to_string(n) + ".png";
      img["uri"] = name;
      RELIEF_RETURN_IF_ERROR(write_file(name, *png));
    }
    doc_["images"].push_back(img);
    const int index = static_cast<int>(doc_["images"].size()) - 1;
    images_[t.get()] = index;
    return index;
  }

  // `mips`: the material's textures have mip chains (without, a minFilter that builds none, so
  // the reloaded textures have the same levels).
  int sampler_for(const SamplerState& s, bool mips) {
    const int key = static_cast<int>(s.filter) * 100 + static_cast<int>(s.wrap_u) * 10 +
                    static_cast<int>(s.wrap_v) + (mips ? 0 : 1000);
    if (auto it = samplers_.find(key); it != samplers_.end()) return it->second;
    auto wrap = [](Wrap w) {
      return w == Wrap::kClamp ? kClampToEdge : w == Wrap::kMirror ? kMirroredRepeat : kRepeat;
    };
    const int min = !mips ? (s.filter == Filter::kNearest ? kNearest : kLinear)
                    : s.filter == Filter::kNearest  ? kNearestMipNearest
                    : s.filter == Filter::kBilinear ? kLinearMipNearest
                                                    : kLinearMipLinear;
    doc_["samplers"].push_back({{"magFilter", s.filter == Filter::kNearest ? kNearest : kLinear},
                                {"minFilter", min},
                                {"wrapS", wrap(s.wrap_u)},
                                {"wrapT", wrap(s.wrap_v)}});
    const int index = static_cast<int>(doc_["samplers"].size()) - 1;
    samplers_[key] = index;
    return index;
  }

  // A textureInfo for texture t whose UvMap (from the uv varying) is `map`: its transform is map
  // composed with the material's main one (uv_scale, uv_offset) on TEXCOORD_0, map itself on
  // TEXCOORD_1, written as KHR_texture_transform offset, rotation and scale.
  Result<ojson> texture_info(const Material& m, const TexturePtr& t, const std::string& label,
                             const UvMap& map = UvMap()) {
    Result<int> img = image_for(t, label);
    if (!img.ok()) return img.status();
    // (ordered_json keeps members in a vector: no reference into doc_ across an insertion)
    bool mips = false;
    for (const auto& [slot, other] : m.textures) mips = mips || other->levels() > 1;
    const int sampler = sampler_for(m.sampler, mips);
    ojson tex = {{"sampler", sampler}, {"source", *img}};
    if (is_float_format(t->format())) {
      // Float texels exactly, level 0, little-endian (the PNG is a 16-bit preview for others).
      if (!raw_views_.count(t.get())) {
        const std::vector<uint8_t>& d = t->level(0).data;
        raw_views_[t.get()] = add_view(d.data(), d.size(), 0);
      }
      tex["extensions"][kReliefExtension] = {{"texels", raw_views_[t.get()]},
                                             {"format", format_name(t->format())},
                                             {"width", t->width()},
                                             {"height", t->height()}};
    }
    doc_["textures"].push_back(tex);
    ojson info = {{"index", doc_["textures"].size() - 1}};
    if (map.set == 1) info["texCoord"] = 1;
    glm::vec2 offset = m.uv_offset, scale = m.uv_scale;
    float rotation = 0.0f;
    if (!map.identity) {
      glm::dmat2 l(glm::dvec2(map.col0), glm::dvec2(map.col1));
      glm::dvec2 o(map.offset);
      if (map.set == 0) {
        o = l * glm::dvec2(m.uv_offset) + o;
        l = l * glm::dmat2(glm::dvec2(m.uv_scale.x, 0.0), glm::dvec2(0.0, m.uv_scale.y));
      }
      // l = R S with columns (c sx, -s sx), (s sy, c sy) (KHR_texture_transform's order)
      const double sx = glm::length(l[0]);
      const double th = std::atan2(-l[0].y, l[0].x);
      const glm::dvec2 r1(std::sin(th), std::cos(th));
      const double sy = glm::dot(l[1], r1);
      if (sx == 0.0 || glm::length(l[1] - sy * r1) > 1e-6 * (std::abs(sy) + sx))
        return fail("material '" + label + "': a texture transform with shear has no glTF form");
      offset = glm::vec2(o);
      scale = glm::vec2(static_cast<float>(sx), static_cast<float>(sy));
      rotation = static_cast<float>(th);
    }
    if (scale != glm::vec2(1.0f) || offset != glm::vec2(0.0f) || rotation != 0.0f) {
      ojson tt = ojson::object();
      if (offset != glm::vec2(0.0f)) tt["offset"] = vec_json(&offset[0], 2);
      if (rotation != 0.0f) tt["rotation"] = shortest(rotation);
      if (scale != glm::vec2(1.0f)) tt["scale"] = vec_json(&scale[0], 2);
      info["extensions"][kTextureTransform] = tt;
      used_.insert(kTextureTransform);
    }
    return info;
  }
  static UvMap slot_map(const Material& m, const std::string& slot) {
    auto it = m.uv_maps.find(slot);
    return it == m.uv_maps.end() ? UvMap() : it->second;
  }

  // pbrMetallicRoughness: base colour, and the metallic-roughness terms of a material lit by them
  // (a Blinn-Phong material writes metallicFactor 0: a viewer without RELIEF_relief_mapping then
  // shows a dielectric).
  Result<ojson> pbr_json(const Material& m, const std::string& label) {
    ojson pbr = {{"baseColorFactor", vec_json(&m.base_color[0], 4)}};
    if (auto it = m.textures.find("base_color"); it != m.textures.end()) {
      Result<ojson> ti =
          texture_info(m, it->second, label + "_base_color", slot_map(m, "base_color"));
      if (!ti.ok()) return ti.status();
      pbr["baseColorTexture"] = *ti;
    }
    if (m.shading == ShadingModel::kBlinnPhong) {
      pbr["metallicFactor"] = 0.0;
      return pbr;
    }
    pbr["metallicFactor"] = shortest(m.metallic);
    pbr["roughnessFactor"] = shortest(m.roughness);
    if (m.metallic_roughness_texture) {
      Result<ojson> ti = texture_info(m, m.metallic_roughness_texture,
                                      label + "_metallic_roughness", m.metallic_roughness_uv);
      if (!ti.ok()) return ti.status();
      pbr["metallicRoughnessTexture"] = *ti;
    }
    return pbr;
  }

  Status write_materials() {
    doc_["materials"] = ojson::array();
    for (size_t i = 0; i < s_.materials.size(); ++i) {
      const Material& m = s_.materials[i];
      const std::string label = m.name.empty() ? "material" + std::to_string(i) : m.name;
      for (const auto& [slot, tex] : m.textures)
        if (slot != "base_color" && slot != "normal" && slot != "depth" && slot != "depth_back" &&
            slot != "normal_back" && slot.rfind("cone_", 0) != 0)
          return fail("material '" + label + "': texture slot '" + slot + "' has no glTF form");
      ojson gm = {{"name", m.name}};
      Result<ojson> pbr = pbr_json(m, label);
      if (!pbr.ok()) return pbr.status();
      gm["pbrMetallicRoughness"] = *pbr;
      if (m.double_sided) gm["doubleSided"] = true;
      if (m.alpha_mode == AlphaMode::kMask) {
        gm["alphaMode"] = "MASK";
        if (m.alpha_cutoff != 0.5f) gm["alphaCutoff"] = m.alpha_cutoff;
      } else if (m.alpha_mode == AlphaMode::kBlend) {
        gm["alphaMode"] = "BLEND";
      }
      ojson e = {{"technique", m.technique}};
      auto depth = m.textures.find("depth");
      auto normal = m.textures.find("normal");
      bool write_normal = normal != m.textures.end();
      if (depth != m.textures.end()) {
        Result<ojson> ti = texture_info(m, depth->second, label + "_depth");
        if (!ti.ok()) return ti.status();
        e["depth_texture"] = *ti;
        if (!write_normal && !m.normal_from_depth) e["normal_from_depth"] = false;
      }
      if (write_normal) {
        Result<ojson> ti =
            texture_info(m, normal->second, label + "_normal", slot_map(m, "normal"));
        if (!ti.ok()) return ti.status();
        gm["normalTexture"] = *ti;
        if (m.normal_scale != 1.0f) gm["normalTexture"]["scale"] = shortest(m.normal_scale);
      }
      // relief_dual's back layer (docs/scene-format.md, "depth_back_texture").
      for (const char* slot : {"depth_back", "normal_back"})
        if (auto it = m.textures.find(slot); it != m.textures.end()) {
          Result<ojson> ti = texture_info(m, it->second, label + "_" + slot, slot_map(m, slot));
          if (!ti.ok()) return ti.status();
          e[std::string(slot) + "_texture"] = *ti;
        }
      // emissive, occlusion, unlit (what read_material reads)
      if (m.emissive != glm::vec3(0.0f)) gm["emissiveFactor"] = vec_json(&m.emissive[0], 3);
      if (m.emissive_texture) {
        Result<ojson> ti = texture_info(m, m.emissive_texture, label + "_emissive", m.emissive_uv);
        if (!ti.ok()) return ti.status();
        gm["emissiveTexture"] = *ti;
      }
      if (m.emissive_strength != 1.0f) {
        gm["extensions"][kEmissiveStrength] = {{"emissiveStrength", shortest(m.emissive_strength)}};
        used_.insert(kEmissiveStrength);
      }
      if (m.occlusion_texture) {
        Result<ojson> ti =
            texture_info(m, m.occlusion_texture, label + "_occlusion", m.occlusion_uv);
        if (!ti.ok()) return ti.status();
        if (m.occlusion_strength != 1.0f) (*ti)["strength"] = shortest(m.occlusion_strength);
        gm["occlusionTexture"] = *ti;
      }
      if (m.unlit) {
        gm["extensions"][kUnlit] = ojson::object();
        used_.insert(kUnlit);
      }
      for (const auto& [slot, tex] : m.textures) {
        if (slot.rfind("cone_", 0) != 0) continue;
        if (e.contains("cone_texture"))
          return fail("material '" + label + "': more than one cone map has no glTF form");
        Result<ojson> ti = texture_info(m, tex, label + "_" + slot);
        if (!ti.ok()) return ti.status();
        e["cone_texture"] = *ti;
        e["cone_kind"] = slot.substr(5);
      }
      ojson params = ojson::object();
      for (const auto& [k, v] : m.params) {
        ojson value = shortest(v);
        if (std::floor(v) == v && std::abs(v) < 1e9f) value = static_cast<int64_t>(v);
        if (k == "depth_scale" || k == "steps" || k == "binary_steps")
          e[k] = value;
        else
          params[k] = value;
      }
      if (!params.empty()) e["params"] = params;
      e["self_shadow"] = m.self_shadow;
      e["depth_write"] = m.depth_write;
      e["silhouette"] = m.silhouette;
      e["casts_shadow"] = m.casts_shadow;
      e["receives_shadow"] = m.receives_shadow;
      if (m.shading == ShadingModel::kBlinnPhong) {
        e["shading"] = "blinn_phong";
        e["specular"] = shortest(m.specular);
        e["shininess"] = shortest(m.shininess);
      } else {
        e["shading"] = "metallic_roughness";
      }
      if (m.sampler.filter == Filter::kAnisotropic) e["max_anisotropy"] = m.sampler.max_aniso;
      if (m.height_ao.rays > 0)
        e["height_ao"] = {{"rays", m.height_ao.rays},
                          {"radius", shortest(m.height_ao.radius)},
                          {"strength", shortest(m.height_ao.strength)}};
      gm["extensions"][kReliefExtension] = e;
      doc_["materials"].push_back(gm);
    }
    return {};
  }

  // A primitive of `mesh` with `material`: its attributes and indices as accessors.
  ojson primitive_json(const Mesh& mesh, int material) {
    ojson attrs = {{"POSITION", add_accessor<3>(mesh.positions, true)}};
    if (mesh.normals.size() == mesh.positions.size())
      attrs["NORMAL"] = add_accessor<3>(mesh.normals, false);
    if (mesh.uvs.size() == mesh.positions.size())
      attrs["TEXCOORD_0"] = add_accessor<2>(mesh.uvs, false);
    if (mesh.uvs1.size() == mesh.positions.size())
      attrs["TEXCOORD_1"] = add_accessor<2>(mesh.uvs1, false);
    if (mesh.colors.size() == mesh.positions.size())
      attrs["COLOR_0"] = add_accessor<4>(mesh.colors, false);
    if (mesh.tangents.size() == mesh.positions.size()) {
      // the file's bitangent points to the image top (-v), ours along +v: w negated
      std::vector<glm::vec4> tangents = mesh.tangents;
      for (glm::vec4& t : tangents) t.w = -t.w;
      attrs["TANGENT"] = add_accessor<4>(tangents, false);
    }
    const size_t iv = add_view(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t), 34963);
    accessors_.push_back({{"bufferView", iv},
                          {"componentType", kUInt},
                          {"count", mesh.indices.size()},
                          {"type", "SCALAR"}});
    return {{"attributes", attrs}, {"indices", accessors_.size() - 1}, {"material", material}};
  }

  void write_meshes_and_nodes() {
    doc_["meshes"] = ojson::array();
    if (s_.animation) {
      write_animated_nodes();
      return;
    }
    std::map<std::pair<int, int>, size_t> gmesh;  // (mesh, material) -> glTF mesh
    for (const Instance& inst : s_.instances) {
      const auto key = std::make_pair(inst.mesh, inst.material);
      if (!gmesh.count(key)) {
        const Mesh& mesh = s_.meshes[inst.mesh];
        ojson prim = primitive_json(mesh, inst.material);
        doc_["meshes"].push_back({{"name", mesh.name}, {"primitives", ojson::array({prim})}});
        gmesh[key] = doc_["meshes"].size() - 1;
      }
      ojson node = {{"mesh", gmesh[key]}};
      if (inst.transform != glm::mat4(1.0f))
        node["matrix"] = vec_json(glm::value_ptr(inst.transform), 16);
      nodes_.push_back(node);
    }
  }

  // A float array as an accessor (animation keys, inverse bind matrices, morph deltas).
  size_t add_floats(const float* v, size_t count, const char* type, int width, bool bounds,
                    int target = 0) {
    const size_t view = add_view(v, count * width * sizeof(float), target);
    ojson a = {{"bufferView", view}, {"componentType", kFloat}, {"count", count}, {"type", type}};
    if (bounds && count > 0) {
      std::vector<float> lo(v, v + width), hi(v, v + width);
      for (size_t i = 0; i < count; ++i)
        for (int c = 0; c < width; ++c) {
          lo[c] = std::min(lo[c], v[i * width + c]);
          hi[c] = std::max(hi[c], v[i * width + c]);
        }
      a["min"] = vec_json(lo.data(), width);
      a["max"] = vec_json(hi.data(), width);
    }
    accessors_.push_back(a);
    return accessors_.size() - 1;
  }

  static ojson doubles_json(const double* v, int n) {
    ojson a = ojson::array();
    for (int i = 0; i < n; ++i) a.push_back(v[i]);
    return a;
  }

  // The node bound to entry `index` of `bindings` (an animated scene's instance, camera, light),
  // or -1.
  static int bound_node(const std::vector<NodeBinding>& bindings, int index) {
    for (const NodeBinding& b : bindings)
      if (b.index == index) return b.node;
    return -1;
  }

  // An animated scene (Scene::animation): its node hierarchy first (glTF node i = AnimNode i),
  // instances on the nodes they follow (a node's instances are one mesh's primitives; a deformed
  // one written from its rest mesh with JOINTS_0 / WEIGHTS_0 and its morph targets), then skins
  // and animations. Instances no node carries become root nodes, as for a static scene.
  void write_animated_nodes() {
    const SceneAnimation& a = *s_.animation;
    for (const AnimNode& n : a.nodes) {
      ojson node = ojson::object();
      if (!n.name.empty()) node["name"] = n.name;
      if (n.has_matrix) {
        node["matrix"] = doubles_json(glm::value_ptr(n.matrix), 16);
      } else {
        if (n.translation != glm::dvec3(0.0))
          node["translation"] = doubles_json(&n.translation[0], 3);
        if (n.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0))
          node["rotation"] = ojson::array({n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w});
        if (n.scale != glm::dvec3(1.0)) node["scale"] = doubles_json(&n.scale[0], 3);
      }
      nodes_.push_back(node);
    }
    for (size_t i = 0; i < a.nodes.size(); ++i)
      if (a.nodes[i].parent >= 0) nodes_[a.nodes[i].parent]["children"].push_back(i);
    write_node_meshes(a);
    for (size_t i = 0; i < s_.instances.size(); ++i) {
      if (bound_node(a.instances, static_cast<int>(i)) >= 0) continue;
      const Instance& inst = s_.instances[i];
      const Mesh& mesh = s_.meshes[inst.mesh];
      ojson prim = primitive_json(mesh, inst.material);
      doc_["meshes"].push_back({{"name", mesh.name}, {"primitives", ojson::array({prim})}});
      ojson node = {{"mesh", doc_["meshes"].size() - 1}};
      if (inst.transform != glm::mat4(1.0f))
        node["matrix"] = vec_json(glm::value_ptr(inst.transform), 16);
      nodes_.push_back(node);
    }
    for (const Skin& sk : a.skins) {
      ojson js = ojson::array();
      for (int j : sk.joints) js.push_back(j);
      std::vector<float> ibm;
      for (const glm::dmat4& m : sk.inverse_bind)
        for (int k = 0; k < 16; ++k) ibm.push_back(static_cast<float>(glm::value_ptr(m)[k]));
      doc_["skins"].push_back(
          {{"joints", js},
           {"inverseBindMatrices", add_floats(ibm.data(), sk.joints.size(), "MAT4", 16, false)}});
    }
    write_animations(a);
  }

  // The meshes on the nodes instances follow: a node's instances are one
  // mesh's primitives; a deformed one is written from its rest mesh with JOINTS_0 / WEIGHTS_0
  // and its morph targets.
  void write_node_meshes(const SceneAnimation& a) {
    // Instances by node, in instance order.
    std::map<int, std::vector<int>> on_node;
    for (size_t i = 0; i < s_.instances.size(); ++i) {
      const int node = bound_node(a.instances, static_cast<int>(i));
      if (node >= 0 && node < static_cast<int>(a.nodes.size()))
        on_node[node].push_back(static_cast<int>(i));
    }
    for (const auto& [node, insts] : on_node) {
      ojson prims = ojson::array();
      int skin = -1;
      size_t targets = 0;
      for (int i : insts) {
        const Instance& inst = s_.instances[i];
        const Deformer* d = nullptr;
        for (const Deformer& x : a.deformers)
          if (x.mesh == inst.mesh && x.node == node) d = &x;
        ojson prim = primitive_json(d ? d->rest : s_.meshes[inst.mesh], inst.material);
        if (d && d->skin >= 0) {
          skin = d->skin;
          // A joint of weight 0 is written as 0 (glTF: unused influences name joint 0).
          std::vector<glm::u16vec4> joints = d->joints;
          for (size_t v = 0; v < joints.size() && v < d->weights.size(); ++v)
            for (int k = 0; k < 4; ++k)
              if (d->weights[v][k] == 0.0f) joints[v][k] = 0;
          const size_t jv = add_view(joints.data(), joints.size() * sizeof(joints[0]), 34962);
          accessors_.push_back({{"bufferView", jv},
                                {"componentType", kUShort},
                                {"count", d->joints.size()},
                                {"type", "VEC4"}});
          prim["attributes"]["JOINTS_0"] = accessors_.size() - 1;
          prim["attributes"]["WEIGHTS_0"] =
              add_floats(&d->weights[0][0], d->weights.size(), "VEC4", 4, false, 34962);
        }
        if (d && !d->targets.empty()) {
          ojson ts = ojson::array();
          for (const MorphTarget& t : d->targets) {
            ojson tj = ojson::object();
            if (!t.positions.empty())
              tj["POSITION"] =
                  add_floats(&t.positions[0][0], t.positions.size(), "VEC3", 3, true, 34962);
            if (!t.normals.empty())
              tj["NORMAL"] =
                  add_floats(&t.normals[0][0], t.normals.size(), "VEC3", 3, false, 34962);
            if (!t.tangents.empty())
              tj["TANGENT"] =
                  add_floats(&t.tangents[0][0], t.tangents.size(), "VEC3", 3, false, 34962);
            ts.push_back(tj);
          }
          prim["targets"] = ts;
          targets = d->targets.size();
        }
        prims.push_back(prim);
      }
      ojson mesh = {{"primitives", prims}};
      if (!a.nodes[node].name.empty()) mesh["name"] = a.nodes[node].name;
      // Morph weights: the node's (load_gltf keeps the node's, else the mesh's, per node).
      if (targets > 0 && a.nodes[node].weights.size() == targets) {
        ojson w = ojson::array();
        for (float x : a.nodes[node].weights) w.push_back(shortest(x));
        nodes_[node]["weights"] = w;
      }
      doc_["meshes"].push_back(mesh);
      nodes_[node]["mesh"] = doc_["meshes"].size() - 1;
      if (skin >= 0) nodes_[node]["skin"] = skin;
    }
  }

  // The animation clips: each sampler's key times and values as accessors, each channel's target.
  void write_animations(const SceneAnimation& a) {
    for (const AnimationClip& clip : a.clips) {
      ojson samplers = ojson::array(), channels = ojson::array();
      std::map<int, AnimPath> path_of;  // sampler -> the path its channels animate
      for (const AnimationChannel& c : clip.channels) path_of[c.sampler] = c.path;
      for (size_t si = 0; si < clip.samplers.size(); ++si) {
        const AnimationSampler& smp = clip.samplers[si];
        const size_t input = add_floats(smp.times.data(), smp.times.size(), "SCALAR", 1, true);
        const AnimPath path = path_of.count(static_cast<int>(si)) ? path_of[static_cast<int>(si)]
                                                                  : AnimPath::kWeights;
        const int width = path == AnimPath::kWeights ? 1 : path == AnimPath::kRotation ? 4 : 3;
        const char* type = width == 1 ? "SCALAR" : width == 4 ? "VEC4" : "VEC3";
        const size_t output =
            add_floats(smp.values.data(), smp.values.size() / width, type, width, false);
        samplers.push_back(
            {{"input", input},
             {"output", output},
             {"interpolation", smp.interpolation == Interpolation::kStep     ? "STEP"
                               : smp.interpolation == Interpolation::kLinear ? "LINEAR"
                                                                             : "CUBICSPLINE"}});
      }
      for (const AnimationChannel& c : clip.channels) {
        const char* path = c.path == AnimPath::kTranslation ? "translation"
                           : c.path == AnimPath::kRotation  ? "rotation"
                           : c.path == AnimPath::kScale     ? "scale"
                                                            : "weights";
        channels.push_back(
            {{"sampler", c.sampler}, {"target", {{"node", c.node}, {"path", path}}}});
      }
      ojson anim = ojson::object();
      if (!clip.name.empty()) anim["name"] = clip.name;
      anim["samplers"] = samplers;
      anim["channels"] = channels;
      doc_["animations"].push_back(anim);
    }
  }

  void write_cameras() {
    for (size_t ci = 0; ci < s_.cameras.size(); ++ci) {
      const Camera& c = s_.cameras[ci];
      ojson gc = {{"name", c.name}};
      if (c.orthographic) {
        gc["type"] = "orthographic";
        gc["orthographic"] = {{"xmag", shortest(c.ortho_half_height)},
                              {"ymag", shortest(c.ortho_half_height)},
                              {"znear", shortest(c.znear)},
                              {"zfar", shortest(c.zfar)}};
      } else {
        gc["type"] = "perspective";
        gc["perspective"] = {{"yfov", double(c.yfov_deg) * kPi / 180.0},
                             {"znear", shortest(c.znear)},
                             {"zfar", shortest(c.zfar)}};
      }
      doc_["cameras"].push_back(gc);
      // The camera-to-world rotation of lookAt(position, target, up), in double precision.
      const glm::dvec3 pos(c.position);
      const glm::dvec3 f = glm::normalize(glm::dvec3(c.target) - pos);
      const glm::dvec3 side = glm::normalize(glm::cross(f, glm::dvec3(c.up)));
      const glm::dvec3 up = glm::cross(side, f);
      const glm::dquat q = glm::normalize(glm::quat_cast(glm::dmat3(side, up, -f)));
      // A camera an animation moves stays on its node (which holds its transform).
      const int bound = s_.animation ? bound_node(s_.animation->cameras, static_cast<int>(ci)) : -1;
      if (bound >= 0 && bound < static_cast<int>(nodes_.size()) &&
          !nodes_[bound].contains("camera")) {
        nodes_[bound]["camera"] = doc_["cameras"].size() - 1;
        continue;
      }
      // target and up exactly (the rotation alone gives them to rounding): load_gltf keeps them.
      const ojson hint = {{"target", vec_json(&c.target[0], 3)}, {"up", vec_json(&c.up[0], 3)}};
      nodes_.push_back({{"name", c.name},
                        {"camera", doc_["cameras"].size() - 1},
                        {"translation", vec_json(&c.position[0], 3)},
                        {"rotation", quat_json(q)},
                        {"extensions", {{kReliefExtension, hint}}}});
    }
  }

  void write_lights() {
    for (size_t li = 0; li < s_.lights.size(); ++li) {
      const Light& l = s_.lights[li];
      // glTF colours lie in [0, 1]: a brighter colour moves its scale into the intensity.
      const float peak = std::max({l.color.r, l.color.g, l.color.b});
      const glm::vec3 color = peak > 1.0f ? l.color / peak : l.color;
      const float intensity = peak > 1.0f ? l.intensity * peak : l.intensity;
      ojson gl = {{"name", l.name},
                  {"type", l.type == LightType::kDirectional ? "directional"
                           : l.type == LightType::kPoint     ? "point"
                                                             : "spot"},
                  {"color", vec_json(&color[0], 3)},
                  {"intensity", shortest(intensity)}};
      if (l.range > 0.0f) gl["range"] = shortest(l.range);
      if (l.type == LightType::kSpot)
        gl["spot"] = {{"innerConeAngle", double(l.inner_cone_deg) * kPi / 180.0},
                      {"outerConeAngle", double(l.outer_cone_deg) * kPi / 180.0}};
      gl["extensions"][kReliefExtension] = {{"casts_shadows", l.casts_shadows},
                                            {"shadow_resolution", l.shadow_resolution}};
      // The direction's float bits (the node's rotation rounds them) and, when the colour was
      // rescaled into [0, 1], the colour and intensity as they were: load_gltf keeps them.
      if (l.type != LightType::kPoint)
        gl["extensions"][kReliefExtension]["direction"] = vec_json(&l.direction[0], 3);
      if (peak > 1.0f) {
        gl["extensions"][kReliefExtension]["color"] = vec_json(&l.color[0], 3);
        gl["extensions"][kReliefExtension]["intensity"] = shortest(l.intensity);
      }
      lights_json_.push_back(gl);
      used_.insert(kLightsPunctual);
      const int bound = s_.animation ? bound_node(s_.animation->lights, static_cast<int>(li)) : -1;
      if (bound >= 0 && bound < static_cast<int>(nodes_.size()) &&
          !nodes_[bound].contains("extensions")) {
        nodes_[bound]["extensions"][kLightsPunctual] = {{"light", lights_json_.size() - 1}};
        continue;
      }
      ojson node = {{"name", l.name}};
      if (l.type != LightType::kDirectional) node["translation"] = vec_json(&l.position[0], 3);
      if (l.type != LightType::kPoint)
        node["rotation"] = quat_json(rotation_to(glm::dvec3(l.direction)));
      node["extensions"][kLightsPunctual] = {{"light", lights_json_.size() - 1}};
      nodes_.push_back(node);
      used_.insert(kLightsPunctual);
    }
  }

  const Scene& s_;
  std::string path_;
  bool glb_ = false;
  fs::path dir_;
  std::string stem_;
  ojson doc_ = ojson::object();
  ojson nodes_ = ojson::array();
  ojson views_ = ojson::array();
  ojson accessors_ = ojson::array();
  ojson lights_json_ = ojson::array();
  std::vector<uint8_t> bin_;
  std::set<std::string> used_;
  std::map<const Texture*, int> images_;
  std::map<const Texture*, size_t> raw_views_;  // float texels' buffer views
  std::map<int, int> samplers_;
  std::set<std::string> file_names_;  // PNG names given out
  StagedFiles staged_;                // the .bin, PNGs and .gltf/.glb, renamed at the end
};

}  // namespace

Status save_gltf(const Scene& scene, const std::string& path) {
  if (!has_suffix(path, ".gltf") && !has_suffix(path, ".glb"))
    return Status::usage(printable(path) + ": expected a .gltf or .glb file name");
  Writer w(scene, path);
  return w.write();
}

}  // namespace relief
