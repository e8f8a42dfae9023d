// The planner (DESIGN.md, "Effects, and simulating only what a scene calls for").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include "bake/environment_bake.h"
#include "plugins/registry.h"
#include "render/derived_maps.h"
#include "render/render.h"
#include "render/validate.h"

namespace relief {
namespace {

void add_effect(BoundMaterial& b, EffectMask effect, bool asked, const char* name) {
  if (!asked) {
    b.reasons.push_back(std::string(name) + ": off (not asked by the material)");
    return;
  }
  if (!(b.plugin->supported_effects & effect)) {
    b.reasons.push_back(std::string(name) + ": off (" + b.plugin->name + " does not support it)");
    return;
  }
  b.effects |= effect;
  b.reasons.push_back(std::string(name) + ": on");
}

std::string effect_names(EffectMask e) {
  static const std::pair<EffectMask, const char*> kNames[] = {
      {kEffectSelfShadow, "self_shadow"},       {kEffectDepthWrite, "depth_write"},
      {kEffectSilhouette, "silhouette"},        {kEffectShadowPass, "shadow_pass"},
      {kEffectReceiveShadow, "receive_shadow"}, {kEffectHeightAo, "height_ao"},
  };
  std::string s;
  for (const auto& [bit, name] : kNames)
    if (e & bit) s += (s.empty() ? "" : ", ") + std::string(name);
  return "{" + s + "}";
}

const char* light_type_name(LightType t) {
  switch (t) {
    case LightType::kDirectional:
      return "directional";
    case LightType::kPoint:
      return "point";
    default:
      return "spot";
  }
}

Status check_shadow_settings(const ShadowSettings& s) {
  const auto bad = [](float v) { return !(v >= 0.0f && v <= 64.0f); };
  if (bad(s.depth_bias)) return Status::usage("shadow depth bias: expected 0..64 texels");
  if (bad(s.slope_bias)) return Status::usage("shadow slope bias: expected 0..64 texels");
  if (s.pcf_radius < 0 || s.pcf_radius > kMaxPcfRadius)
    return Status::usage("shadow PCF radius: expected 0.." + std::to_string(kMaxPcfRadius));
  return {};
}

// Who casts and who visibly receives, over the scene's instances.
struct ShadowParticipants {
  Bounds casters, receivers;  // receivers: clipped to the camera's view box
  std::vector<int> caster_instances, receiver_instances;  // receivers: the visible ones
  int relief_casters = 0;  // casters whose plugin runs its intersection from the light
  int visible = 0, visible_receivers = 0;
};

ShadowParticipants find_participants(const Scene& scene, const Plan& plan) {
  ShadowParticipants p;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const int mi = scene.instances[i].material;
    const Material& m = scene.materials[mi];
    const PluginDescriptor& plugin = *plan.materials[mi].plugin;
    const Bounds b = instance_bounds(scene, static_cast<int>(i));
    if (m.casts_shadow && m.alpha_mode != AlphaMode::kBlend && !b.empty()) {
      p.casters.add(b);
      p.caster_instances.push_back(static_cast<int>(i));
      if (plugin.supported_effects & kEffectShadowPass) ++p.relief_casters;
    }
    if (!bounds_in_view(b, plan.frame.view_proj)) continue;
    ++p.visible;
    if (m.receives_shadow && (plugin.supported_effects & kEffectReceiveShadow)) {
      p.receivers.add(clip_to_view(b, plan.frame.view_proj));
      p.receiver_instances.push_back(static_cast<int>(i));
      ++p.visible_receivers;
    }
  }
  return p;
}

// `fitted` (the light's pass at its shadow_resolution) at the side the view resolves
// (ShadowSize::kView, render/shadow_map.h): fitted again at that side, and once more if the
// smaller map's wider filter margin asks for a texel more.
ShadowPassSetup view_sized_shadow_pass(const Light& l, const ShadowParticipants& who,
                                       const RenderOptions& opt, const FrameUniforms& frame,
                                       const std::vector<std::vector<glm::vec3>>& polygons,
                                       const ShadowPassSetup& fitted) {
  const glm::mat4 proj = frame.view_proj * glm::inverse(frame.view);
  ShadowPassSetup s = fitted;
  int side = view_shadow_size(s, polygons, frame.view, proj, opt.height, l.shadow_resolution);
  for (int round = 0; round < 2 && side != s.size; ++round) {
    Light sized = l;
    sized.shadow_resolution = side;
    s = fit_shadow_pass(sized, who.receivers, who.casters, opt.shadow);
    side = std::max(
        side, view_shadow_size(s, polygons, frame.view, proj, opt.height, l.shadow_resolution));
  }
  return s;
}

// A shadow pass per light that casts shadows, when something casts and something visible
// receives (DESIGN.md); the others are listed in plan.skipped with the reason.
Status plan_shadow_passes(const Scene& scene, const RenderOptions& opt, Plan& plan) {
  const ShadowParticipants who = find_participants(scene, plan);
  // the visible receivers' triangles clipped to the view, for ShadowSize::kView
  std::vector<std::vector<glm::vec3>> polygons;
  for (size_t li = 0; li < scene.lights.size(); ++li) {
    const Light& l = scene.lights[li];
    const std::string head = "light '" + l.name + "' (" + light_type_name(l.type) + "): ";
    std::string why_not;
    if (!l.casts_shadows)
      why_not = "casts_shadows is off";
    else if (!opt.shadows)
      why_not = "shadows are switched off for this frame";
    else if (who.caster_instances.empty())
      why_not = "no material casts shadows";
    else if (who.visible_receivers == 0)
      why_not = "nothing visible receives shadows (" + std::to_string(who.visible) +
                " visible instance(s), none with receives_shadow on a plugin that supports it)";
    if (!why_not.empty()) {
      plan.skipped.push_back(head + "no shadow pass: " + why_not);
      continue;
    }
    if (l.shadow_resolution < 16 || l.shadow_resolution > kMaxTargetSize)
      return Status::error(head + "shadow_resolution " + std::to_string(l.shadow_resolution) +
                           " out of range 16.." + std::to_string(kMaxTargetSize));
    PassPlan pass;
    pass.kind = PassPlan::Kind::kShadow;
    pass.name = "shadow:" + l.name;
    pass.light = static_cast<int>(li);
    pass.instances = who.caster_instances;
    pass.shadow = fit_shadow_pass(l, who.receivers, who.casters, opt.shadow);
    std::string sized;
    if (opt.shadow_size == ShadowSize::kView) {
      if (polygons.empty())
        polygons = visible_receiver_polygons(scene, who.receiver_instances, plan.frame.view_proj);
      pass.shadow = view_sized_shadow_pass(l, who, opt, plan.frame, polygons, pass.shadow);
      if (pass.shadow.size < l.shadow_resolution)
        sized = " (the light asks for " + std::to_string(l.shadow_resolution) +
                "; a texel per pixel of this view is " + std::to_string(pass.shadow.size) + ")";
    }
    pass.reason = head + "casts shadows; " + std::to_string(who.caster_instances.size()) +
                  " caster(s), " + std::to_string(who.relief_casters) +
                  " with relief depth from the light; " + std::to_string(who.visible_receivers) +
                  " visible receiver(s); " + describe_shadow_pass(pass.shadow) + sized;
    plan.passes.push_back(std::move(pass));
  }
  return {};
}

// Each material's part in the shadow passes: receiving (main-pass variant) and casting
// (shadow-pass variant).
void plan_shadow_variants(const Scene& scene, Plan& plan) {
  std::string maps;
  for (const PassPlan& p : plan.passes)
    if (p.kind == PassPlan::Kind::kShadow) maps += (maps.empty() ? "" : ", ") + p.name;
  const bool any = !maps.empty();
  for (size_t k = 0; k < scene.materials.size(); ++k) {
    const Material& m = scene.materials[k];
    BoundMaterial& b = plan.materials[k];
    const std::string plugin = b.plugin->name;
    if (!m.receives_shadow)
      b.reasons.push_back("receive_shadow: off (not asked by the material)");
    else if (!(b.plugin->supported_effects & kEffectReceiveShadow))
      b.reasons.push_back("receive_shadow: off (" + plugin + " does not support it)");
    else if (!any)
      b.reasons.push_back("receive_shadow: off (no shadow pass)");
    else {
      b.effects |= kEffectReceiveShadow;
      b.reasons.push_back("receive_shadow: on (looks up " + maps + " at the shaded point)");
    }
    if (!m.casts_shadow) {
      b.reasons.push_back("casts_shadow: off (not asked by the material)");
    } else if (m.alpha_mode == AlphaMode::kBlend) {
      b.reasons.push_back("casts_shadow: off (alphaMode BLEND: blended surfaces cast no shadow)");
    } else if (!any) {
      b.reasons.push_back("casts_shadow: asked, but there is no shadow pass");
    } else if (b.plugin->supported_effects & kEffectShadowPass) {
      b.shadow_caster = true;
      b.shadow_effects = kEffectShadowPass | (b.effects & kEffectSilhouette);
      b.reasons.push_back(
          "casts_shadow: on (shadow passes run " + plugin +
          "'s intersection from the light and write the corrected depth" +
          (m.alpha_mode == AlphaMode::kMask ? ", cut out by alpha at the hit)" : ")"));
    } else {
      b.shadow_caster = true;
      b.reasons.push_back(
          "casts_shadow: on (polygon depth: " + plugin + " has no shadow-pass variant" +
          (m.alpha_mode == AlphaMode::kMask ? "; cut out by the base colour's alpha)" : ")"));
    }
  }
}

// `v` as %g prints it (0.5, not 0.500000).
std::string short_number(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

// Plan::draw_order: OPAQUE and MASK instances in submission order, then BLEND ones sorted back
// to front by the view-space depth of their bounds' centre, ties (and empty bounds, drawn first)
// in submission order.
std::vector<int> blend_draw_order(const Scene& scene, const glm::mat4& view) {
  std::vector<int> order, blended;
  std::vector<float> far_key(scene.instances.size(), 0.0f);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Material& m = scene.materials[scene.instances[i].material];
    if (m.alpha_mode != AlphaMode::kBlend) {
      order.push_back(static_cast<int>(i));
      continue;
    }
    const Bounds b = instance_bounds(scene, static_cast<int>(i));
    const float z = b.empty() ? NAN : (view * glm::vec4((b.lo + b.hi) * 0.5f, 1.0f)).z;
    // distance along the view direction (the eye looks down -z); farthest first
    far_key[i] = std::isfinite(z) ? -z : std::numeric_limits<float>::infinity();
    blended.push_back(static_cast<int>(i));
  }
  std::stable_sort(blended.begin(), blended.end(),
                   [&](int a, int b) { return far_key[a] > far_key[b]; });
  order.insert(order.end(), blended.begin(), blended.end());
  return order;
}

// Whether height-field AO values are in range (rays 0..16, radius and strength in [0, 1]);
// `what` names the values' origin in the error.
Status check_height_ao(const HeightAoParams& h, const std::string& what) {
  if (h.rays < 0 || h.rays > kMaxHeightAoRays)
    return Status::error(what + ": height-field AO rays " + std::to_string(h.rays) +
                         " outside 0.." + std::to_string(kMaxHeightAoRays));
  if (!(h.radius >= 0.0f && h.radius <= 1.0f))
    return Status::error(what + ": height-field AO radius " + short_number(h.radius) +
                         " outside [0, 1] (uv units)");
  if (!(h.strength >= 0.0f && h.strength <= 1.0f))
    return Status::error(what + ": height-field AO strength " + short_number(h.strength) +
                         " outside [0, 1]");
  return {};
}

// What make_plan checks of the scene and the options before binding anything.
Status check_request(const Scene& scene, const RenderOptions& opt) {
  if (scene.cameras.empty()) return Status::error("scene '" + scene.name + "' has no camera");
  if (opt.camera < 0 || opt.camera >= static_cast<int>(scene.cameras.size()))
    return Status::usage("camera index " + std::to_string(opt.camera) +
                         " out of range (scene has " + std::to_string(scene.cameras.size()) + ")");
  uint64_t triangles = 0;
  for (const Instance& inst : scene.instances)
    if (inst.mesh >= 0 && inst.mesh < static_cast<int>(scene.meshes.size()))
      triangles += scene.meshes[inst.mesh].indices.size() / 3;
  if (triangles > kMaxSceneTriangles)
    return Status::error("scene '" + scene.name + "': " + std::to_string(triangles) +
                         " triangles to draw, more than the limit of " +
                         std::to_string(kMaxSceneTriangles));
  if (!opt.technique.empty()) {
    Result<const PluginDescriptor*> t = find_technique(opt.technique, ValueOrigin::option());
    if (!t.ok()) return t.status();
  }
  HeightAoParams h;
  h.rays = opt.height_ao_rays.value_or(0);
  h.radius = opt.height_ao_radius.value_or(h.radius);
  h.strength = opt.height_ao_strength.value_or(h.strength);
  if (Status s = check_height_ao(h, "--height-ao"); !s.ok()) return Status::usage(s.message());
  return check_shadow_settings(opt.shadow);
}

// The texture slots of b.plugin from the material, the derived-map cache, or nothing (an
// optional slot, or one these parameters do not read).
Status bind_textures(const Material& m, BoundMaterial& b) {
  for (int s = 0; s < b.plugin->num_textures; ++s) {
    const TextureSlotSpec& slot = b.plugin->textures[s];
    if (b.plugin->reads_texture && !b.plugin->reads_texture(b.uniforms.params, s)) {
      if (is_derived_slot(slot.name))
        b.reasons.push_back(std::string(slot.name) +
                            ": not baked (these parameters do not read it)");
      continue;
    }
    auto it = m.textures.find(slot.name);
    if (it == m.textures.end() || !it->second) {
      // cone maps and max-mips: baked from depth, cached; the normal map when the material asks
      if (is_derived_slot(slot.name) || derives_normal_map(m, slot.name)) {
        Result<DerivedMap> d = derive_map(m, slot.name);
        if (!d.ok()) return d.status().with_context("material '" + m.name + "'");
        b.uniforms.textures[s] = d->texture.get();
        b.uniforms.samplers[s] = m.sampler;
        b.keep_alive.push_back(d->texture);
        b.reasons.push_back(d->note);
        continue;
      }
      if (slot.required)
        return Status::error("material '" + m.name + "': technique " + b.plugin->name +
                             " needs a '" + slot.name + "' texture");
      continue;
    }
    b.uniforms.textures[s] = it->second.get();
    b.uniforms.samplers[s] = m.sampler;
    b.keep_alive.push_back(it->second);
    if (auto u = m.uv_maps.find(slot.name); u != m.uv_maps.end()) b.uniforms.uv_maps[s] = u->second;
  }
  return {};
}

// The material-wide glTF terms (plugins/surface.h finish_surface), colours and alpha mode.
void bind_surface(const Material& m, BoundMaterial& b) {
  b.uniforms.emissive = m.emissive * m.emissive_strength;
  if (m.emissive_texture && b.uniforms.emissive != glm::vec3(0.0f)) {
    b.uniforms.emissive_texture = m.emissive_texture.get();
    b.uniforms.emissive_sampler = m.sampler;
    b.uniforms.emissive_uv = m.emissive_uv;
    b.keep_alive.push_back(m.emissive_texture);
  }
  b.uniforms.shading = m.shading;
  b.uniforms.metallic = m.metallic;
  b.uniforms.roughness = m.roughness;
  if (m.shading == ShadingModel::kMetallicRoughness && m.metallic_roughness_texture) {
    b.uniforms.metallic_roughness_texture = m.metallic_roughness_texture.get();
    b.uniforms.metallic_roughness_sampler = m.sampler;
    b.uniforms.metallic_roughness_uv = m.metallic_roughness_uv;
    b.keep_alive.push_back(m.metallic_roughness_texture);
  }
  if (m.occlusion_texture && m.occlusion_strength != 0.0f) {
    b.uniforms.occlusion_texture = m.occlusion_texture.get();
    b.uniforms.occlusion_sampler = m.sampler;
    b.uniforms.occlusion_uv = m.occlusion_uv;
    b.uniforms.occlusion_strength = m.occlusion_strength;
    b.keep_alive.push_back(m.occlusion_texture);
  }
  b.uniforms.normal_scale = m.normal_scale;
  b.uniforms.unlit = m.unlit;
  if (m.unlit)
    b.reasons.push_back("unlit: base colour only (KHR_materials_unlit)");
  else if (m.shading == ShadingModel::kMetallicRoughness)
    b.reasons.push_back("shading: glTF metallic-roughness (metallic " + short_number(m.metallic) +
                        ", roughness " + short_number(m.roughness) +
                        (b.uniforms.metallic_roughness_texture ? ", times its texture)" : ")"));
  b.uniforms.base_color = m.base_color;
  b.uniforms.specular = m.specular;
  b.uniforms.shininess = m.shininess;
  b.uniforms.alpha_mode = m.alpha_mode;
  b.uniforms.alpha_cutoff = m.alpha_cutoff;
  if (m.alpha_mode == AlphaMode::kMask)
    b.reasons.push_back("alpha: MASK (discarded below alpha " + short_number(m.alpha_cutoff) +
                        ", main and shadow passes)");
  else if (m.alpha_mode == AlphaMode::kBlend)
    b.reasons.push_back("alpha: BLEND (after the opaque draws, back to front, no depth write)");
  b.double_sided = m.double_sided;
}

// A layered technique (PluginDescriptor::layers) draws its shells alpha-tested, so that the depth
// test keeps the outermost opaque shell of each pixel: MASK at the material's own cutoff when it
// is MASK already (coverage is 0 or 1, times the base colour's alpha), else at 0.5. BLEND is
// replaced too: N shells blended in draw order would composite inner over outer ones.
void bind_layers(const Material& m, BoundMaterial& b) {
  if (!b.plugin->layers) return;
  const MaterialLayers layers = material_layers(b);
  if (m.alpha_mode != AlphaMode::kMask) b.uniforms.alpha_cutoff = 0.5f;
  b.uniforms.alpha_mode = AlphaMode::kMask;
  b.reasons.push_back("layers: " + std::to_string(layers.layers) + " shells, outermost first, " +
                      "alpha-tested against the depth map (MASK at " +
                      short_number(b.uniforms.alpha_cutoff) +
                      (m.alpha_mode == AlphaMode::kBlend ? ", instead of BLEND)" : ")"));
}

// Whether the bound material's self-shadow is a darkening with depth rather than rays: shells,
// and a technique whose `shadow` parameter is set to its `depth` choice (steep parallax).
bool self_shadow_by_depth(const BoundMaterial& b) {
  if (b.plugin->layers) return true;
  const int i = param_index(*b.plugin, "shadow");
  if (i < 0 || !b.plugin->params[i].choices) return false;
  const std::string choices = std::string("|") + b.plugin->params[i].choices + "|";
  const size_t at = choices.find("|depth|");
  if (at == std::string::npos) return false;
  const int index = static_cast<int>(std::count(choices.begin(), choices.begin() + at, '|'));
  return static_cast<int>(b.uniforms.params[i]) == index;
}

// The effects the material asks for that its plugin supports and this frame allows.
void bind_effects(const Scene& scene, const Material& m, const RenderOptions& opt,
                  BoundMaterial& b) {
  if (m.self_shadow && scene.lights.empty())
    b.reasons.push_back("self_shadow: off (the scene has no light)");
  else if (m.self_shadow && !opt.self_shadow)
    b.reasons.push_back("self_shadow: off (switched off for this frame)");
  else
    add_effect(b, kEffectSelfShadow, m.self_shadow, "self_shadow");
  if (b.effects & kEffectSelfShadow)
    b.reasons.back() += self_shadow_by_depth(b) ? " (darkening with depth, no shadow rays)"
                                                : " (rays only where N.L > 0)";
  add_effect(b, kEffectDepthWrite, m.depth_write, "depth_write");
  add_effect(b, kEffectSilhouette, m.silhouette, "silhouette");
}

// Height-field ambient occlusion (shaders_cpp/height_ao.h): the material's, with the options'
// values over every relief material (one with a depth map); on where the plugin supports it.
Status bind_height_ao(const Material& m, const RenderOptions& opt, BoundMaterial& b) {
  HeightAoParams h = m.height_ao;
  if (m.textures.count("depth") != 0) {
    if (opt.height_ao_rays) h.rays = *opt.height_ao_rays;
    if (opt.height_ao_radius) h.radius = *opt.height_ao_radius;
    if (opt.height_ao_strength) h.strength = *opt.height_ao_strength;
  }
  RELIEF_RETURN_IF_ERROR(check_height_ao(h, "material '" + m.name + "'"));
  if (h.rays == 0 || h.radius == 0.0f || h.strength == 0.0f || m.unlit) {
    b.reasons.push_back(h.rays == 0 ? "height_ao: off (not asked by the material)"
                        : m.unlit   ? "height_ao: off (unlit material)"
                                    : "height_ao: off (radius or strength 0)");
    return {};
  }
  if (!(b.plugin->supported_effects & kEffectHeightAo)) {
    b.reasons.push_back(std::string("height_ao: off (not supported by technique ") +
                        b.plugin->name + ")");
    return {};
  }
  b.effects |= kEffectHeightAo;
  b.uniforms.height_ao = h;
  b.reasons.push_back("height_ao: on (" + std::to_string(h.rays) + " rays x 4 steps, radius " +
                      short_number(h.radius) + " uv, strength " + short_number(h.strength) +
                      "; ambient/environment light only)");
  return {};
}

// One material bound to its plugin. `--technique` replaces the technique of the relief materials
// (those with a depth map); the others (plain spheres through a relief floor, say) keep theirs.
// `--param key=value` goes to every material whose technique declares the key (param_used).
Result<BoundMaterial> bind_material(const Scene& scene, const Material& m, const RenderOptions& opt,
                                    std::map<std::string, bool>& param_used) {
  BoundMaterial b;
  b.name = m.name;
  const bool relief_material = m.textures.count("depth") != 0;
  const std::string technique =
      opt.technique.empty() || !relief_material ? m.technique : opt.technique;
  if (m.source.pending())  // load_scene (render/validate.h) resolves it
    return Status::error("material '" + m.name +
                         "': its scene file's technique and parameters are not validated " +
                         "(load it with load_scene)");
  Result<const PluginDescriptor*> plugin =
      find_technique(technique, ValueOrigin::of_material(m.name));
  if (!plugin.ok()) return plugin.status();
  b.plugin = *plugin;
  Result<std::vector<float>> values = material_param_values(*b.plugin, m, opt.params, param_used);
  if (!values.ok()) return values.status();
  for (size_t i = 0; i < values->size(); ++i) b.uniforms.params[i] = (*values)[i];
  RELIEF_RETURN_IF_ERROR(bind_textures(m, b));
  bind_surface(m, b);
  bind_layers(m, b);
  bind_effects(scene, m, opt, b);
  RELIEF_RETURN_IF_ERROR(bind_height_ao(m, opt, b));
  return b;
}

// The main pass's camera, target and lights.
Status frame_uniforms(const Scene& scene, const RenderOptions& opt, FrameUniforms& f) {
  const Camera& cam = scene.cameras[opt.camera];
  const float aspect = static_cast<float>(opt.width) / static_cast<float>(opt.height);
  f.view = cam.view();
  f.view_proj = cam.projection(aspect) * f.view;
  f.eye = cam.position;
  f.orthographic = cam.orthographic;
  f.view_dir = glm::normalize(cam.target - cam.position);
  f.ambient = scene.ambient;
  f.aovs = opt.aovs;
  f.width = opt.width;
  f.height = opt.height;
  f.scalar_lanes = opt.scalar_lanes;
  if (scene.lights.size() > static_cast<size_t>(kMaxLights))
    return Status::error("scene has " + std::to_string(scene.lights.size()) + " lights; at most " +
                         std::to_string(kMaxLights) + " are supported");
  for (const Light& l : scene.lights) {
    LightUniform& u = f.lights[f.num_lights++];
    u.type = l.type;
    u.position = l.position;
    u.direction = glm::normalize(l.direction);
    u.color = l.color * l.intensity;
    u.range = l.range;
    u.inner_cone_cos = std::cos(glm::radians(l.inner_cone_deg));
    u.outer_cone_cos = std::cos(glm::radians(l.outer_cone_deg));
  }
  return {};
}

// The side of the built-in studio environment's equirectangular image: its panels and gradients
// are soft, and its bake (docs/environment.md) is cached for the process.
constexpr int kStudioEnvironmentWidth = 512;

// The frame's image-based light: the one asked for, else the studio environment for a scene
// without lights (when allowed), else none (the scene's ambient colour).
Status plan_environment(const Scene& scene, const RenderOptions& opt, Plan& plan) {
  char view[96];
  std::snprintf(view, sizeof view, " (rotation %g deg, intensity %g)",
                glm::degrees(std::atan2(opt.env_view.sin_rotation, opt.env_view.cos_rotation)),
                opt.env_view.intensity);
  if (opt.environment) {
    plan.environment = opt.environment;
    plan.environment_reason = "image-based light " + opt.environment_name + view;
  } else if (scene.lights.empty() && opt.studio_environment) {
    Result<DerivedEnvironment> studio = derived_environment(
        studio_environment(kStudioEnvironmentWidth, kStudioEnvironmentWidth / 2));
    if (!studio.ok()) return studio.status();
    plan.environment = studio->maps;
    plan.environment_reason = "the built-in studio environment" + std::string(view) +
                              ": the scene has no lights and no --env (" + studio->note + ")";
  } else {
    char amb[96];
    std::snprintf(amb, sizeof amb, "none: the ambient colour (%g, %g, %g) is the indirect light",
                  scene.ambient.r, scene.ambient.g, scene.ambient.b);
    plan.environment_reason = amb;
  }
  plan.frame.environment = plan.environment.get();
  plan.frame.env_view = opt.env_view;
  return {};
}

}  // namespace

