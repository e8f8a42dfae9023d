#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang-14 + ASan + UBSan (scripts/clang-sanitized.sh)
# and runs each for FUZZ_SECONDS (default 60), JOBS (default nproc) at a time, from its seed
# corpus tests/fuzz/<target>/. Any crash, leak, sanitizer report or timeout fails the script;
# libFuzzer leaves the reproducer in
# $BUILD/crashes/. Usage: scripts/ci-fuzz.sh [build-dir]   (default build-fuzz; .ci/run passes
# build-ci-asan, configured the same way by scripts/ci-sanitizers.sh, so the libraries are built
# once for both).
# CI runs a fixed seed (FUZZ_SEED, default 1): the same binary, seed and corpus give the same
# sequence of inputs, so CI replays what was checked here (a faster machine goes a little further
# in the same sequence in its 60 s). FUZZ_SEED=0 picks a random seed (for exploring);
# FUZZ_RUNS caps the inputs per target (-1, the default: only the time limit).
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${1:-build-fuzz}
SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
SEED=${FUZZ_SEED:-1}
RUNS=${FUZZ_RUNS:--1}
JOBS=${JOBS:-$(nproc)}
TARGETS=(gltf gltf_struct image image_header cli plugin_schema)
SANITIZER_CXX=${FUZZ_CXX:-${SANITIZER_CXX:-clang++-14}}
source scripts/clang-sanitized.sh

t0=$(date +%s)
configure_sanitized "$BUILD" fuzzer-no-link,address,undefined
cmake --build "$BUILD" -j "$JOBS" --target "${TARGETS[@]/#/fuzz_}"
echo "ci-fuzz: build $(( $(date +%s) - t0 )) s"
[ "$SECONDS_PER_TARGET" -gt 0 ] || exit 0  # FUZZ_SECONDS=0: build only

mkdir -p "$BUILD/crashes"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan.supp
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# fuzz_one TARGET: runs one target for its time; prints its line; fails when it found something.
fuzz_one() {
  local t=$1 t1 work
  t1=$(date +%s)
  work="$BUILD/corpus/$t"  # new inputs go here; the seeds in the repo stay untouched
  mkdir -p "$work"
  local rc=0
  "$BUILD/bin/fuzz_$t" "$work" "tests/fuzz/$t" -max_total_time="$SECONDS_PER_TARGET" -seed="$SEED" -runs="$RUNS" \
      -timeout=10 -rss_limit_mb=4096 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$BUILD/crashes/$t-" >"$BUILD/fuzz_$t.log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "ci-fuzz: fuzz_$t FOUND A FAILURE (log $BUILD/fuzz_$t.log, input $BUILD/crashes/):"
    grep -m 20 -E "ERROR|SUMMARY|runtime error|#[0-9]+ " "$BUILD/fuzz_$t.log" || tail -20 "$BUILD/fuzz_$t.log"
  fi
  echo "ci-fuzz: fuzz_$t $(( $(date +%s) - t1 )) s, $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$BUILD/fuzz_$t.log" | grep -o '[0-9]*$' || echo '?') runs"
  return "$rc"
}
# JOBS targets at a time (each libFuzzer process runs on one core): the same time a target, a
# fraction of the wall time.
status=0
pids=()
for t in "${TARGETS[@]}"; do
  fuzz_one "$t" &
  pids+=($!)
  if [ "${#pids[@]}" -ge "$JOBS" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done
echo "ci-fuzz: total $(( $(date +%s) - t0 )) s"
exit $status
