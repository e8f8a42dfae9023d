#!/usr/bin/env bash
# Sanitizer runs for CI (issue 10), clang-14 (scripts/clang-sanitized.sh): an ASan + UBSan build
# running every test but the GL backend's (test_gl and test_gl_frames: Mesa's llvmpipe is not
# instrumented and its JIT under ASan is the slow part) and the installed-package test; and a
# ThreadSanitizer build running test_rasterizer and test_frames (the thread pool, tiles,
# determinism across thread counts and tile sizes, recycled frames, shadow passes: every frame of
# a built-in scene) but their file-loading suites (hostile input, glTF decoding: no threads of
# ours, and ASan runs them) and the sRGB table's exhaustive check (one thread, 2^30 floats);
# test_render's suites (validation, metrics, materials, plugin properties) render through the
# same pool and tiles as test_frames and run under ASan. Neither runs the script tests (layers,
# format, style, docs, link, simd.*: they read sources or compile probes, which no sanitizer
# instruments; the Release run has them).
# The ASan folder is configured with fuzzer-no-link too, so scripts/ci-fuzz.sh build-ci-asan reuses
# its libraries. Any report fails the run (halt_on_error). Each step prints its wall time.
# Usage: scripts/ci-sanitizers.sh [asan|tsan|all]   (build folders build-ci-asan, build-ci-tsan)
set -euo pipefail
cd "$(dirname "$0")/.."
WHAT=${1:-all}
JOBS=${JOBS:-$(nproc)}
PREFIX=${SANITIZER_BUILD_PREFIX:-build-ci}
source scripts/clang-sanitized.sh
# Tests of a program the step did not build, and the script tests.
NOT_HERE='_NOT_BUILT|^(layers|format|style|docs|link|simd)\.'

step() {  # step NAME COMMAND...: runs and prints the wall time
  local name=$1 t0
  shift
  t0=$(date +%s)
  "$@"
  echo "ci-sanitizers: $name $(( $(date +%s) - t0 )) s"
}

if [[ $WHAT == asan || $WHAT == all ]]; then
  B=$PREFIX-asan
  step "asan configure" configure_sanitized "$B" fuzzer-no-link,address,undefined
  step "asan build" cmake --build "$B" -j "$JOBS" --target relief relief_test_plugin \
    test_rasterizer test_shaders_cpp test_plugins test_bake test_scene test_builtin test_render \
    test_frames test_sweep test_apps
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
  # OpenImageIO 2.4 loses the string its ImageInput::geterror assigns (tests/fuzz/lsan.supp says
  # why); the tests reach it now that image errors come from the ImageInput, as the fuzz targets do.
  export LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
  step "asan tests" ctest --test-dir "$B" -j "$JOBS" --output-on-failure -E "$NOT_HERE"
  unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS
fi

if [[ $WHAT == tsan || $WHAT == all ]]; then
  B=$PREFIX-tsan
  step "tsan configure" configure_sanitized "$B" thread
  step "tsan build" cmake --build "$B" -j "$JOBS" --target relief test_rasterizer test_frames
  export TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1
  step "tsan tests" ctest --test-dir "$B" -j "$JOBS" --output-on-failure \
    -E "$NOT_HERE|^(Hostile[A-Za-z]*|Gltf[A-Za-z]*|SupportTable|ExtensionWarnings|Validate|DualBake|SrgbBytes)\."
  unset TSAN_OPTIONS
fi
