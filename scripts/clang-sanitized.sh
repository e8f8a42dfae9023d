# Sourced by scripts/ci-sanitizers.sh and scripts/ci-fuzz.sh: one configuration for the clang
# sanitizer builds, so the ASan + UBSan test build and the libFuzzer build can share a folder
# (.ci/run builds the libraries once for both). clang-14 rather than GCC 12: GCC with
# -fsanitize=address,undefined at -O1 needed over 15 minutes for a quarter of the plugins on 2
# cores (their many lane-type x effect instantiations); clang builds the whole tree in about 4.
# -O1 -g1 keeps the build short with line numbers in reports; -fno-sanitize-recover=all makes any
# report fatal.
CXX=${SANITIZER_CXX:-clang++-14}
command -v "$CXX" >/dev/null || { echo "$0: $CXX not found (scripts/install-deps.sh installs it)"; exit 1; }

# One SIMD target in the sanitizer builds where the CPU runs Highway's AVX2 target (AVX2, BMI2, FMA,
# F16C): -march=haswell makes AVX2 the static target and HWY_COMPILE_ONLY_STATIC compiles it alone,
# so each per-target file (the plugins' kernels, the samplers, the tile traversal) is compiled once
# instead of twice (EMU128 and AVX2; AVX3 is off here already): about half of each such file's
# compile. The sanitizers check the AVX2 code these builds ran before (the CPU's best level with
# AVX3 off); the Release suite checks every level bit for bit against the baseline. Elsewhere both
# targets, as before. -ffp-contract=off (CMakeLists.txt) keeps FMA out of the arithmetic.
SANITIZER_SIMD_FLAGS=""
if grep -qw avx2 /proc/cpuinfo && grep -qw bmi2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo &&
    grep -qw f16c /proc/cpuinfo; then
  SANITIZER_SIMD_FLAGS="-march=haswell -DHWY_COMPILE_ONLY_STATIC=1"
fi

# configure_sanitized DIR SANITIZERS: SANITIZERS for -fsanitize= (address,undefined | thread; with
# fuzzer-no-link the libFuzzer targets can be built in the same folder).
configure_sanitized() {
  cmake -S . -B "$1" -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS="-fno-sanitize-recover=all -DRELIEF_NO_FLATTEN $SANITIZER_SIMD_FLAGS" \
    -DRELIEF_SANITIZE="$2" -DRELIEF_BUILD_FUZZ="$([[ $2 == *fuzzer* ]] && echo ON || echo OFF)" \
    -DRELIEF_BUILD_BENCH=OFF -DRELIEF_HWY_DISABLED_TARGETS="HWY_SSSE3|HWY_SSE4|HWY_AVX3" >/dev/null
}
