// The built-in plugins, registered by name in plugins/builtin.cpp.
#pragma once

#include "plugins/plugin.h"

namespace relief {

extern const PluginDescriptor kFlatPlugin;
extern const PluginDescriptor kNormalPlugin;
extern const PluginDescriptor kParallaxPlugin;
extern const PluginDescriptor kSteepParallaxPlugin;
extern const PluginDescriptor kPomPlugin;
extern const PluginDescriptor kReliefPlugin;
extern const PluginDescriptor kExactPlugin;
extern const PluginDescriptor kConePlugin;
extern const PluginDescriptor kConeQuadPlugin;
extern const PluginDescriptor kRelaxedConePlugin;
extern const PluginDescriptor kReliefQuadricPlugin;
extern const PluginDescriptor kReliefDualPlugin;

}  // namespace relief
