#!/usr/bin/env bash
# Checks that every C++ source the repository tracks is formatted as .clang-format says
# (clang-format 14, --dry-run --Werror): prints each file that differs and fails.
# Usage: check-format.sh [FILE...]; without files, every tracked .h/.cpp (a git checkout; outside
# one, every .h/.cpp under the source folders). Fix with: clang-format -i FILE.
# check-format.sh --self-test: a misformatted file written to a temporary folder must be refused.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--self-test" ]; then
  d=$(mktemp -d)
  trap 'rm -rf "$d"' EXIT
  printf 'int  misformatted( ){return 1;}\n' >"$d/misformatted.cpp"
  if out=$(bash "$0" "$d/misformatted.cpp" 2>&1); then
    echo "check-format: self-test: a misformatted file was accepted" >&2
    exit 1
  fi
  echo "$out"
  exit 0
fi
cf=$(command -v clang-format-14 || command -v clang-format || true)
if [ -z "$cf" ]; then
  echo "check-format: clang-format not found (scripts/install-deps.sh installs clang-format-14)" >&2
  exit 1
fi
if [ $# -gt 0 ]; then
  files=("$@")
elif git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.h' '*.cpp' ':!tests/tools/*')
else
  mapfile -t files < <(find apps bake base bench builtin cmake examples gl plugins rasterizer render scene \
                         shaders_cpp sweep tests -path tests/tools -prune -o \
                         \( -name '*.h' -o -name '*.cpp' \) -print | sort)
fi
bad=0
for f in "${files[@]}"; do
  if ! "$cf" --dry-run --Werror "$f" >/dev/null 2>&1; then
    echo "check-format: $f differs from .clang-format (clang-format -i $f)" >&2
    bad=1
  fi
done
echo "check-format: ${#files[@]} files checked"
exit $bad
