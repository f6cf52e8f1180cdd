#!/usr/bin/env bash
# run-fuzzer.sh <fuzzer> <committed corpus> <work folder> <seconds> [<seed list> <shared folder>]
# Runs a libFuzzer target for a bounded time on its committed corpus (every input in it is
# replayed first, regression cases included), the real files its seed list names (patterns
# relative to ../shared, gathered into the work folder: never copied into the project) and what
# earlier runs found (work folder). A crash, a hang or running out of memory fails the run; the
# input that did it is copied into the committed corpus as regression-<kind>-<hash>, so it
# replays on every run once committed.
set -uo pipefail
fuzzer=$1 corpus=$2 work=$3 seconds=$4 seedlist=${5:-} shared=${6:-}
if [ ! -x "$fuzzer" ]; then
  echo "run-fuzzer: $fuzzer was not built (the RoboPlanFuzzers sub-build failed?)" >&2
  exit 1
fi
mkdir -p "$work/found" "$work/artifacts" "$corpus"
rm -f "$work"/artifacts/*
rm -rf "$work/seeds" && mkdir -p "$work/seeds"
name=$(basename "$fuzzer")
if [ -n "$seedlist" ] && [ -f "$seedlist" ]; then
  while read -r pattern; do
    case "$pattern" in ''|'#'*) continue ;; esac
    for file in "$shared"/$pattern; do
      [ -f "$file" ] && cp "$file" "$work/seeds/$(basename "$(dirname "$file")")-$(basename "$file")"
    done
  done <"$seedlist"
  echo "[$name] $(ls "$work/seeds" | wc -l) seeds from $shared ($(basename "$seedlist"))"
fi
# Readers size their buffers by the memory check (rpMemoryBudget.h): keep it under the 2 GB limit.
export ROBOPLAN_MEMORY_LIMIT_MB=${ROBOPLAN_MEMORY_LIMIT_MB:-1024}
"$fuzzer" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
  -artifact_prefix="$work/artifacts/" "$work/found" "$corpus" "$work/seeds" 2>"$work/fuzzer.log"
status=$?
grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|INFO: seed corpus|Done )" "$work/fuzzer.log" | sed "s/^/[$name] /"
if [ $status -eq 0 ]; then
  exit 0
fi
tail -n 60 "$work/fuzzer.log" >&2
kept=0
for artifact in "$work"/artifacts/*; do
  [ -f "$artifact" ] || continue
  base=$(basename "$artifact")
  cp "$artifact" "$corpus/regression-$base"
  echo "run-fuzzer: $name failed on $base; kept as $corpus/regression-$base (commit it: it replays every run)" >&2
  kept=1
done
[ $kept -eq 1 ] || echo "run-fuzzer: $name exited with $status" >&2
exit 1
