#!/usr/bin/env bash
# Checks the per-target SIMD code (base/simd.h): every file that opens a Highway per-target region
# (HWY_BEFORE_NAMESPACE) must define no friend function inside a class. GCC compiles such a friend,
# and an implicitly defined constructor, without the target options of the region around it: it
# becomes baseline code with the baseline calling convention, called from AVX2 or AVX-512 code
# that passes its vectors in registers, and is wrong wherever the compiler does not inline it.
# (Constructors: a class whose default member initializers hold lane values declares its own.)
# Usage: check-per-target.sh [FILE...]; without files, every tracked .h/.cpp of the repository
# (a git checkout).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then
  # tests/tools/ holds the check's own bad fixture
  mapfile -t files < <(git ls-files '*.h' '*.cpp' ':!tests/tools/*')
else
  files=("$@")
fi
bad=0
checked=0
for f in "${files[@]}"; do
  grep -q 'HWY_BEFORE_NAMESPACE' "$f" || continue
  checked=$((checked + 1))
  # a friend declaration with a parameter list and a body on the line (not `friend X f(...);`)
  if grep -nE '^\s*friend\b.*\(.*\{' "$f"; then
    echo "check-per-target: $f: a friend function defined in a class in a per-target file" \
         "(define it at namespace scope; see shaders_cpp/lanes.h)" >&2
    bad=1
  fi
done
echo "check-per-target: $checked per-target files checked"
exit $bad
