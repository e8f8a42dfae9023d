# Sourced by scripts/ci-sanitizers.sh and scripts/ci-fuzz.sh: one configuration for the clang
# sanitizer builds, so the ASan + UBSan test build and the libFuzzer build can share a folder
# (.ci/run builds the libraries once for both). clang-14 rather than GCC 12: GCC with
# -fsanitize=address,undefined at -O1 needed over 15 minutes for a quarter of the plugins on 2
# cores (their many lane-type x effect instantiations); clang builds the whole tree in about 4.
# -O1 -g1 keeps the build short with line numbers in reports; -fno-sanitize-recover=all makes any
# report fatal.
CXX=${SANITIZER_CXX:-clang++-14}
command -v "$CXX" >/dev/null || { echo "$0: $CXX not found (scripts/install-deps.sh installs it)"; exit 1; }

# configure_sanitized DIR SANITIZERS: SANITIZERS for -fsanitize= (address,undefined | thread; with
# fuzzer-no-link the libFuzzer targets can be built in the same folder).
configure_sanitized() {
  cmake -S . -B "$1" -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="-fno-sanitize-recover=all -DRELIEF_NO_FLATTEN" \
    -DRELIEF_SANITIZE="$2" -DRELIEF_BUILD_FUZZ="$([[ $2 == *fuzzer* ]] && echo ON || echo OFF)" \
    -DRELIEF_BUILD_BENCH=OFF -DRELIEF_HWY_DISABLED_TARGETS="HWY_SSSE3|HWY_SSE4|HWY_AVX3" >/dev/null
}
