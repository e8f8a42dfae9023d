#include "apps/version.h"

#include "base/simd.h"
#include "relief_build_info.h"  // RELIEF_GIT_COMMIT, generated (cmake/relief_version.cmake)

#ifndef RELIEF_VERSION
#define RELIEF_VERSION "unknown"
#endif
#ifndef RELIEF_BUILD_TYPE
#define RELIEF_BUILD_TYPE "unknown"
#endif
#ifndef RELIEF_HAVE_GL  // 0 in a build without the GL backend
#define RELIEF_HAVE_GL 1
#endif

namespace relief::cli {

BuildInfo build_info() {
  BuildInfo b;
  b.version = RELIEF_VERSION;
  b.commit = RELIEF_GIT_COMMIT;
  b.build_type = *RELIEF_BUILD_TYPE ? RELIEF_BUILD_TYPE : "none";
#if defined(__clang__)
  b.compiler = "Clang " __clang_version__;
#elif defined(__GNUC__)
  b.compiler = "GCC " __VERSION__;
#else
  b.compiler = "unknown";
#endif
  b.simd = simd_level_name(simd_level());
  b.simd_supported = simd_level_name(simd_supported());
  b.backends = {"cpu"};
  if (RELIEF_HAVE_GL) b.backends.push_back("gl");
  return b;
}

nlohmann::json build_info_json() {
  const BuildInfo b = build_info();
  return {{"version", b.version},   {"commit", b.commit}, {"build_type", b.build_type},
          {"compiler", b.compiler}, {"simd", b.simd},     {"simd_supported", b.simd_supported},
          {"backends", b.backends}};
}

std::string build_info_text() {
  const BuildInfo b = build_info();
  std::string backends;
  for (const std::string& s : b.backends) backends += (backends.empty() ? "" : ", ") + s;
  std::string simd = b.simd;
  if (b.simd != b.simd_supported) simd += " (this CPU has " + b.simd_supported + "; RELIEF_SIMD)";
  return "relief " + b.version + "\n" + "commit:     " + b.commit + "\n" +
         "build type: " + b.build_type + "\n" + "compiler:   " + b.compiler + "\n" +
         "simd:       " + simd + "\n" + "backends:   " + backends + "\n";
}

}  // namespace relief::cli
