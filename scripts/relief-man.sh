#!/usr/bin/env bash
# Writes relief(1), gzipped, from the built binary's help text: `relief --help` as the
# description, then one section per subcommand with its `relief SUBCOMMAND --help`.
# Usage: scripts/relief-man.sh RELIEF_BINARY VERSION OUT.1.gz   (run by the relief_man target)
set -euo pipefail
bin=$1 version=$2 out=$3
help() { (exec -a relief "$bin" "$@" --help); }
# roff: backslashes as \e, every - as \- (options copy as typed), \& before a leading . or '.
roff() { sed -e 's/\\/\\e/g' -e 's/-/\\-/g' -e "s/^\([.']\)/\\\\\&\1/"; }
main="$(help)"
subs="$(printf '%s\n' "$main" | sed -n '/^Subcommands:/,$p' | sed -n 's/^  \([a-z][a-z0-9_-]*\) .*/\1/p')"
[ -n "$subs" ] || { echo "relief-man.sh: no subcommands in '$bin --help'" >&2; exit 1; }
summary="$(printf '%s\n' "$main" | head -n 1 | sed 's/^relief: //')"
tmp="$out.tmp"
mkdir -p "$(dirname "$out")"
{
  echo ".TH RELIEF 1 \"\" \"relief $version\" \"User Commands\""
  echo ".SH NAME"
  echo "relief \\- $(printf '%s' "$summary" | sed 's/-/\\-/g')"
  echo ".SH SYNOPSIS"
  echo ".B relief"
  echo "\\fISUBCOMMAND\\fR [\\fIOPTIONS\\fR]"
  echo ".SH DESCRIPTION"
  echo ".nf"
  printf '%s\n' "$main" | roff
  echo ".fi"
  echo ".SH SUBCOMMANDS"
  for s in $subs; do
    echo ".SS relief $s"
    echo ".nf"
    help "$s" | roff
    echo ".fi"
  done
  echo ".SH ENVIRONMENT"
  echo ".TP"
  echo ".B RELIEF_CACHE_DIR"
  echo "Folder of the cone-map cache (else \$XDG_CACHE_HOME/relief, else ~/.cache/relief); none turns it off."
  echo ".TP"
  echo ".B RELIEF_GL_SHADER_DIR"
  echo "GL backend: read GLSL files from this folder first, then from the source tree's gl/shaders where it exists, then the copies built into the binary."
  echo ".TP"
  echo ".B RELIEF_SIMD"
  echo "baseline forces the baseline x86\\-64 kernels instead of AVX2 (the image is the same)."
  echo ".SH EXIT STATUS"
  echo "0 success, 1 input error, 2 usage error, 130 and 143 on SIGINT and SIGTERM."
  echo ".SH SEE ALSO"
  echo "/usr/share/doc/relief/README.md and the other pages in /usr/share/doc/relief."
} > "$tmp"
gzip -n -9 -c "$tmp" > "$out"
rm -f "$tmp"
