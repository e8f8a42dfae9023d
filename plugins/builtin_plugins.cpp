// Registers the built-in plugins: the list is generated from the RELIEF_BUILTIN_PLUGIN markers in
// plugins/*.cpp (plugins/builtin_plugins.h, cmake/builtin_plugins.cmake).
#include "plugins/builtin_plugins.h"
#include "plugins/registry.h"

namespace relief {

#define RELIEF_BUILTIN(descriptor) RELIEF_BUILTIN_PLUGIN(descriptor);
#include "plugins/builtin_plugins.inc"
#undef RELIEF_BUILTIN

void register_builtin_plugins(PluginRegistry& r) {
#define RELIEF_BUILTIN(descriptor) &descriptor,
  for (const PluginDescriptor* p : {
#include "plugins/builtin_plugins.inc"
       }) {
    CHECK(r.add(p).ok());
  }
#undef RELIEF_BUILTIN
}

}  // namespace relief
