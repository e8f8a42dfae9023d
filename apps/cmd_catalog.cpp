// `relief techniques` and `relief scenes`: what is built in.
#include <cstdio>

#include "apps/commands.h"
#include "apps/scene_source.h"
#include "builtin/builtin.h"
#include "plugins/registry.h"

namespace relief::cli {
namespace {

std::string effect_names(EffectMask e) {
  std::string s;
  auto add = [&](EffectMask bit, const char* name) {
    if (e & bit) s += (s.empty() ? "" : ", ") + std::string(name);
  };
  add(kEffectSelfShadow, "self_shadow");
  add(kEffectDepthWrite, "depth_write");
  add(kEffectSilhouette, "silhouette");
  add(kEffectShadowPass, "shadow_caster");
  add(kEffectReceiveShadow, "receives_shadow");
  return s.empty() ? "none" : s;
}

}  // namespace

void register_techniques(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("techniques",
                                 "List the shading techniques (plugins) and their parameters");
  auto plugins = std::make_shared<std::vector<std::string>>();
  sub->add_option("--plugin", *plugins, "Load an external plugin (.so) first");
  sub->callback([&action, plugins] {
    action = [plugins] {
      for (const auto& p : *plugins) {
        Status s = load_plugin_arg(p);
        if (!s.ok()) return fail(s.message(), s.exit_code());
      }
      for (const PluginDescriptor* p : PluginRegistry::global().all()) {
        std::printf("%s: %s\n", p->name, p->description);
        std::printf("  effects: %s\n", effect_names(p->supported_effects).c_str());
        std::string tex;
        for (int i = 0; i < p->num_textures; ++i)
          tex += (i ? ", " : "") + std::string(p->textures[i].name) +
                 (p->textures[i].required ? " (required)" : "");
        std::printf("  textures: %s\n", tex.empty() ? "none" : tex.c_str());
        if (p->num_params) std::printf("  parameters:\n%s", describe_params(*p).c_str());
      }
      return 0;
    };
  });
}

void register_scenes(CLI::App& app, Action& action) {
  auto* sub = app.add_subcommand("scenes", "List the built-in scenes");
  sub->callback([&action] {
    action = [] {
      for (const auto& s : builtin_scenes())
        std::printf("%-18s %s%s\n", s.name.c_str(), s.description.c_str(),
                    s.name == default_scene_name() ? " (default)" : "");
      return 0;
    };
  });
}

}  // namespace relief::cli
