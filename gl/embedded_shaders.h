// Copies of gl/shaders/* compiled into the binary (gl/embedded_shaders.cpp), the last place
// read_shader_file() looks, so an installed binary works without the source tree.
#pragma once

#include <cstddef>
#include <vector>

namespace relief::gl {

struct EmbeddedShader {
  const char* name;  // file name in gl/shaders
  const char* text;  // not NUL-terminated
  size_t size;
};

const std::vector<EmbeddedShader>& embedded_shaders();

}  // namespace relief::gl
