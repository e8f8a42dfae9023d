// glTF input, materials (scene/gltf_internal.h): glTF 2.0 specification section 3.9
// (pbrMetallicRoughness base colour, normal, emissive and occlusion textures, alpha modes),
// KHR_materials_emissive_strength, KHR_materials_unlit and the RELIEF_relief_mapping material
// extension (technique, relief textures and parameters; docs/scene-format.md,
// docs/relief_mapping.schema.json), checked against the plugin registry.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include <glm/matrix.hpp>

#include "bake/normal_map.h"
#include "plugins/registry.h"
#include "scene/gltf.h"
#include "scene/gltf_internal.h"
#include "scene/gltf_validate.h"

namespace relief::gltf_detail {

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

namespace {

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

}  // namespace

// A material: its core properties, KHR_materials_emissive_strength and KHR_materials_unlit,
// RELIEF_relief_mapping (technique, relief textures, parameters), then every texture it reads.
Result<Reader::MaterialInfo> Reader::read_material(int index) {
  const tinygltf::Material& gm = m_.materials[index];
  const std::string mp = "/materials/" + std::to_string(index);
  MaterialInfo info;
  Material& mat = info.material;
  mat.name = gm.name.empty() ? "material" + std::to_string(index) : gm.name;
  std::vector<TextureSlot> slots;
  RELIEF_RETURN_IF_ERROR(read_core_material(gm, mp, mat, slots));
  RELIEF_RETURN_IF_ERROR(read_khr_material_extensions(gm, mp, mat));

  Result<json> ext = extension(gm.extensions_json_string, kReliefExtension, mp);
  if (!ext.ok()) return ext.status();
  const std::string ep = mp + "/extensions/" + kReliefExtension;
  bool normal_from_depth = true;
  int max_aniso = 0;
  if (ext->is_null()) {
    mat.technique = gm.normalTexture.index >= 0 ? "normal" : "flat";
  } else {
    RELIEF_RETURN_IF_ERROR(
        read_relief_material(*ext, ep, mat, slots, normal_from_depth, max_aniso));
  }

  RELIEF_RETURN_IF_ERROR(load_material_textures(slots, info));
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
  RELIEF_RETURN_IF_ERROR(check_required_textures(mat, ext->is_null() ? mp : ep));
  return info;
}

// The core material: doubleSided, alpha, base colour, normal, emissive and occlusion (their
// factors, and their textures as slots).
Status Reader::read_core_material(const tinygltf::Material& gm, const std::string& mp,
                                  Material& mat, std::vector<TextureSlot>& slots) const {
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
  // Emissive and occlusion (plugins/surface.h finish_surface; unlit: read_khr_material_extensions).
  if (gm.emissiveFactor.size() == 3) {
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(gm.emissiveFactor[i]) || gm.emissiveFactor[i] < 0.0 ||
          gm.emissiveFactor[i] > 1.0)
        return fail(mp + "/emissiveFactor/" + std::to_string(i), "expected a number in [0, 1]");
      mat.emissive[i] = static_cast<float>(gm.emissiveFactor[i]);
    }
  }
  if (gm.emissiveTexture.index >= 0) {
    Result<TexRef> r = tex_ref(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
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
  return {};
}

// KHR_materials_emissive_strength and KHR_materials_unlit.
Status Reader::read_khr_material_extensions(const tinygltf::Material& gm, const std::string& mp,
                                            Material& mat) const {
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
  return {};
}

// The material's RELIEF_relief_mapping object `e` (at `ep`): technique, flags, Blinn-Phong terms,
// relief textures and plugin parameters.
Status Reader::read_relief_material(const json& e, const std::string& ep, Material& mat,
                                    std::vector<TextureSlot>& slots, bool& normal_from_depth,
                                    int& max_aniso) const {
  RELIEF_RETURN_IF_ERROR(check_keys(
      e, ep, {"technique",      "depth_texture",   "depth_is_height",    "normal_from_depth",
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
  RELIEF_RETURN_IF_ERROR(read_relief_textures(e, ep, depth_is_height, mat.technique, slots));
  return read_relief_params(e, ep, mat);
}

// The relief textures of RELIEF_relief_mapping `e` as slots: depth, relief_dual's back layer,
// the cone map.
Status Reader::read_relief_textures(const json& e, const std::string& ep, bool depth_is_height,
                                    const std::string& technique,
                                    std::vector<TextureSlot>& slots) const {
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
        return fail(ep + "/cone_kind", "expected conservative, quad or relaxed, got " + k.dump());
      kind = k.get<std::string>();
    } else if (const PluginDescriptor* p = PluginRegistry::global().find(technique)) {
      for (int i = 0; i < p->num_textures && kind.empty(); ++i)
        if (std::string(p->textures[i].name).rfind("cone_", 0) == 0) kind = p->textures[i].name + 5;
    }
    if (kind.empty())
      return fail(ep + "/cone_texture",
                  "technique " + technique + " reads no cone map: give cone_kind");
    slots.push_back({"cone_" + kind, *r, TexUse::kCone});
  }
  return {};
}

// Plugin parameters: the three common ones at the top level, any other in "params".
Status Reader::read_relief_params(const json& e, const std::string& ep, Material& mat) const {
  std::map<std::string, std::string> param_pointer;  // parameter -> JSON pointer
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
        return fail(p, std::string("expected a number, a boolean or a choice name, got ") + got);
      }
      const PluginDescriptor* by = declaring_plugin(mat.technique, it.key());
      if (!by) return fail(p, "no technique has a parameter '" + it.key() + "'");
      Result<float> v = resolve_param_value(*by, it.key(), pv);
      if (!v.ok()) return fail(p, v.status().message());
      mat.params[it.key()] = *v;
      param_pointer[it.key()] = p;
    }
  }
  return check_params(mat, param_pointer);
}

// Textures: one sampler per material; a texture transform per texture. The uv varying is
// the main texture's transformed TEXCOORD_0 (the depth map's, else the base colour's, else
// the first's); every other texture maps from it (relative_uv_map).
Status Reader::load_material_textures(const std::vector<TextureSlot>& slots, MaterialInfo& info) {
  Material& mat = info.material;
  std::vector<UvTransform> transforms;
  for (const TextureSlot& s : slots) {
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
    const TextureSlot& s = slots[i];
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
  return {};
}

// Texture slots the technique requires; an error at `pointer` names the first one missing.
Status Reader::check_required_textures(const Material& mat, const std::string& pointer) const {
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
    return fail(pointer,
                "technique " + mat.technique + " needs a '" + name + "' texture (" + where + ")");
  }
  return {};
}

// Each parameter is checked by the material's technique when it declares it, otherwise by a
// technique that does (parameters of other techniques apply when --technique switches).
const PluginDescriptor* Reader::declaring_plugin(const std::string& technique,
                                                 const std::string& name) {
  const PluginRegistry& reg = PluginRegistry::global();
  if (const PluginDescriptor* own = reg.find(technique);
      own && param_index(*own, name.c_str()) >= 0)
    return own;
  for (const PluginDescriptor* p : reg.all())
    if (param_index(*p, name.c_str()) >= 0) return p;
  return nullptr;
}

Status Reader::check_params(const Material& mat,
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

}  // namespace relief::gltf_detail
