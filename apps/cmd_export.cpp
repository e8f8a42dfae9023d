// `relief export`: writes a scene (built-in or file) as glTF 2.0 with the relief material
// extension; how the examples in scenes/ are made (`relief export plane -o scenes/plane.gltf`).
#include <cstdio>

#include "apps/commands.h"
#include "apps/scene_source.h"
#include "render/derived_maps.h"
#include "scene/gltf.h"

namespace relief::cli {

void register_export(CLI::App& app, Action& action) {
  auto scene = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto allow_outside = std::make_shared<bool>(false);
  auto strict = std::make_shared<bool>(false);
  auto* sub = app.add_subcommand(
      "export", "Write a scene as .gltf (with .bin and PNG textures beside it) or .glb");
  sub->add_option("scene", *scene, "Built-in scene name (see `relief scenes`) or .gltf/.glb file")
      ->required();
  sub->add_option("-o,--output", *output, "Output .gltf or .glb")->required();
  sub->add_flag("--allow-outside-scene-dir", *allow_outside, kAllowOutsideSceneDirHelp);
  sub->add_flag("--strict", *strict, kStrictHelp);
  sub->callback([&action, scene, output, allow_outside, strict] {
    action = [scene, output, allow_outside, strict] {
      Result<Scene> s = load_scene_source(*scene, *allow_outside, *strict);
      if (!s.ok()) return fail(s.status().message(), s.status().exit_code());
      drop_derivable_normal_maps(*s);  // the file asks for them from depth instead
      Status w = save_gltf(*s, *output);
      if (!w.ok()) return fail(w.message(), w.exit_code());
      std::printf("%s: %s, %zu meshes, %zu materials, %zu lights, %zu cameras\n", output->c_str(),
                  scene->c_str(), s->meshes.size(), s->materials.size(), s->lights.size(),
                  s->cameras.size());
      return 0;
    };
  });
}

}  // namespace relief::cli
