// Built-in plugins. Each plugins/<name>.cpp marks its descriptor, at the start of a line and
// in namespace relief, before defining it:
//   RELIEF_BUILTIN_PLUGIN(kNamePlugin);
//   const PluginDescriptor kNamePlugin = {...};
// The build collects the markers (cmake/builtin_plugins.cmake) into the list
// plugins/builtin_plugins.cpp registers, so a new technique edits no list (docs/plugins.md, "Adding
// a built-in technique").
#pragma once

#include "plugins/plugin.h"

// Declares the descriptor with external linkage (a namespace-scope const has internal linkage
// otherwise) and marks it for the built-in list.
#define RELIEF_BUILTIN_PLUGIN(descriptor) extern const ::relief::PluginDescriptor descriptor
