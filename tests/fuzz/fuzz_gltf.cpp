// libFuzzer target: load_scene (render/validate.h: scene/gltf.h's load_gltf, then the
// validator) on arbitrary .gltf (JSON) or .glb bytes, RELIEF_relief_mapping checked against the
// built-in plugins. Any input must give a Scene or a one-line error; never a crash, a leak or UB.
#include <cstring>

#include "fuzz_util.h"
#include "render/validate.h"
#include "scene/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  relief::fuzz::TempFile file(data, size, binary ? ".glb" : ".gltf");
  relief::Result<relief::Scene> scene = relief::load_scene(file.path());
  if (!scene.ok() && scene.status().message().find('\n') != std::string::npos) __builtin_trap();
  return 0;
}
