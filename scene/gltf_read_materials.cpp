// glTF input, materials (scene/gltf_internal.h): glTF 2.0 specification section 3.9
// (pbrMetallicRoughness base colour, normal, emissive and occlusion textures, alpha modes),
// KHR_materials_emissive_strength, KHR_materials_unlit and the RELIEF_relief_mapping material
// extension (technique, relief textures and parameters; docs/scene-format.md,
// docs/relief_mapping.schema.json). What only the plugin registry can check (the technique, the
// parameters' types, a cone map's kind, the required textures) is recorded in Material::source
// with its JSON pointers for render/validate.h; scene/ knows no technique.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include <glm/matrix.hpp>

#include "scene/gltf.h"
#include "scene/gltf_internal.h"
#include "scene/gltf_validate.h"

namespace relief::gltf_detail {

namespace {

// The UvMap (shaders_cpp/uniforms.h) from the uv varying (the main texture's transformed
// TEXCOORD_0) to the coordinates of a texture with transform t: t composed with the inverse of
// `main` on TEXCOORD_0, t itself on TEXCOORD_1.
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
  mat.source.file = path_;
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
  // A cone map whose kind the technique decides waits in the source (render/validate.h).
  if (auto cone = mat.textures.find(kConeOfTechnique); cone != mat.textures.end()) {
    mat.source.cone_texture = cone->second;
    mat.textures.erase(cone);
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
  // The normal map a relief material needs comes from its depth map when none is given
  // (render/derived_maps.h, when a technique reads it).
  mat.normal_from_depth = normal_from_depth;
  mat.source.slots_pointer = ext->is_null() ? mp : ep;
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
  // metallic-roughness (plugins/surface.h sample_surface); RELIEF_relief_mapping may ask for
  // Blinn-Phong instead (read_relief_material)
  mat.shading = ShadingModel::kMetallicRoughness;
  const std::string pbr = mp + "/pbrMetallicRoughness";
  const double metallic = gm.pbrMetallicRoughness.metallicFactor;
  const double roughness = gm.pbrMetallicRoughness.roughnessFactor;
  if (!std::isfinite(metallic) || metallic < 0.0 || metallic > 1.0)
    return fail(pbr + "/metallicFactor", "expected a number in [0, 1], got " + fmt(metallic));
  if (!std::isfinite(roughness) || roughness < 0.0 || roughness > 1.0)
    return fail(pbr + "/roughnessFactor", "expected a number in [0, 1], got " + fmt(roughness));
  mat.metallic = static_cast<float>(metallic);
  mat.roughness = static_cast<float>(roughness);
  const auto& mrt = gm.pbrMetallicRoughness.metallicRoughnessTexture;
  if (mrt.index >= 0) {
    Result<TexRef> r = tex_ref(mrt.index, mrt.texCoord, mrt.extensions_json_string,
                               pbr + "/metallicRoughnessTexture");
    if (!r.ok()) return r.status();
    slots.push_back({kMetallicRoughnessSlot, *r, TexUse::kLinear});
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
  RELIEF_RETURN_IF_ERROR(check_keys(e, ep,
                                    {"technique",
                                     "depth_texture",
                                     "depth_is_height",
                                     "normal_from_depth",
                                     "cone_texture",
                                     "cone_kind",
                                     "depth_scale",
                                     "steps",
                                     "binary_steps",
                                     "self_shadow",
                                     "depth_write",
                                     "silhouette",
                                     "casts_shadow",
                                     "receives_shadow",
                                     "specular",
                                     "shininess",
                                     "shading",
                                     "max_anisotropy",
                                     "params",
                                     "depth_back_texture",
                                     "normal_back_texture",
                                     "height_ao"}));
  mat.technique = "relief";
  if (e.contains("technique")) {
    if (!e["technique"].is_string() || e["technique"].get<std::string>().empty())
      return fail(ep + "/technique", "expected a technique name, got " + e["technique"].dump());
    mat.technique = e["technique"].get<std::string>();
  }
  mat.source.technique_pointer = ep + "/technique";  // checked by render/validate.h
  bool depth_is_height = false;
  RELIEF_RETURN_IF_ERROR(get_bool(e, "depth_is_height", ep, depth_is_height));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "normal_from_depth", ep, normal_from_depth));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "self_shadow", ep, mat.self_shadow));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "depth_write", ep, mat.depth_write));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "silhouette", ep, mat.silhouette));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "casts_shadow", ep, mat.casts_shadow));
  RELIEF_RETURN_IF_ERROR(get_bool(e, "receives_shadow", ep, mat.receives_shadow));
  // "shading": "blinn_phong" | "metallic_roughness"; a file that gives specular or shininess and
  // no shading was written for Blinn-Phong (relief before metallic-roughness) and keeps it.
  if (e.contains("shading") && e["shading"] != "blinn_phong" &&
      e["shading"] != "metallic_roughness")
    return fail(ep + "/shading",
                "expected \"blinn_phong\" or \"metallic_roughness\", got " + e["shading"].dump());
  mat.shading = relief_extension_is_blinn_phong(e) ? ShadingModel::kBlinnPhong
                                                   : ShadingModel::kMetallicRoughness;
  double specular = mat.specular, shininess = mat.shininess;
  RELIEF_RETURN_IF_ERROR(get_number(e, "specular", ep, specular, 0.0, 1e6));
  RELIEF_RETURN_IF_ERROR(get_number(e, "shininess", ep, shininess, 0.0, 1e6));
  mat.specular = static_cast<float>(specular);
  mat.shininess = static_cast<float>(shininess);
  RELIEF_RETURN_IF_ERROR(get_int(e, "max_anisotropy", ep, max_aniso, 1, 16));
  RELIEF_RETURN_IF_ERROR(read_height_ao(e, ep, mat));
  RELIEF_RETURN_IF_ERROR(read_relief_textures(e, ep, depth_is_height, mat, slots));
  return read_relief_params(e, ep, mat);
}

