#!/usr/bin/env bash
# compile-cpu.sh: the CPU time (user + system, seconds) of every compiler run of a build, sub-builds
# included, one line per object in $COMPILE_CPU_LOG. ccache runs it in front of the compiler:
#
#   CCACHE_PREFIX=$PWD/Utilities/Scripts/compile-cpu.sh COMPILE_CPU_LOG=/tmp/cpu.log .ci/run
#   sort -rn /tmp/cpu.log | head            # the costliest objects
#
# Ninja's log gives wall times, which the oracle's and fuzzers' sub-builds inflate (they run their
# own Ninja beside the main one: up to 10 compilers on 2 cores). CPU time does not depend on that.
# Only compiles that miss the cache run the compiler, so use an empty CCACHE_DIR.
set -u
out=""
prev=""
for arg in "$@"; do
  [ "$prev" = "-o" ] && out=$arg
  prev=$arg
done
times=$(mktemp)
TIMEFORMAT="%U %S"
{ time "$@" 2>&3; } 3>&2 2>"$times"
rc=$?
read -r user sys <"$times"
rm -f "$times"
awk -v u="$user" -v s="$sys" -v o="$PWD/$out" 'BEGIN { printf "%.3f %s\n", u + s, o }' >>"${COMPILE_CPU_LOG:-/dev/null}"
exit $rc
