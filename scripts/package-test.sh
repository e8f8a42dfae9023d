#!/usr/bin/env bash
# Builds the Debian packages from BUILD with CPack, unpacks them with `dpkg -x` into a scratch root
# (no dpkg database, no root-owned paths outside a temporary folder) and checks the installed
# files: the package metadata, the man page, the CLI rendering on the CPU (and on the GL backend
# where this machine has one) with the source tree hidden, each image equal to the build's, and
# examples/embed built against the packaged CMake package.
# Usage: scripts/package-test.sh [BUILD_DIR]   (default ./build; the relief and relief_man
# targets must be built: `cmake --build build --target relief relief_man`). Exit 0 pass, 1 fail.
set -euo pipefail
src="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$src/build}" && pwd)"
t0=$SECONDS
say() { echo "package-test: $*"; }
fail() { echo "package-test: FAIL: $*" >&2; exit 1; }

work="$(mktemp -d /tmp/relief-package.XXXXXX)"
trap 'rm -rf "$work"' EXIT
quiet() { "$@" > "$work/step.log" 2>&1 || { cat "$work/step.log"; fail "$*"; }; }

[ -x "$build/bin/relief" ] || fail "$build/bin/relief: not built"
[ -f "$build/man/relief.1.gz" ] || fail "$build/man/relief.1.gz: not built (target relief_man)"
version="$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")"
arch="$(dpkg --print-architecture)"

# --- the packages
(cd "$build" && quiet cpack -G DEB -B "$work/pkg")
bin_deb="$work/pkg/relief_${version}_${arch}.deb"
dev_deb="$work/pkg/relief-dev_${version}_${arch}.deb"
for deb in "$bin_deb" "$dev_deb"; do [ -f "$deb" ] || fail "cpack made no $(basename "$deb")"; done
depends="$(dpkg-deb -f "$bin_deb" Depends)"
for lib in libopenimageio libepoxy libstdc++6; do
  [[ "$depends" == *"$lib"* ]] || fail "relief's Depends lacks $lib: $depends"
done
dpkg-deb -c "$bin_deb" | awk '{print $6}' | sed 's|^\./|/|' > "$work/bin.list"
dpkg-deb -c "$dev_deb" | awk '{print $6}' | sed 's|^\./|/|' > "$work/dev.list"
for f in /usr/bin/relief /usr/share/man/man1/relief.1.gz /usr/share/doc/relief/README.md \
  /usr/share/doc/relief/packaging.md /usr/share/doc/relief/examples/slurm/render-array.sh; do
  grep -qx "$f" "$work/bin.list" || fail "relief .deb lacks $f"
done
for f in /usr/lib/cmake/relief/reliefConfig.cmake /usr/lib/librelief_render.a \
  /usr/include/relief/render/render.h /usr/include/relief/gl/gl_backend.h; do
  grep -qE "^${f//./\\.}$" "$work/dev.list" || fail "relief-dev .deb lacks $f"
done
say "$(basename "$bin_deb") ($(du -k "$bin_deb" | cut -f1) KiB, Depends: $depends)"
say "$(basename "$dev_deb") ($(du -k "$dev_deb" | cut -f1) KiB, $(grep -c '\.h$' "$work/dev.list") headers)"

root="$work/root"
dpkg -x "$bin_deb" "$root"
dpkg -x "$dev_deb" "$root"
relief="$root/usr/bin/relief"

# --- the man page: every subcommand of `relief --help` has its section, and groff reads it cleanly
man="$(zcat "$root/usr/share/man/man1/relief.1.gz")"
for sub in $("$relief" --help | sed -n '/^Subcommands:/,$p' | sed -n 's/^  \([a-z][a-z0-9_-]*\) .*/\1/p'); do
  grep -qx "\.SS relief $sub" <<< "$man" || fail "man page has no section for 'relief $sub'"
done
if command -v groff > /dev/null; then
  warnings="$(groff -man -Tutf8 -ww -z <<< "$man" 2>&1)"
  [ -z "$warnings" ] || fail "groff warns on relief.1: $warnings"
fi

# --- the installed CLI renders what the build renders, bit for bit. The references come from the
# build; the installed binary then runs with the source tree hidden (a tmpfs over it in a private
# mount namespace) where unshare allows, so it must find everything (plugins, GL shaders) in itself.
gl=0
info="$("$build/bin/relief" info 2> /dev/null || true)"  # read whole: see slurm-test.sh
grep -q '^gl: available' <<< "$info" && gl=1
"$build/bin/relief" render pattern --size 320x240 -o "$work/ref_cpu.png" > /dev/null
[ "$gl" = 1 ] && "$build/bin/relief" render pattern --size 320x240 --backend gl \
  -o "$work/ref_gl.png" > /dev/null
cat > "$work/installed.sh" << EOF
set -e
cd "$work"
"$relief" render pattern --size 320x240 -o "$work/pkg_cpu.png" > /dev/null
"$relief" info > "$work/info.txt" 2>&1
if [ "$gl" = 1 ]; then
  "$relief" render pattern --size 320x240 --backend gl -o "$work/pkg_gl.png" > /dev/null
fi
EOF
hidden=0
if unshare -m true 2> /dev/null; then
  unshare -m bash -c "mount -t tmpfs relief-hidden '$src' && bash '$work/installed.sh'" ||
    fail "the installed relief failed with the source tree hidden"
  hidden=1
else
  bash "$work/installed.sh" || fail "the installed relief failed"
fi
cmp -s "$work/pkg_cpu.png" "$work/ref_cpu.png" || fail "installed relief's CPU image differs"
where="CPU"
if [ "$gl" = 1 ]; then
  cmp -s "$work/pkg_gl.png" "$work/ref_gl.png" || fail "installed relief's GL image differs"
  if [ "$hidden" = 1 ]; then
    grep -q 'shaders: *embedded' "$work/info.txt" ||
      fail "installed relief does not read its embedded shaders: $(grep shaders: "$work/info.txt")"
  fi
  where="CPU and GL"
fi
say "installed relief renders pattern on $where like the build (cmp)$([ "$hidden" = 1 ] &&
  echo ', source tree hidden')"

# --- the packaged CMake package: examples/embed against the unpacked /usr, image equal to the CLI's
quiet cmake -S "$src/examples/embed" -B "$work/embed" -DCMAKE_PREFIX_PATH="$root/usr" \
  -DCMAKE_BUILD_TYPE=Release
grep -q "relief_DIR:PATH=$root/usr/lib/cmake/relief" "$work/embed/CMakeCache.txt" ||
  fail "examples/embed did not find the packaged reliefConfig.cmake"
quiet cmake --build "$work/embed"
"$work/embed/embed" "$src/scenes/pattern.gltf" "$work/embed.exr" > /dev/null
"$relief" render "$src/scenes/pattern.gltf" --size 800x600 -o "$work/cli.exr" > /dev/null
quiet "$relief" compare "$work/embed.exr" "$work/cli.exr" --linear --max-rmse 0 --threshold 0 \
  --max-over 0
say "examples/embed built against the packaged CMake package renders like the CLI"
say "PASS in $((SECONDS - t0)) s"