// The triangle limit again once the materials are bound: a layered material (shells) draws its
// instances' triangles once per layer, which the prepare stage would allocate.
Status check_layered_triangles(const Scene& scene, const Plan& plan) {
  uint64_t triangles = 0;
  bool layered = false;
  for (const Instance& inst : scene.instances) {
    const int layers = material_layers(plan.materials[inst.material]).layers;
    layered = layered || layers > 0;
    triangles +=
        scene.meshes[inst.mesh].indices.size() / 3 * static_cast<uint64_t>(std::max(layers, 1));
  }
  if (!layered || triangles <= kMaxSceneTriangles) return {};
  return Status::error("scene '" + scene.name + "': " + std::to_string(triangles) +
                       " triangles to draw with every shell layer, more than the limit of " +
                       std::to_string(kMaxSceneTriangles) + " (use fewer layers)");
}

Result<Plan> make_plan(const Scene& scene, const RenderOptions& opt) {
  Plan plan;
  RELIEF_RETURN_IF_ERROR(check_request(scene, opt));
  // A `--param` key no technique in this scene declares is an error.
  std::map<std::string, bool> param_used;
  for (const auto& [k, v] : opt.params) param_used[k] = false;
  for (const Material& m : scene.materials) {
    Result<BoundMaterial> b = bind_material(scene, m, opt, param_used);
    if (!b.ok()) return b.status();
    plan.materials.push_back(std::move(b).value());
  }
  for (const auto& [key, used] : param_used)
    if (!used && !plan.materials.empty())  // the first material's plugin names the key
      return undeclared_param_option(*plan.materials.front().plugin, key, opt.params.at(key));
  RELIEF_RETURN_IF_ERROR(frame_uniforms(scene, opt, plan.frame));
  RELIEF_RETURN_IF_ERROR(plan_environment(scene, opt, plan));
  for (const Instance& inst : scene.instances)
    if (inst.material < 0 || inst.material >= static_cast<int>(scene.materials.size()) ||
        inst.mesh < 0 || inst.mesh >= static_cast<int>(scene.meshes.size()))
      return Status::error("scene '" + scene.name + "': an instance has no valid mesh or material");
  RELIEF_RETURN_IF_ERROR(check_layered_triangles(scene, plan));
  plan.shadow = opt.shadow;
  plan.shadow_on_demand = opt.shadow_on_demand;
  RELIEF_RETURN_IF_ERROR(plan_shadow_passes(scene, opt, plan));
  plan_shadow_variants(scene, plan);
  plan.draw_order = blend_draw_order(scene, plan.frame.view);
  const Camera& cam = scene.cameras[opt.camera];
  PassPlan main;
  main.kind = PassPlan::Kind::kMain;
  main.name = "main";
  main.reason =
      "camera '" + cam.name + "', " + std::to_string(scene.instances.size()) + " instance(s)";
  plan.passes.push_back(main);
  return plan;
}

std::string Plan::explain() const {
  std::ostringstream os;
  os << "passes:\n";
  for (const PassPlan& p : passes) os << "  " << p.name << ": " << p.reason << "\n";
  if (!skipped.empty()) {
    os << "not planned:\n";
    for (const std::string& s : skipped) os << "  " << s << "\n";
  }
  os << "environment: " << environment_reason << "\n";
  os << "materials:\n";
  for (size_t i = 0; i < materials.size(); ++i) {
    const BoundMaterial& b = materials[i];
    os << "  [" << i << "] " << b.name << ": " << b.plugin->name << ", main variant "
       << effect_names(b.effects);
    if (b.shadow_caster) os << ", shadow-pass variant " << effect_names(b.shadow_effects);
    os << "\n";
    for (const std::string& r : b.reasons) os << "      " << r << "\n";
  }
  return os.str();
}

}  // namespace relief
