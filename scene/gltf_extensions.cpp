// The extension table and the scan for what relief ignores (see gltf_extensions.h).
#include "scene/gltf_extensions.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "scene/gltf_validate.h"

namespace relief {
namespace {

using json = nlohmann::json;
using S = ExtensionStatus;

// Ratified KHR extensions (KhronosGroup/glTF extensions/README.md, "Ratified Khronos Extensions",
// plus those ratified since: anisotropy, dispersion, diffuse_transmission, animation_pointer),
// the archived ones files still carry, the multi-vendor EXT ones relief reads, and ours.
constexpr ExtensionInfo kTable[] = {
    {"RELIEF_relief_mapping", S::kSupported, "relief's own: techniques, relief maps, effects"},
    {"KHR_lights_punctual", S::kSupported, "point, spot, directional lights"},
    {"KHR_texture_transform", S::kSupported, "offset, rotation, scale, texCoord, per texture"},
    {"KHR_mesh_quantization", S::kSupported, "quantized attributes"},
    {"KHR_draco_mesh_compression", S::kSupported, "decoded with libdraco"},
    {"EXT_meshopt_compression", S::kSupported, "decoded with meshoptimizer"},
    {"EXT_texture_webp", S::kSupported, "WebP images through OpenImageIO"},
    {"KHR_materials_emissive_strength", S::kSupported, "scales emissiveFactor"},
    {"KHR_materials_unlit", S::kSupported, "base colour only, no lighting"},
    {"KHR_materials_clearcoat", S::kIgnored, "no clear coat layer"},
    {"KHR_materials_ior", S::kIgnored, "the core BRDF's IOR 1.5 (f0 0.04)"},
    {"KHR_materials_iridescence", S::kIgnored, "no thin-film iridescence"},
    {"KHR_materials_sheen", S::kIgnored, "no sheen layer"},
    {"KHR_materials_specular", S::kIgnored, "specular is RELIEF_relief_mapping's"},
    {"KHR_materials_transmission", S::kIgnored, "drawn opaque (no transmission)"},
    {"KHR_materials_volume", S::kIgnored, "no volume attenuation"},
    {"KHR_materials_anisotropy", S::kIgnored, "isotropic highlights"},
    {"KHR_materials_dispersion", S::kIgnored, "no dispersion"},
    {"KHR_materials_diffuse_transmission", S::kIgnored, "no diffuse transmission"},
    {"KHR_materials_variants", S::kIgnored, "the default material of each primitive"},
    {"KHR_materials_pbrSpecularGlossiness", S::kIgnored, "archived: the core material is used"},
    {"KHR_texture_basisu", S::kIgnored, "KTX2 not decoded: the texture's fallback source is used"},
    {"KHR_animation_pointer", S::kIgnored, "only node TRS and weights channels are animated"},
    {"KHR_xmp_json_ld", S::kIgnored, "metadata not read"},
    {"KHR_xmp", S::kIgnored, "archived metadata, not read"},
    {"KHR_techniques_webgl", S::kIgnored, "archived shaders, not run"},
    {"EXT_mesh_gpu_instancing", S::kIgnored, "each mesh drawn once, at its node"},
    {"EXT_lights_image_based", S::kIgnored, "no image-based lights from files"},
};

int material_of(const std::string& pointer) {
  static const char kPrefix[] = "/materials/";
  if (pointer.rfind(kPrefix, 0) != 0) return -1;
  return std::atoi(pointer.c_str() + sizeof kPrefix - 1);
}

struct Scan {
  // extension -> (first pointer, materials)
  struct Use {
    std::string pointer;
    std::set<int> materials;
  };
  std::map<std::string, Use> extensions;

