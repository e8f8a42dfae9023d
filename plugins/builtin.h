// The built-in plugins, registered by name in plugins/builtin.cpp.
#pragma once

#include "plugins/plugin.h"

namespace relief {

extern const PluginDescriptor kFlatPlugin;
extern const PluginDescriptor kNormalPlugin;

}  // namespace relief
