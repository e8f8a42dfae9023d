// GLSL sources and programs for the GL backend.
//
// Shader files live in gl/shaders/ and are read at run time from, in order: the directory named by
// the environment variable RELIEF_GL_SHADER_DIR, the source tree's gl/shaders (compile-time
// RELIEF_GL_SHADER_DIR), then the copy embedded into the binary when it was built (so an
// installed binary works without the source tree). Shaders the build generates (prelude.glsl:
// the constants C++ and GLSL share, gl/tools/glsl_prelude.cpp) are always read from the binary,
// since they describe its C++ side.
//
// A file starts with `#version 450 core`; `#include "name"` lines pull in another file of the same
// directory once (later includes of it are skipped). The preprocessor inserts the variant's
// #defines after the #version line and `#line` directives that number every file as its own
// source string, so a compile error names the file and line the driver reported:
// "flat.frag:12: 'foo' : undeclared identifier" (one line; the first error of the log).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "base/status.h"

namespace relief::gl {

// Reads a shader file by name ("flat.frag") from the search path above.
Result<std::string> read_shader_file(const std::string& name);
// Whether a shader file by that name exists on the search path.
bool shader_file_exists(const std::string& name);
// Every shader file on the search path and the generated ones, sorted by name.
std::vector<std::string> list_shader_files();
// Where shaders are read from now ("<dir>" or "embedded").
std::string shader_source_location();

struct ShaderSource {
  std::string text;                // what the driver compiles
  std::vector<std::string> files;  // files[i]: the file whose source-string number is i
};

using ShaderReader = std::function<Result<std::string>(const std::string& name)>;

// Expands includes and inserts `defines` ("NAME VALUE" or "NAME") after the #version line.
// `text` is the content of `name`. Errors: missing #version, unreadable includes, include cycles.
Result<ShaderSource> preprocess_shader(const std::string& name, const std::string& text,
                                       const std::vector<std::string>& defines,
                                       const ShaderReader& read = read_shader_file);

// Turns the first error of a driver info log into "file:line: message" using source-string
// numbers (Mesa "0:12(3): error: ...", NVIDIA "0(12) : error C0000: ...",
// AMD "ERROR: 0:12: ..."); the log's first line unchanged when it has no position.
std::string format_shader_log(const std::string& log, const std::vector<std::string>& files);

// The following need a current GL context.
// Compiles one stage (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER); returns the shader object.
Result<unsigned> compile_shader(unsigned stage, const ShaderSource& source);
// Links a program from compiled stages (which it detaches but does not delete).
Result<unsigned> link_program(const std::vector<unsigned>& shaders, const std::string& label);
// Reads, preprocesses and compiles vertex + fragment files into a program.
Result<unsigned> build_program(const std::string& vertex_file, const std::string& fragment_file,
                               const std::vector<std::string>& defines);

}  // namespace relief::gl
