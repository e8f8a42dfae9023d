#!/usr/bin/env bash
# No function in the library folders longer than a limit (issue 25: 120 lines, tests excepted): a
# function this long holds more than one idea, and the next reader pays for it.
# A function is a brace block opened at namespace or class scope after a `)` (optionally followed
# by const, noexcept, override, final, a trailing return type or a constructor's initializers);
# lambdas and blocks inside it count towards it. Its length is the lines from its `{` to its `}`.
# Comments, strings and character literals are skipped, so braces in them do not count.
# Usage: check-function-length.sh [REPO_DIR] [LIMIT]   (prints the five longest, fails over LIMIT)
#        check-function-length.sh --self-test           (a fixture with one function over the
#                                                         limit, the check must refuse it)
set -euo pipefail
if [ "${1:-}" = "--self-test" ]; then
  d=$(mktemp -d)
  trap 'rm -rf "$d"' EXIT
  mkdir -p "$d/render"
  {
    echo 'namespace relief {'
    echo 'const int kTable[] = {'  # a long initializer is not a function
    for i in $(seq 1 30); do echo "  $i,"; done
    echo '};'
    echo 'struct Short {'  # a long class of short functions passes
    for i in $(seq 1 10); do printf '  int f%d() const {\n    return %d;\n  }\n' "$i" "$i"; done
    echo '};'
    echo 'int long_one(int x) {'
    for i in $(seq 1 25); do echo "  if (x > $i) { x -= 1; }  // { not a brace"; done
    echo '  auto g = [&](int y) { return y + x; };'
    echo '  return g(x);'
    echo '}'
    echo '}  // namespace relief'
  } >"$d/render/fixture.cpp"
  if out=$(bash "$0" "$d" 20 2>&1); then
    echo "check-function-length: self-test: a 29-line function passed a limit of 20" >&2
    echo "$out" >&2
    exit 1
  fi
  echo "$out"
  exit 0
fi
root="${1:-$(dirname "$0")/..}"
limit="${2:-120}"
cd "$root"
python3 - "$limit" base rasterizer shaders_cpp plugins bake scene builtin render gl sweep apps <<'PY'
import os, re, sys

limit = int(sys.argv[1])
folders = [f for f in sys.argv[2:] if os.path.isdir(f)]


def strip(text):
    """The text with comments, strings and char literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i)); i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j])); i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j])); i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (j + 1 - i)); i = j + 1
        elif c == "#" and (i == 0 or text[i - 1] == "\n"):  # preprocessor line
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i)); i = j
        else:
            out.append(c); i += 1
    return "".join(out)


QUAL = r"(\s*(const|noexcept|override|final|mutable|&|&&|->\s*[\w:<>,\s\*&]+))*"
FUNC = re.compile(r"\)" + QUAL + r"\s*$|\)\s*:\s*[\w:]+[\(\{]")
SCOPE = re.compile(r"^\s*(template\s*<.*>\s*)?(namespace|class|struct|union|extern)\b")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else)\b")

found = []
for folder in folders:
    for name in sorted(os.listdir(folder)):
        if not name.endswith((".h", ".cpp")):
            continue
        path = os.path.join(folder, name)
        text = strip(open(path, encoding="utf-8", errors="replace").read())
        stack = []  # (kind, line, name)
        header_start = 0
        line = 1
        for i, c in enumerate(text):
            if c == "\n":
                line += 1
            elif c in ";":
                header_start = i + 1
            elif c == "{":
                header = text[header_start:i]
                outer = all(k == "scope" for k, _, _ in stack)
                if SCOPE.match(header) and outer:
                    kind = "scope"
                elif outer and "(" in header and not header.rstrip().endswith("=") and \
                        not CONTROL.match(header) and FUNC.search(header):
                    kind = "function"
                else:
                    kind = "block"
                sig = " ".join(header.split())
                stack.append((kind, line, sig))
                header_start = i + 1
            elif c == "}":
                if stack:
                    kind, start, sig = stack.pop()
                    if kind == "function":
                        m = re.search(r"([\w:~]+)\s*\(", sig)
                        found.append((line - start + 1, path, start, m.group(1) if m else sig[:40]))
                header_start = i + 1

found.sort(reverse=True)
for length, path, start, fn in found[:5]:
    print(f"{length:5d} lines  {path}:{start}  {fn}")
bad = [f for f in found if f[0] > limit]
for length, path, start, fn in bad:
    print(f"check-function-length: {path}:{start} {fn} is {length} lines (limit {limit})",
          file=sys.stderr)
sys.exit(1 if bad else 0)
PY
