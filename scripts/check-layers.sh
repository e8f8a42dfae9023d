#!/usr/bin/env bash
# The layers of DESIGN.md, enforced: every `#include "FOLDER/..."` in a library folder must name
# that folder or one of the folders below it. The build runs this (target relief_layers), so a
# wrong-direction include fails `make`. Layers, bottom up:
#   base -> rasterizer -> shaders_cpp -> {plugins, bake} -> scene -> {builtin, render} -> gl
#   -> sweep -> apps
# (a folder may include any folder listed as below it here). Exceptions are listed file by file
# with the work that removes them; a new one is a design change, not a quick fix.
# Usage: check-layers.sh [REPO_DIR]; check-layers.sh --self-test (a tree with a kernel header that
# includes render/: the check must refuse it).
set -euo pipefail
if [ "${1:-}" = "--self-test" ]; then
  d=$(mktemp -d)
  trap 'rm -rf "$d"' EXIT
  mkdir -p "$d/shaders_cpp" "$d/render"
  echo '#include "render/render.h"' > "$d/shaders_cpp/kernel.h"
  if out=$(bash "$0" "$d" 2>&1); then
    echo "check-layers: self-test: a kernel including render/ was accepted" >&2
    exit 1
  fi
  echo "$out"
  exit 0
fi
cd "${1:-$(dirname "$0")/..}"

declare -A allowed=(
  [base]="base"
  [rasterizer]="base rasterizer"
  [shaders_cpp]="base rasterizer shaders_cpp"
  [plugins]="base rasterizer shaders_cpp plugins"
  [bake]="base rasterizer shaders_cpp bake"
  [scene]="base rasterizer scene"
  [builtin]="base rasterizer shaders_cpp plugins bake scene builtin"
  [render]="base rasterizer shaders_cpp plugins bake scene render"
  [gl]="base rasterizer shaders_cpp plugins bake scene render gl"
  [sweep]="base rasterizer shaders_cpp plugins bake scene builtin render gl sweep"
  [apps]="base rasterizer shaders_cpp plugins bake scene builtin render gl sweep apps"
)
# Single headers a folder may include from a layer it may not otherwise see: the scene model
# shares the uniforms' vocabulary (alpha modes, light types, uv maps, limits) with the kernels,
# plain data with no code behind it.
declare -A allowed_headers=(
  [scene]="shaders_cpp/uniforms.h"
)
# Known exceptions, file by file ("FILE INCLUDED"): none. (Issue 25 removed the last three: the
# scene model no longer includes the plugin ABI or the registry, nor bakes normal maps while
# loading; render/validate.h checks techniques and parameters, render/derived_maps.h derives the
# normal maps.)
exceptions=()

bad=0
for folder in "${!allowed[@]}"; do
  [ -d "$folder" ] || continue
  for f in "$folder"/*.h "$folder"/*.cpp; do
    [ -e "$f" ] || continue
    while IFS= read -r inc; do
      dep=${inc%%/*}
      [ -d "$dep" ] || continue  # a generated or system header
      case " ${allowed[$folder]} " in *" $dep "*) continue ;; esac
      case " ${allowed_headers[$folder]:-} " in *" $inc "*) continue ;; esac
      ok=0
      for e in "${exceptions[@]+"${exceptions[@]}"}"; do [ "$e" = "$f $inc" ] && ok=1; done
      [ $ok -eq 1 ] && continue
      echo "check-layers: $f includes $inc: $folder/ may include only ${allowed[$folder]}" >&2
      bad=1
    done < <(sed -n 's/^#include "\([a-z_]*\/[^"]*\)".*/\1/p' "$f")
  done
done
exit $bad
