// What this binary is: `relief --version`, `relief version`, and the "build" object of the JSON
// that `relief render --stats` and `relief bench --json` write.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace relief::cli {

struct BuildInfo {
  std::string version;         // the project version (CMakeLists.txt), e.g. "0.1.0"
  std::string commit;          // `git describe --always --dirty` at build time, or "unknown"
  std::string build_type;      // CMAKE_BUILD_TYPE / the configuration: Release, Debug, ...
  std::string compiler;        // e.g. "GCC 12.2.0"
  std::string simd;            // the SIMD path the kernels run now: "avx2" or "baseline" (SSE2)
  std::string simd_supported;  // the best path this CPU has
  std::vector<std::string> backends;  // compiled in: "cpu", "gl"
};

BuildInfo build_info();
// {"version", "commit", "build_type", "compiler", "simd", "simd_supported", "backends": [...]}.
nlohmann::json build_info_json();
// The lines `relief version` prints.
std::string build_info_text();

}  // namespace relief::cli
