// Copies of gl/shaders/* compiled into the binary (gl/embedded_shaders.cpp), the last place
// read_shader_file() looks, so an installed binary works without the source tree; and the
// shaders generated at build time (prelude.glsl), which are read from here only.
#pragma once

#include <cstddef>
#include <vector>

namespace relief::gl {

struct EmbeddedShader {
  const char* name;  // file name in gl/shaders
  const char* text;  // not NUL-terminated
  size_t size;
  bool generated;  // made by the build (gl/tools/glsl_prelude.cpp), not a gl/shaders file
};

const std::vector<EmbeddedShader>& embedded_shaders();

}  // namespace relief::gl
