#!/usr/bin/env bash
# Reduced sanitizer runs for CI (issue 10): an ASan + UBSan build of the libraries and the
# test programs of rasterizer, shaders_cpp, plugins, scene and render, whose tests all run; and a
# ThreadSanitizer build of test_rasterizer and test_render, running the tests that use the thread
# pool (pipeline, determinism across thread counts and tile sizes, recycled frames). -O1 -g1
# keeps the build short with line numbers in the reports; any report fails the run
# (-fno-sanitize-recover, halt_on_error). Each step prints its wall time.
# Usage: scripts/ci-sanitizers.sh [asan|tsan|all]   (build folders build-ci-asan, build-ci-tsan)
set -euo pipefail
cd "$(dirname "$0")/.."
WHAT=${1:-all}
JOBS=${JOBS:-$(nproc)}
PREFIX=${SANITIZER_BUILD_PREFIX:-build-ci}
# clang: GCC 12 with -fsanitize=address,undefined at -O1 needed over 15 minutes for a quarter of
# the plugins on 2 cores (their many lane-type x effect instantiations); clang-14 builds the same
# files in a few minutes.
CXX=${SANITIZER_CXX:-clang++-14}
command -v "$CXX" >/dev/null || { echo "ci-sanitizers: $CXX not found (scripts/install-deps.sh installs it)"; exit 1; }

step() {  # step NAME COMMAND...: runs and prints the wall time
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  echo "ci-sanitizers: $name $(( $(date +%s) - t0 )) s"
}

configure() {  # configure DIR SANITIZERS
  cmake -S . -B "$1" -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DRELIEF_SANITIZE="$2" -DCMAKE_CXX_FLAGS="-fno-sanitize-recover=all" \
    -DRELIEF_BUILD_BENCH=OFF >/dev/null
}

if [[ $WHAT == asan || $WHAT == all ]]; then
  B=$PREFIX-asan
  step "asan configure" configure "$B" address,undefined
  step "asan build" cmake --build "$B" -j "$JOBS" --target relief relief_test_plugin \
    test_rasterizer test_shaders_cpp test_plugins test_scene test_render
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  step "asan tests" ctest --test-dir "$B" -j "$JOBS" --output-on-failure -E '_NOT_BUILT'
  unset ASAN_OPTIONS UBSAN_OPTIONS
fi

if [[ $WHAT == tsan || $WHAT == all ]]; then
  B=$PREFIX-tsan
  step "tsan configure" configure "$B" thread
  step "tsan build" cmake --build "$B" -j "$JOBS" --target relief test_rasterizer test_render
  export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
  step "tsan tests" ctest --test-dir "$B" -j "$JOBS" --output-on-failure -E '_NOT_BUILT' \
    -R '^(Pipeline|Determinism|Recycle)\.'
  unset TSAN_OPTIONS
fi
