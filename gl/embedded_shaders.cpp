// Embeds the shader files at build time with the assembler's .incbin: every gl/shaders file and
// the generated ones (prelude.glsl), from the list CMakeLists.txt writes
// (embedded_shader_list.inc: X(symbol, name, absolute path, generated)). CMake globs gl/shaders,
// so a new shader file needs no edit here, and recompiles this file when any listed file changes.
#include "gl/embedded_shaders.h"

// Defines relief_shader_<sym>_begin/_end around the bytes of <file>.
#define RELIEF_EMBED(sym, file, path, generated)       \
  __asm__(                                             \
      ".section .rodata\n"                             \
      ".global relief_shader_" #sym                    \
      "_begin\n"                                       \
      ".hidden relief_shader_" #sym                    \
      "_begin\n"                                       \
      "relief_shader_" #sym                            \
      "_begin:\n"                                      \
      ".incbin \"" path                                \
      "\"\n"                                           \
      ".global relief_shader_" #sym                    \
      "_end\n"                                         \
      ".hidden relief_shader_" #sym                    \
      "_end\n"                                         \
      "relief_shader_" #sym                            \
      "_end:\n"                                        \
      ".previous\n");                                  \
  extern "C" const char relief_shader_##sym##_begin[]; \
  extern "C" const char relief_shader_##sym##_end[];

#define X RELIEF_EMBED
#include "gl/embedded_shader_list.inc"
#undef X

namespace relief::gl {

const std::vector<EmbeddedShader>& embedded_shaders() {
#define X(sym, file, path, generated)                                                          \
  EmbeddedShader{file, relief_shader_##sym##_begin,                                            \
                 static_cast<size_t>(relief_shader_##sym##_end - relief_shader_##sym##_begin), \
                 generated != 0},
  static const std::vector<EmbeddedShader> list = {
#include "gl/embedded_shader_list.inc"
  };
#undef X
  return list;
}

}  // namespace relief::gl
