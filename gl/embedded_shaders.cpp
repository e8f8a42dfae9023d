// Embeds gl/shaders/* at build time with the assembler's .incbin, reading the files from
// RELIEF_GL_SHADER_DIR (the source tree's gl/shaders, set by CMake). A new shader file gets one
// RELIEF_EMBED line here; tests/gl/shader_test.cpp checks that every file on disk is listed.
// A clean build always embeds the current files; an incremental build re-embeds them when this
// file is recompiled.
#include "gl/embedded_shaders.h"

#ifndef RELIEF_GL_SHADER_DIR
#error "RELIEF_GL_SHADER_DIR must name gl/shaders (set in CMakeLists.txt)"
#endif

// Defines relief_shader_<sym>_begin/_end around the bytes of <file>.
#define RELIEF_EMBED(sym, file)                        \
  __asm__(                                             \
      ".section .rodata\n"                             \
      ".global relief_shader_" #sym                    \
      "_begin\n"                                       \
      ".hidden relief_shader_" #sym                    \
      "_begin\n"                                       \
      "relief_shader_" #sym                            \
      "_begin:\n"                                      \
      ".incbin \"" RELIEF_GL_SHADER_DIR "/" file       \
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

#define RELIEF_SHADER_LIST(X)                   \
  X(relief_vert, "relief.vert")                 \
  X(common_glsl, "common.glsl")                 \
  X(ray_glsl, "ray.glsl")                       \
  X(search_glsl, "search.glsl")                 \
  X(shadow_glsl, "shadow.glsl")                 \
  X(exact_glsl, "exact.glsl")                   \
  X(relief_shell_glsl, "relief_shell.glsl")     \
  X(flat_frag, "flat.frag")                     \
  X(normal_frag, "normal.frag")                 \
  X(parallax_frag, "parallax.frag")             \
  X(steep_parallax_frag, "steep_parallax.frag") \
  X(pom_frag, "pom.frag")                       \
  X(relief_frag, "relief.frag")                 \
  X(quadric_glsl, "quadric.glsl")               \
  X(relief_quadric_frag, "relief_quadric.frag") \
  X(relief_dual_frag, "relief_dual.frag")       \
  X(exact_frag, "exact.frag")                   \
  X(cone_glsl, "cone.glsl")                     \
  X(cone_frag, "cone.frag")                     \
  X(cone_quad_frag, "cone_quad.frag")           \
  X(relaxed_cone_frag, "relaxed_cone.frag")     \
  X(shadow_map_glsl, "shadow_map.glsl")         \
  X(depth_only_frag, "depth_only.frag")

RELIEF_SHADER_LIST(RELIEF_EMBED)

namespace relief::gl {

const std::vector<EmbeddedShader>& embedded_shaders() {
#define RELIEF_ENTRY(sym, file)                     \
  EmbeddedShader{file, relief_shader_##sym##_begin, \
                 static_cast<size_t>(relief_shader_##sym##_end - relief_shader_##sym##_begin)},
  static const std::vector<EmbeddedShader> list = {RELIEF_SHADER_LIST(RELIEF_ENTRY)};
#undef RELIEF_ENTRY
  return list;
}

}  // namespace relief::gl
