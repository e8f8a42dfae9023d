#!/usr/bin/env bash
# The layers of DESIGN.md, enforced: every `#include "FOLDER/..."` in a library folder must name
# that folder or one of the folders below it. The build runs this (target relief_layers), so a
# wrong-direction include fails `make`. Layers, bottom up:
#   base -> rasterizer -> shaders_cpp -> {plugins, bake} -> scene -> {builtin, render} -> gl
#   -> sweep -> apps
# (a folder may include any folder listed as below it here). Exceptions are listed file by file
# with the work that removes them; a new one is a design change, not a quick fix. File names are
# unique across the library folders.
# The compiler enforces the same table through per-library include roots and link lists
# (CMakeLists.txt, ctest layers.*); this check stays for what those cannot say: single headers
# from a layer otherwise out of sight (allowed_headers) and the exceptions, which today widen
# relief_scene's links, and it names the file and the rule in one line before anything compiles.
# Usage: check-layers.sh [REPO_DIR]; check-layers.sh --self-test (a tree with a kernel header that
# includes render/, then one with two shadow_map.h: the check must refuse both).
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
  # Two folders with a file of the same name must be refused as well.
  rm "$d/shaders_cpp/kernel.h"
  touch "$d/shaders_cpp/shadow_map.h" "$d/render/shadow_map.h"
  if out=$(bash "$0" "$d" 2>&1); then
    echo "check-layers: self-test: two shadow_map.h were accepted" >&2
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
# No two library folders hold a file of the same name (a header's name says which one it is).
dupes=$(for folder in "${!allowed[@]}"; do
  for f in "$folder"/*.h "$folder"/*.cpp; do
    [ -e "$f" ] && basename "$f"
  done
done | sort | uniq -d || true)
for name in $dupes; do
  echo "check-layers: $name is in more than one library folder: rename one" >&2
  bad=1
done
exit $bad
