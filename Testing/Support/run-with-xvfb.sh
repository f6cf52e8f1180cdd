#!/usr/bin/env bash
# run-with-xvfb.sh <command...>: runs a GUI test on its own virtual X server.
# Xvfb chooses a free display itself (-displayfd), so tests started in parallel (ctest -j, other
# builds on the machine) never race for the same display number as `xvfb-run -a` can (a test
# then talks to another test's server and VTK aborts: "bad X server connection").
set -u
tmp=$(mktemp -d "${TMPDIR:-/tmp}/rp-xvfb.XXXXXX")
fifo="$tmp/display"
mkfifo "$fifo"
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp -noreset 3>"$fifo" 2>"$tmp/xvfb.log" &
server=$!
display=""
if ! read -r -t 20 display <"$fifo" || [ -z "$display" ]; then
  echo "run-with-xvfb: Xvfb did not start:" >&2
  cat "$tmp/xvfb.log" >&2
  kill "$server" 2>/dev/null
  rm -rf "$tmp"
  exit 1
fi
# ASan builds: the GL driver is preloaded into the test (not into Xvfb) so that it is never
# unloaded before LeakSanitizer's check (RoboPlanMacros.cmake, ROBOPLAN_GUI_TEST_PRELOAD).
if [ -n "${ROBOPLAN_GUI_TEST_PRELOAD:-}" ]; then
  DISPLAY=":$display" LD_PRELOAD="$ROBOPLAN_GUI_TEST_PRELOAD${LD_PRELOAD:+ $LD_PRELOAD}" "$@"
else
  DISPLAY=":$display" "$@"
fi
status=$?
if [ $status -ne 0 ] && ! kill -0 "$server" 2>/dev/null; then
  echo "run-with-xvfb: the X server :$display exited during the test:" >&2
  cat "$tmp/xvfb.log" >&2
fi
kill "$server" 2>/dev/null
wait "$server" 2>/dev/null
rm -rf "$tmp"
exit $status
