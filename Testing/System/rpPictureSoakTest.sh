#!/usr/bin/env bash
# rpPictureSoakTest.sh <rpPictureSoak> <runs under xvfb-run -a> <runs without DISPLAY>
# The demo's pictures in fresh processes, each on a fresh X server that resets when its last client
# leaves (xvfb-run's default, no -noreset), then on the private Xvfb a process starts for itself
# when it has no DISPLAY. Passes when no run aborts and every run draws every picture.
set -u
soak=$1 xvfb_runs=$2 private_runs=$3
work=$(mktemp -d "${TMPDIR:-/tmp}/rp-soak.XXXXXX")
trap 'rm -rf "$work"' EXIT
if ! command -v xvfb-run >/dev/null; then
  echo "rpPictureSoakTest: xvfb-run is not installed (package xvfb)" >&2
  exit 1
fi
failures=0 aborts=0
run() {  # run <label> <command...>
  local label=$1; shift
  local out="$work/$label"
  "$@" "$out" >"$work/$label.log" 2>&1
  local rc=$?
  local pictures
  pictures=$(find "$out" -name '*.png' -size +2k 2>/dev/null | wc -l)
  if [ "$rc" -ne 0 ] || [ "$pictures" -ne 6 ]; then
    failures=$((failures + 1))
    # 134 = 128 + SIGABRT (VTK's "bad X server connection ... Aborting."), from xvfb-run or the shell
    if [ "$rc" -eq 134 ] || grep -q "Aborting" "$work/$label.log"; then aborts=$((aborts + 1)); fi
    echo "rpPictureSoakTest: $label: exit $rc, $pictures of 6 pictures" >&2
    tail -5 "$work/$label.log" >&2
  fi
}
for ((i = 1; i <= xvfb_runs; i++)); do
  run "xvfb-run-$i" xvfb-run -a -s "-screen 0 1920x1080x24" "$soak"
done
for ((i = 1; i <= private_runs; i++)); do
  run "private-$i" env -u DISPLAY -u XAUTHORITY "$soak"
done
total=$((xvfb_runs + private_runs))
echo "rpPictureSoakTest: $((total - failures)) of $total runs drew every picture; $aborts aborted"
[ "$failures" -eq 0 ]
