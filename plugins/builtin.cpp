// The static list of built-in plugins. A new technique adds its descriptor here.
#include "plugins/builtin.h"
#include "plugins/registry.h"

namespace relief {

void register_builtin_plugins(PluginRegistry& r) {
  for (const PluginDescriptor* p : {
           &kFlatPlugin,
           &kNormalPlugin,
           &kParallaxPlugin,
           &kSteepParallaxPlugin,
           &kPomPlugin,
           &kReliefPlugin,
           &kExactPlugin,
           &kConePlugin,
           &kConeQuadPlugin,
           &kRelaxedConePlugin,
           &kReliefQuadricPlugin,
           &kReliefDualPlugin,
       }) {
    CHECK(r.add(p).ok());
  }
}

}  // namespace relief