  void walk(const json& j, const std::string& p, int depth) {
    if (depth > kMaxJsonNesting) return;
    if (j.is_array()) {
      for (size_t i = 0; i < j.size(); ++i) walk(j[i], p + "/" + std::to_string(i), depth + 1);
      return;
    }
    if (!j.is_object()) return;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "extras") continue;  // application data, not glTF's
      const std::string q = p + "/" + pointer_token(it.key());
      if (it.key() == "extensions" && it->is_object()) {
        for (auto e = it->begin(); e != it->end(); ++e) {
          const std::string ep = q + "/" + pointer_token(e.key());
          if (!gltf_extension_supported(e.key())) {
            auto [u, fresh] = extensions.try_emplace(e.key(), Use{ep, {}});
            // The first use on a material wins (so --explain and the line agree), else the first.
            if (!fresh && material_of(u->second.pointer) < 0 && material_of(ep) >= 0)
              u->second.pointer = ep;
            if (const int m = material_of(ep); m >= 0) u->second.materials.insert(m);
          }
          walk(*e, ep, depth + 2);
        }
        continue;
      }
      walk(*it, q, depth + 1);
    }
  }
};

std::string list_of(const std::set<int>& s) {
  std::string out;
  for (int i : s) out += (out.empty() ? "" : ", ") + std::to_string(i);
  return out;
}

const char* filter_name(int f) {
  switch (f) {
    case 9728:
      return "NEAREST";
    case 9729:
      return "LINEAR";
    case 9984:
      return "NEAREST_MIPMAP_NEAREST";
    case 9985:
      return "LINEAR_MIPMAP_NEAREST";
    case 9986:
      return "NEAREST_MIPMAP_LINEAR";
    case 9987:
      return "LINEAR_MIPMAP_LINEAR";
    default:
      return "?";
  }
}

int int_at(const json& o, const char* key, int missing) {
  auto it = o.find(key);
  return it != o.end() && it->is_number_integer() ? it->get<int>() : missing;
}

// Every textureInfo a material holds (core and our extension): its texture indices.
void material_textures(const json& m, std::set<int>& out) {
  auto add = [&](const json* t) {
    if (t && t->is_object()) {
      const int i = int_at(*t, "index", -1);
      if (i >= 0) out.insert(i);
    }
  };
  auto get = [](const json& o, const char* k) -> const json* {
    auto it = o.find(k);
    return it == o.end() ? nullptr : &*it;
  };
  if (const json* pbr = get(m, "pbrMetallicRoughness"); pbr && pbr->is_object()) {
    add(get(*pbr, "baseColorTexture"));
    add(get(*pbr, "metallicRoughnessTexture"));
  }
  for (const char* k : {"normalTexture", "occlusionTexture", "emissiveTexture"}) add(get(m, k));
  if (const json* ex = get(m, "extensions"); ex && ex->is_object())
    if (const json* r = get(*ex, "RELIEF_relief_mapping"); r && r->is_object())
      for (const char* k :
           {"depth_texture", "depth_back_texture", "cone_texture", "normal_back_texture"})
        add(get(*r, k));
}

}  // namespace

std::span<const ExtensionInfo> gltf_extensions() {
  return kTable;
}

const ExtensionInfo* find_gltf_extension(std::string_view name) {
  for (const ExtensionInfo& e : kTable)
    if (name == e.name) return &e;
  return nullptr;
}

bool gltf_extension_supported(std::string_view name) {
  const ExtensionInfo* e = find_gltf_extension(name);
  return e && e->status == ExtensionStatus::kSupported;
}

const char* extension_status_text(ExtensionStatus s) {
  switch (s) {
    case ExtensionStatus::kSupported:
      return "supported";
    case ExtensionStatus::kIgnored:
      return "ignored with a warning";
    case ExtensionStatus::kRefused:
      return "refused";
  }
  return "?";
}

