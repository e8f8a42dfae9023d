// relief_gl in a CPU-only build (cmake -DRELIEF_GL=OFF): the gl/ interface with no OpenGL, EGL or
// libepoxy behind it. Every entry point that would make a context fails with one line naming the
// build option, so `relief render --backend gl` and `relief bench --backend gl` say why at once
// and everything else (the CPU backend, `relief info`) works as in a full build.
#include <string>
#include <vector>

#include "gl/appendix_relief.h"
#include "gl/context.h"
#include "gl/gl_backend.h"
#include "gl/shader.h"

namespace relief {
namespace {

// For `--backend gl`, and for `relief info`'s "gl: unavailable (...)".
const char kNoGlBackend[] =
    "this build has no GL backend (configured with -DRELIEF_GL=OFF); use --backend cpu";
const char kNoGl[] = "not in this build, configured with -DRELIEF_GL=OFF";

}  // namespace

Result<std::unique_ptr<Backend>> make_gl_backend(const BackendConfig&) {
  return Status::usage(std::string("--backend gl: ") + kNoGlBackend);
}

std::string gl_twin_file(const std::string& plugin_name) {
  return plugin_name + ".frag";
}
bool gl_has_twin(const std::string&) {
  return false;
}

namespace gl {

Result<std::vector<EglDevice>> list_egl_devices() {
  return Status::error(kNoGl);
}

Result<std::unique_ptr<Context>> Context::create(int) {
  return Status::error(kNoGl);
}
Context::~Context() = default;
Status Context::make_current() {
  return Status::error(kNoGl);
}
bool Context::has_extension(const char*) const {
  return false;
}

Result<std::string> read_shader_file(const std::string& name) {
  return Status::error("shader file \"" + name + "\": " + kNoGl);
}
bool shader_file_exists(const std::string&) {
  return false;
}
std::vector<std::string> list_shader_files() {
  return {};
}
std::string shader_source_location() {
  return "none (a CPU-only build, -DRELIEF_GL=OFF)";
}

Result<ShaderSource> preprocess_shader(const std::string& name, const std::string&,
                                       const std::vector<std::string>&, const ShaderReader&) {
  return Status::error(name + ": " + kNoGl);
}
std::string format_shader_log(const std::string& log, const std::vector<std::string>&) {
  return log.substr(0, log.find('\n'));
}
Result<unsigned> compile_shader(unsigned, const ShaderSource&) {
  return Status::error(kNoGl);
}
Result<unsigned> link_program(const std::vector<unsigned>&, const std::string&) {
  return Status::error(kNoGl);
}
Result<unsigned> build_program(const std::string&, const std::string&,
                               const std::vector<std::string>&) {
  return Status::error(kNoGl);
}

struct AppendixRelief::State {};
Result<std::unique_ptr<AppendixRelief>> AppendixRelief::create(int) {
  return Status::error(kNoGl);
}
AppendixRelief::~AppendixRelief() = default;
Status AppendixRelief::prepare(const Scene&, int, int, int, int) {
  return Status::error(kNoGl);
}
Result<double> AppendixRelief::draw() {
  return Status::error(kNoGl);
}
Status AppendixRelief::draw_hits(Image&, Image&) {
  return Status::error(kNoGl);
}
std::string AppendixRelief::device() const {
  return "none";
}

}  // namespace gl
}  // namespace relief
