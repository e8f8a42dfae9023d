#!/usr/bin/env bash
# Checks the calls made by the AVX2 clones of a relief binary built by GCC (functions whose name
# has "_avx2": shade_packet_avx2, the sampler entries' clones, gather_*_avx2). A clone is
# compiled for AVX2 with `flatten`; whatever GCC leaves out of line is ordinary baseline code.
# GCC gives each function the calling convention of its own target: a single 32-byte vector (F8,
# I8, M8, __m256, __vector(8)) travels in a ymm register to and from AVX2 code and in memory to
# and from baseline code. So no call out of a clone may take or return such a value by value
# (the demangled name shows a template's return type; structs of two or more vectors travel in
# memory either way and are fine), and no call may go to an .isra or .part clone whose
# signature mentions a lane type at all (GCC rewrites those clones' parameters; by reference
# may become by value). Session 7 found such a call in review: a refactor left decode8<1, F8>
# out of line as a baseline .constprop clone taking an I8 by value, and the render crashed
# (docs/performance.md). Return types are checked twice: by name where the demangled name shows
# one, and at every call site by the first use of the return register after the call (a clone
# reading %ymm0 there takes a vector the baseline callee returned in memory); session 9 found a
# lambda returning an F8 that the name check could not see. Clang classifies every call by the translation unit's flags, so its
# sanitizer builds call by-value helpers safely and are not checked.
#
# Usage: scripts/check-avx2-calls.sh BINARY   (prints the calls it checked; exit 1 on a bad one)
set -euo pipefail

binary=${1:?usage: check-avx2-calls.sh BINARY}
if ! command -v objdump >/dev/null; then
  echo "check-avx2-calls: objdump not found" >&2
  exit 1
fi

objdump -d -C --no-show-raw-insn "$binary" | perl -e '
use strict;
use warnings;
my $lane = qr/\b(?:F8|I8|M8)\b|__vector\(8\)|__m256/;
# a type that is one 32-byte vector
my $vector = qr/^(?:(?:relief::)?(?:F8|I8|M8)|relief::LaneTraits<[^>]*>::Mask|.*__vector\(8\)|__m256\w*)$/;
my ($in_clone, %calls, %ymm_return, $clones, $after) = (0);
# The operands of an AT&T instruction, split at the commas outside parentheses.
sub operands {
  my ($text) = @_;
  my @ops;
  my ($cur, $d) = ("", 0);
  for my $c (split //, $text) {
    if ($c eq "," && $d == 0) { push @ops, $cur; $cur = ""; next; }
    ++$d if $c eq "(";
    --$d if $c eq ")";
    $cur .= $c;
  }
  push @ops, $cur if $cur ne "";
  return @ops;
}
while (my $line = <STDIN>) {
  if ($line =~ /^[0-9a-f]+ <(.*)>:$/) {
    $in_clone = ($1 =~ /_avx2/) ? 1 : 0;
    $clones += $in_clone;
    $after = undef;
    next;
  }
  next unless $in_clone && $line =~ /^\s*[0-9a-f]+:\s+(\S+)\s*(.*?)\s*$/;
  my ($op, $args) = ($1, $2);
  if ($op =~ /^call/ && $args =~ /^[0-9a-f]+ <(.*)>$/) {
    my $callee = $1;
    $callee =~ s/\+0x[0-9a-f]+$//;
    $calls{$callee}++;
    $after = $callee =~ /_avx2/ ? undef : $callee;
    next;
  }
  # After a call to baseline code, the first use of the return register: reading %ymm0 means
  # the clone takes a 32-byte vector returned in a register, which baseline code returns in
  # memory. This catches what the names cannot show: non-template functions and lambdas do not
  # carry their return type in the mangled name.
  next unless defined $after;
  if ($op =~ /^(?:j|ret|call)/) { $after = undef; next; }
  my @ops = operands($args);
  next unless grep { /%[xy]mm0\b/ } @ops;
  my @sources = @ops > 1 ? @ops[0 .. $#ops - 1] : ($op =~ /^vmov|^vpext|^vextract/ ? () : @ops);
  $ymm_return{$after}++ if grep { /%ymm0\b/ } @sources;
  $after = undef;
}

# Splits "RET NAME<...>(PARAMS) const [clone .x]" into the return type (templates only), the
# parameters and the clone suffix, at depth 0 of <> and ().
sub parse {
  my ($sig) = @_;
  my $suffix = "";
  $suffix = $1 if $sig =~ s/\s*(\[clone [^\]]*\])\s*$//;
  $sig =~ s/\s+const$//;
  my ($depth, $space, $open) = (0, -1, -1);
  my @chars = split //, $sig;
  for (my $i = $#chars; $i >= 0; --$i) {  # the last top-level ( ... ) is the parameter list
    my $c = $chars[$i];
    if ($c eq ")") { ++$depth; }
    elsif ($c eq "(") { if (--$depth == 0) { $open = $i; last; } }
  }
  return (undef) if $open < 0;
  $depth = 0;
  for (my $i = 0; $i < $open; ++$i) {
    my $c = $chars[$i];
    if ($c eq "<" || $c eq "(") { ++$depth; }
    elsif ($c eq ">" || $c eq ")") { --$depth; }
    elsif ($c eq " " && $depth == 0) { $space = $i; last; }
  }
  my $ret = $space >= 0 ? substr($sig, 0, $space) : "";
  my $params = substr($sig, $open + 1, length($sig) - $open - 2);
  my @params;
  my ($cur, $d) = ("", 0);
  for my $c (split //, $params) {
    if ($c eq "," && $d == 0) { push @params, $cur; $cur = ""; next; }
    ++$d if $c eq "<" || $c eq "(";
    --$d if $c eq ">" || $c eq ")";
    $cur .= $c;
  }
  push @params, $cur if $cur =~ /\S/;
  return ($ret, \@params, $suffix);
}

my $bad = 0;
for my $callee (sort keys %calls) {
  my ($ret, $params, $suffix) = parse($callee);
  my @why;
  if (defined $params) {
    push @why, "returns $ret by value" if $ret =~ $vector;
    for my $p (@$params) {
      (my $t = $p) =~ s/^\s+|\s+$//g;
      $t =~ s/\s+const$//;
      push @why, "takes $t by value" if $t =~ $vector;
    }
    my ($kind) = $suffix =~ /(\.isra|\.part)/;
    push @why, "is a GCC $kind clone of a function with lane types (its parameters are rewritten)"
      if $kind && $callee =~ $lane;
  }
  push @why, "returns a 32-byte vector: the caller reads %ymm0 after the call"
    if $ymm_return{$callee};
  printf "%6d  %s%s\n", $calls{$callee}, $callee, @why ? "\n        BAD: " . join("; ", @why) : "";
  $bad += @why ? 1 : 0;
}
if (!$clones) {
  print STDERR "check-avx2-calls: no _avx2 function in the binary\n";
  exit 1;
}
if ($bad) {
  print STDERR "check-avx2-calls: $bad callee(s) of the AVX2 clones take or return a vector by value\n";
  exit 1;
}
print "check-avx2-calls: $clones AVX2 clones, ", scalar(keys %calls),
  " distinct callees, none takes or returns a single vector by value\n";
'
