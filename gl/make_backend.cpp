// make_backend (gl/gl_backend.h): the one place a backend is chosen by name. Compiled in GL and
// CPU-only builds alike (in the latter make_gl_backend says the build has no GL).
#include "gl/gl_backend.h"

namespace relief {

Result<std::unique_ptr<Backend>> make_backend(const std::string& name,
                                              const BackendConfig& config) {
  // threads apply to the CPU backend; llvmpipe takes LP_NUM_THREADS from the environment.
  if (name == "cpu") return make_cpu_backend(config);
  if (name == "gl") return make_gl_backend(config);
  return Status::usage("--backend: expected cpu or gl, got '" + name + "'");
}

}  // namespace relief
