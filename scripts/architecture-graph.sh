#!/usr/bin/env bash
# The library graph of docs/architecture.md, drawn from CMake's own (`cmake --graphviz`): each relief
# library and the relief libraries it links directly, bottom up. Configures the source tree with
# default options in a temporary folder (about a second; nothing is built).
# Usage: architecture-graph.sh          print the graph
#        architecture-graph.sh --check  fail when docs/architecture.md's copy differs (ctest
#                                       docs.ArchitectureGraphMatchesCMake)
#        architecture-graph.sh --write  replace docs/architecture.md's copy
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake -S . -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release --graphviz="$tmp/relief.dot" >"$tmp/log" 2>&1 ||
  { cat "$tmp/log" >&2; exit 1; }
python3 - "$tmp/relief.dot" >"$tmp/graph.txt" <<'PY'
import re, sys
dot = open(sys.argv[1]).read()
labels = dict(re.findall(r'"(node\d+)" \[ label = "([^"]+)"', dot))
deps = {}
for a, b in re.findall(r'"(node\d+)" -> "(node\d+)"', dot):
    la, lb = labels[a], labels[b]
    if la.startswith("relief_") and lb.startswith("relief_"):
        deps.setdefault(la, set()).add(lb)
        deps.setdefault(lb, set())
def below(lib, seen=None):
    seen = set() if seen is None else seen
    for d in deps[lib]:
        if d not in seen:
            seen.add(d)
            below(d, seen)
    return seen
order = sorted(deps, key=lambda l: (len(below(l)), l))
width = max(len(l) for l in order)
for lib in order:
    direct = sorted(deps[lib], key=lambda l: (-len(below(l)), l))
    print(f"{lib:<{width}}  -> {', '.join(direct) if direct else '(none)'}")
PY
doc=docs/architecture.md
begin='<!-- library graph: scripts/architecture-graph.sh --write -->'
end='<!-- end of library graph -->'
section() { sed -n "\|^$begin\$|,\|^$end\$|p" "$doc" | sed '1,2d;$d' | sed '$d'; }
case "${1:-}" in
  --check)
    if ! diff <(section) "$tmp/graph.txt" >"$tmp/diff"; then
      echo "architecture-graph: $doc's library graph differs from CMake's" \
           "(scripts/architecture-graph.sh --write):" >&2
      cat "$tmp/diff" >&2
      exit 1
    fi
    echo "architecture-graph: $doc matches CMake's graph" ;;
  --write)
    python3 - "$doc" "$tmp/graph.txt" "$begin" "$end" <<'PY'
import sys
doc, graph, begin, end = sys.argv[1:]
text = open(doc).read()
i, j = text.index(begin), text.index(end)
open(doc, "w").write(text[:i] + begin + "\n```\n" + open(graph).read() + "```\n" + text[j:])
PY
    ;;
  *) cat "$tmp/graph.txt" ;;
esac
