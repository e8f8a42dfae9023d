// Whether this test program is a sanitizer build (RELIEF_SANITIZE: scripts/ci-sanitizers.sh).
// There the heaviest brute-force comparisons run on their smaller inputs only: ASan, UBSan and
// TSan check memory, undefined behaviour and races, which the smaller inputs reach on the same
// code paths; the Release suite (`make test`) runs the full sizes and holds the accuracy bounds.
#pragma once

namespace relief::test {

#ifdef RELIEF_SANITIZED_BUILD
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif

// `full` in a Release build, `reduced` under a sanitizer.
inline constexpr int sanitized_or(int full, int reduced) {
  return kSanitizedBuild ? reduced : full;
}

}  // namespace relief::test