// RELIEF_relief_mapping's "height_ao": {"rays" (0..16), "radius" (uv units, [0, 1]), "strength"
// ([0, 1])}, each optional (Material::height_ao's defaults); a value out of range is an error at
// its pointer.
Status Reader::read_height_ao(const json& e, const std::string& ep, Material& mat) const {
  auto it = e.find("height_ao");
  if (it == e.end()) return {};
  const std::string hp = ep + "/height_ao";
  if (!it->is_object())
    return fail(hp, "expected an object {\"rays\", \"radius\", \"strength\"}, got " + it->dump());
  RELIEF_RETURN_IF_ERROR(check_keys(*it, hp, {"rays", "radius", "strength"}));
  RELIEF_RETURN_IF_ERROR(get_int(*it, "rays", hp, mat.height_ao.rays, 0, kMaxHeightAoRays));
  double radius = mat.height_ao.radius, strength = mat.height_ao.strength;
  RELIEF_RETURN_IF_ERROR(get_number(*it, "radius", hp, radius, 0.0, 1.0));
  RELIEF_RETURN_IF_ERROR(get_number(*it, "strength", hp, strength, 0.0, 1.0));
  mat.height_ao.radius = static_cast<float>(radius);
  mat.height_ao.strength = static_cast<float>(strength);
  return {};
}

// The relief textures of RELIEF_relief_mapping `e` as slots: depth, relief_dual's back layer,
// the cone map.
Status Reader::read_relief_textures(const json& e, const std::string& ep, bool depth_is_height,
                                    Material& mat, std::vector<TextureSlot>& slots) const {
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
    // The slot is cone_<kind>: cone_kind, else the kind the technique reads (render/validate.h
    // names the slot once it knows the technique).
    std::string slot = kConeOfTechnique;
    if (e.contains("cone_kind")) {
      const json& k = e["cone_kind"];
      if (!k.is_string() || (k != "conservative" && k != "quad" && k != "relaxed"))
        return fail(ep + "/cone_kind", "expected conservative, quad or relaxed, got " + k.dump());
      slot = "cone_" + k.get<std::string>();
    } else {
      mat.source.cone_pointer = ep + "/cone_texture";
    }
    slots.push_back({slot, *r, TexUse::kCone});
  }
  return {};
}

// Plugin parameters: the three common ones at the top level, any other in "params", recorded as
// the file gives them with their JSON pointers (render/validate.h types them by the schema of the
// technique that declares them, by the rules --param applies).
Status Reader::read_relief_params(const json& e, const std::string& ep, Material& mat) const {
  std::map<std::string, FileParam>& params = mat.source.params;
  const auto top_level = [&](const char* key, double value) {
    FileParam& f = params[key];
    f.number = value;
    f.pointer = ep + "/" + key;
    f.top_level = true;
  };
  int steps = 0, binary_steps = 0;
  double depth_scale = 0.0;
  if (e.contains("steps")) {
    RELIEF_RETURN_IF_ERROR(get_int(e, "steps", ep, steps, 1, 1 << 20));
    top_level("steps", steps);
  }
  if (e.contains("binary_steps")) {
    RELIEF_RETURN_IF_ERROR(get_int(e, "binary_steps", ep, binary_steps, 0, 1 << 20));
    top_level("binary_steps", binary_steps);
  }
  if (e.contains("depth_scale")) {
    RELIEF_RETURN_IF_ERROR(get_number(e, "depth_scale", ep, depth_scale, 0.0, 1e6));
    top_level("depth_scale", static_cast<float>(depth_scale));
  }
  if (!e.contains("params")) return {};
  const json& ps = e["params"];
  const std::string pp = ep + "/params";
  if (!ps.is_object()) return fail(pp, "expected an object of parameter values");
  for (auto it = ps.begin(); it != ps.end(); ++it) {
    const std::string p = pp + "/" + pointer_token(it.key());
    if (params.count(it.key()))
      return fail(p, "given twice (also at " + params[it.key()].pointer + ")");
    FileParam f;
    f.pointer = p;
    if (it->is_boolean()) {
      f.kind = FileParam::Kind::kBool;
      f.boolean = it->get<bool>();
    } else if (it->is_number()) {
      f.number = it->get<double>();
    } else if (it->is_string()) {
      f.kind = FileParam::Kind::kText;
      f.text = it->get<std::string>();
    } else {
      const char* got = it->is_array() ? "an array" : it->is_object() ? "an object" : "null";
      return fail(p, std::string("expected a number, a boolean or a choice name, got ") + got);
    }
    params[it.key()] = std::move(f);
  }
  return {};
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
    else if (s.name == kMetallicRoughnessSlot)
      mat.metallic_roughness_uv = map;
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
    else if (s.name == kMetallicRoughnessSlot)
      mat.metallic_roughness_texture = *tex;
    else
      mat.textures[s.name] = *tex;
  }
  return {};
}

}  // namespace relief::gltf_detail