namespace {

// Extensions relief does not support, used (found by the scan) or listed in extensionsUsed: one
// finding each, naming its materials, and one per other material for --explain.
void unsupported_extensions(const json& doc, std::vector<GltfIgnored>& out) {
  Scan scan;
  scan.walk(doc, "", 0);
  if (auto used = doc.find("extensionsUsed"); used != doc.end() && used->is_array())
    for (size_t i = 0; i < used->size(); ++i) {
      const json& x = (*used)[i];
      if (x.is_string() && !gltf_extension_supported(x.get<std::string>()))
        scan.extensions.try_emplace(x.get<std::string>(),
                                    Scan::Use{"/extensionsUsed/" + std::to_string(i), {}});
    }
  for (const auto& [name, use] : scan.extensions) {
    const ExtensionInfo* info = find_gltf_extension(name);
    GltfIgnored g;
    g.pointer = use.pointer;
    g.feature = name;
    g.refused = info && info->status == ExtensionStatus::kRefused;
    g.what = "extension " + name + " is not supported" + (g.refused ? "" : ", ignored");
    std::string detail = info ? info->note : "";
    if (use.materials.size() > 1 || (use.materials.size() == 1 && material_of(use.pointer) < 0))
      detail += std::string(detail.empty() ? "" : "; ") + "materials " + list_of(use.materials);
    if (!detail.empty()) g.what += " (" + detail + ")";
    g.material = material_of(use.pointer);
    out.push_back(g);
    // The other materials carrying it, for --explain (the line above names them).
    for (int m : use.materials) {
      if (m == g.material) continue;
      GltfIgnored also = g;
      also.material = m;
      also.pointer = "/materials/" + std::to_string(m) + "/extensions/" + pointer_token(name);
      also.warn = false;
      out.push_back(std::move(also));
    }
  }
}

}  // namespace

bool relief_extension_is_blinn_phong(const nlohmann::json& ext) {
  if (!ext.is_object()) return false;
  if (auto s = ext.find("shading"); s != ext.end()) return *s == "blinn_phong";
  return ext.contains("specular") || ext.contains("shininess");
}

