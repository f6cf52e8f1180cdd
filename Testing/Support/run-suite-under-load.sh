#!/usr/bin/env bash
# run-suite-under-load.sh BUILD_DIR N: runs the whole suite (ctest -j2) N times while two busy
# loops keep both cores loaded, the proof that no test is flaky when the machine is busy.
# One line per run (passed, failed, seconds, the failed tests), a summary at the end; exits
# non-zero if any run had a failure. The busy loops are killed however the script ends.
set -u
if [ $# -ne 2 ] || ! [ "$2" -ge 1 ] 2>/dev/null; then
  echo "usage: $0 BUILD_DIR N" >&2
  exit 2
fi
build_dir=$(cd "$1" && pwd) || exit 2
runs=$2
if [ ! -f "$build_dir/CTestTestfile.cmake" ]; then
  echo "run-suite-under-load: $build_dir is not a configured build (no CTestTestfile.cmake)" >&2
  exit 2
fi
# As .ci/run: with ../shared/data beside the sources a test may not skip for lack of it.
src_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
if [ -d "$src_dir/../shared/data" ]; then
  export ROBOPLAN_REQUIRE_SHARED_DATA=1
fi

loops=()
stop_loops() {
  for pid in "${loops[@]}"; do
    kill "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  loops=()
}
trap stop_loops EXIT
trap 'exit 130' INT
trap 'exit 143' TERM HUP
for _ in 1 2; do
  (while :; do :; done) &
  loops+=($!)
done
echo "run-suite-under-load: $runs run(s) of ctest -j2 in $build_dir, busy loops ${loops[*]}"

log_dir="$build_dir/Testing/Temporary/under-load"
mkdir -p "$log_dir"
failed_runs=0
total_failed=0
total_seconds=0
for run in $(seq 1 "$runs"); do
  log="$log_dir/run-$run.log"
  start=$(date +%s)
  (cd "$build_dir" && ctest -j2 --output-on-failure) >"$log" 2>&1
  status=$?
  seconds=$(( $(date +%s) - start ))
  total_seconds=$((total_seconds + seconds))
  # "100% tests passed, 0 tests failed out of 67"
  summary=$(grep -E '^[0-9]+% tests passed, [0-9]+ tests failed out of [0-9]+' "$log" | tail -1)
  if [ -n "$summary" ]; then
    failed=$(sed -E 's/.* ([0-9]+) tests failed out of ([0-9]+).*/\1/' <<<"$summary")
    total=$(sed -E 's/.* out of ([0-9]+).*/\1/' <<<"$summary")
    passed=$((total - failed))
  else
    failed="?" total="?" passed="?"
  fi
  names=$(sed -n '/^The following tests FAILED:/,$p' "$log" | grep -E '^[[:space:]]+[0-9]+ - ' \
          | sed -E 's/^[[:space:]]+[0-9]+ - ([^ ]+).*/\1/' | tr '\n' ' ' | sed 's/ $//')
  if [ $status -ne 0 ] || [ "$failed" != 0 ]; then
    failed_runs=$((failed_runs + 1))
    [ "$failed" = "?" ] || total_failed=$((total_failed + failed))
    echo "run $run/$runs: $passed of $total passed, $failed failed, ${seconds} s  FAILED: ${names:-ctest exit $status} (log: $log)"
  else
    echo "run $run/$runs: $passed of $total passed, 0 failed, ${seconds} s"
  fi
done
echo "summary: $runs run(s), $((runs - failed_runs)) without failure, $failed_runs with failures" \
     "($total_failed failed test(s) in all), $total_seconds s, both cores loaded"
[ $failed_runs -eq 0 ]
