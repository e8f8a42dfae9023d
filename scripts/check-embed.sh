#!/usr/bin/env bash
# Installs relief from BUILD into a temporary prefix, builds examples/embed against the installed
# CMake package (find_package(relief)) and checks that its image equals the CLI's bit for bit.
# Usage: scripts/check-embed.sh BUILD_DIR   (run by ctest as embed.InstalledPackage)
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "$1" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
quiet() { "$@" > "$work/step.log" 2>&1 || { cat "$work/step.log"; echo "failed: $*" >&2; exit 1; }; }
quiet cmake --install "$build" --prefix "$work/prefix"
quiet cmake -S "$src/examples/embed" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release
quiet cmake --build "$work/build"
"$work/build/embed" "$src/scenes/pattern.gltf" "$work/embed.exr"
"$work/prefix/bin/relief" render "$src/scenes/pattern.gltf" --size 800x600 -o "$work/cli.exr" > /dev/null
"$work/prefix/bin/relief" compare "$work/embed.exr" "$work/cli.exr" --linear --max-rmse 0 --threshold 0 --max-over 0