namespace {

// Core material properties a Blinn-Phong material does not shade with (metallic-roughness).
// `sampler_users` gets the materials each sampler's textures serve.
void ignored_material_properties(const json& doc, std::map<int, std::set<int>>& sampler_users,
                                 std::vector<GltfIgnored>& out) {
  const json* materials = nullptr;
  if (auto it = doc.find("materials"); it != doc.end() && it->is_array()) materials = &*it;
  const json* textures = nullptr;
  if (auto it = doc.find("textures"); it != doc.end() && it->is_array()) textures = &*it;
  for (size_t mi = 0; materials && mi < materials->size(); ++mi) {
    const json& m = (*materials)[mi];
    if (!m.is_object()) continue;
    const std::string mp = "/materials/" + std::to_string(mi);
    std::vector<std::string> props;
    // Only a material RELIEF_relief_mapping lights with Blinn-Phong ignores them ("shading":
    // "blinn_phong", or specular or shininess and no "shading": gltf_read_materials.cpp).
    bool blinn_phong = false;
    if (auto ex = m.find("extensions"); ex != m.end() && ex->is_object())
      if (auto r = ex->find("RELIEF_relief_mapping"); r != ex->end() && r->is_object())
        blinn_phong = relief_extension_is_blinn_phong(*r);
    if (auto pbr = m.find("pbrMetallicRoughness");
        blinn_phong && pbr != m.end() && pbr->is_object()) {
      if (pbr->contains("metallicRoughnessTexture")) props.push_back("metallicRoughnessTexture");
      // Our export writes metallicFactor 0 with the extension's Blinn-Phong terms.
      if (auto f = pbr->find("metallicFactor");
          f != pbr->end() && !(f->is_number() && f->get<double>() == 0.0))
        props.push_back("metallicFactor");
      if (pbr->contains("roughnessFactor")) props.push_back("roughnessFactor");
    }
    if (!props.empty()) {
      GltfIgnored g;
      g.pointer = mp + "/pbrMetallicRoughness";
      g.material = static_cast<int>(mi);
      std::string names;
      for (const std::string& p : props) names += (names.empty() ? "" : ", ") + p;
      g.feature = names;
      g.what = names +
               " ignored (RELIEF_relief_mapping lights this material with Blinn-Phong: "
               "specular, shininess)";
      out.push_back(std::move(g));
    }
    std::set<int> texs;
    material_textures(m, texs);
    for (int t : texs)
      if (textures && t < static_cast<int>(textures->size()) && (*textures)[t].is_object()) {
        const int s = int_at((*textures)[t], "sampler", -1);
        if (s >= 0) sampler_users[s].insert(static_cast<int>(mi));
      }
  }
}

// Sampler settings relief cannot honour: one filter for minification and magnification.
void ignored_sampler_settings(const json& doc, const std::map<int, std::set<int>>& sampler_users,
                              std::vector<GltfIgnored>& out) {
  const json* samplers = nullptr;
  if (auto it = doc.find("samplers"); it != doc.end() && it->is_array()) samplers = &*it;
  for (const auto& [si, users] : sampler_users) {
    if (!samplers || si >= static_cast<int>(samplers->size()) || !(*samplers)[si].is_object())
      continue;
    const json& s = (*samplers)[si];
    const int min = int_at(s, "minFilter", -1), mag = int_at(s, "magFilter", -1);
    const bool nearest = min == 9728 || min == 9984 || (min == -1 && mag == 9728);
    std::vector<std::pair<std::string, std::string>> found;  // (property, why)
    if (min == 9986)
      found.push_back({"minFilter", "NEAREST_MIPMAP_LINEAR drawn as LINEAR_MIPMAP_LINEAR"});
    if (mag != -1 && (mag == 9728) != nearest)
      found.push_back({"magFilter", std::string(filter_name(mag)) + " ignored: magnification " +
                                        (nearest ? "is NEAREST" : "is LINEAR") +
                                        " with minFilter " +
                                        (min == -1 ? "absent" : filter_name(min))});
    for (const auto& [prop, why] : found)
      for (int m : users) {
        GltfIgnored g;
        g.pointer = "/samplers/" + std::to_string(si) + "/" + prop;
        g.feature = prop;
        g.material = m;
        g.what = why + " (materials " + list_of(users) + ")";
        g.warn = m == *users.begin();
        out.push_back(std::move(g));
      }
  }
}

// Primitive attribute sets relief does not read (custom "_NAME" attributes are the
// application's, ignored silently as glTF says).
void ignored_attribute_sets(const json& doc, std::vector<GltfIgnored>& out) {
  std::map<std::string, std::string> attrs;  // name -> first pointer
  if (auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array())
    for (size_t mi = 0; mi < meshes->size(); ++mi) {
      const json& mesh = (*meshes)[mi];
      auto prims = mesh.is_object() ? mesh.find("primitives") : mesh.end();
      if (!mesh.is_object() || prims == mesh.end() || !prims->is_array()) continue;
      for (size_t pi = 0; pi < prims->size(); ++pi) {
        const json& p = (*prims)[pi];
        auto a = p.is_object() ? p.find("attributes") : p.end();
        if (!p.is_object() || a == p.end() || !a->is_object()) continue;
        for (auto it = a->begin(); it != a->end(); ++it) {
          const std::string& n = it.key();
          auto set_index = [&](const char* prefix) {
            const size_t l = std::strlen(prefix);
            if (n.size() <= l || n.compare(0, l, prefix) != 0) return -1;
            if (n.find_first_not_of("0123456789", l) != std::string::npos) return -1;
            return std::atoi(n.c_str() + l);
          };
          if (set_index("TEXCOORD_") >= 2 || set_index("COLOR_") >= 1)
            attrs.try_emplace(n, "/meshes/" + std::to_string(mi) + "/primitives/" +
                                     std::to_string(pi) + "/attributes/" + pointer_token(n));
        }
      }
    }
  for (const auto& [name, p] : attrs) {
    GltfIgnored g;
    g.pointer = p;
    g.feature = name;
    g.what = "attribute " + name + " ignored (relief reads TEXCOORD_0, TEXCOORD_1 and COLOR_0)";
    out.push_back(std::move(g));
  }
}

}  // namespace

std::vector<GltfIgnored> find_ignored_features(const json& doc) {
  std::vector<GltfIgnored> out;
  if (!doc.is_object()) return out;
  unsupported_extensions(doc, out);
  std::map<int, std::set<int>> sampler_users;  // sampler -> materials
  ignored_material_properties(doc, sampler_users, out);
  ignored_sampler_settings(doc, sampler_users, out);
  ignored_attribute_sets(doc, out);
  return out;
}

std::string ignored_line(const std::string& path, const GltfIgnored& g) {
  return one_line_text(path, 200) + ": " + one_line_text(g.pointer, 100) + ": " +
         one_line_text(g.what, 200);
}

}  // namespace relief
