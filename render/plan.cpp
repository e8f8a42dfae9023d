// The planner (DESIGN.md, "Effects, and simulating only what a scene calls for").
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "plugins/registry.h"
#include "render/derived_maps.h"
#include "render/render.h"

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

}  // namespace

Result<Plan> make_plan(const Scene& scene, const RenderOptions& opt) {
  Plan plan;
  if (scene.cameras.empty()) return Status::error("scene '" + scene.name + "' has no camera");
  if (opt.camera < 0 || opt.camera >= static_cast<int>(scene.cameras.size()))
    return Status::usage("camera index " + std::to_string(opt.camera) + " out of range (scene has " +
                         std::to_string(scene.cameras.size()) + ")");
  const PluginRegistry& reg = PluginRegistry::global();
  if (!opt.technique.empty() && !reg.find(opt.technique))
    return Status::usage("unknown technique '" + opt.technique + "' (see `relief techniques`)");

  bool any_self_shadow = false;
  for (const Material& m : scene.materials) {
    BoundMaterial b;
    const std::string technique = opt.technique.empty() ? m.technique : opt.technique;
    b.plugin = reg.find(technique);
    if (!b.plugin)
      return Status::error("material '" + m.name + "': unknown technique '" + technique + "'");
    // Scene parameters the chosen plugin does not declare belong to other techniques.
    std::map<std::string, float> scene_params;
    for (const auto& [k, v] : m.params)
      if (param_index(*b.plugin, k.c_str()) >= 0) scene_params[k] = v;
    Result<std::vector<float>> values = resolve_params(*b.plugin, scene_params, opt.params);
    if (!values.ok()) return values.status().with_context("material '" + m.name + "'");
    for (size_t i = 0; i < values->size(); ++i) b.uniforms.params[i] = (*values)[i];
    for (int s = 0; s < b.plugin->num_textures; ++s) {
      const TextureSlotSpec& slot = b.plugin->textures[s];
      auto it = m.textures.find(slot.name);
      if (it == m.textures.end() || !it->second) {
        if (is_derived_slot(slot.name)) {  // cone maps: baked from depth, cached
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
    }
    b.uniforms.base_color = m.base_color;
    b.uniforms.specular = m.specular;
    b.uniforms.shininess = m.shininess;
    b.double_sided = m.double_sided;
    add_effect(b, kEffectSelfShadow, m.self_shadow && !scene.lights.empty(), "self_shadow");
    add_effect(b, kEffectDepthWrite, m.depth_write, "depth_write");
    add_effect(b, kEffectSilhouette, m.silhouette, "silhouette");
    any_self_shadow |= (b.effects & kEffectSelfShadow) != 0;
    plan.materials.push_back(std::move(b));
  }

  const Camera& cam = scene.cameras[opt.camera];
  const float aspect = static_cast<float>(opt.width) / static_cast<float>(opt.height);
  FrameUniforms& f = plan.frame;
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
  PassPlan main;
  main.kind = PassPlan::Kind::kMain;
  main.name = "main";
  main.reason = "camera '" + cam.name + "', " + std::to_string(scene.instances.size()) +
                " instance(s)";
  plan.passes.push_back(main);
  (void)any_self_shadow;
  return plan;
}

std::string Plan::explain() const {
  std::ostringstream os;
  os << "passes:\n";
  for (const PassPlan& p : passes) os << "  " << p.name << ": " << p.reason << "\n";
  os << "materials:\n";
  for (size_t i = 0; i < materials.size(); ++i) {
    const BoundMaterial& b = materials[i];
    os << "  [" << i << "] " << b.plugin->name << "\n";
    for (const std::string& r : b.reasons) os << "      " << r << "\n";
  }
  return os.str();
}

}  // namespace relief
