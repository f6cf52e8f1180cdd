#!/usr/bin/env bash
# run-with-xvfb.sh <command...>: runs a GUI test on its own virtual X server.
# Xvfb chooses a free display itself (-displayfd), so tests started in parallel (ctest -j, other
# builds on the machine) never race for the same display number as `xvfb-run -a` can (a test
# then talks to another test's server and VTK aborts: "bad X server connection").
set -u

# Xvfb is stopped with SIGTERM, but one SIGTERM is not always enough: the server tests its
# termination flag just before it sleeps in epoll_wait (xserver os/WaitFor.c: "keep this check
# close to select() call to minimize race"), so a SIGTERM whose handler runs between that test
# and the call sets the flag without waking it, and it sleeps until its next timer, the screen
# saver's, 10 minutes later. After a GUI test had passed, this script then waited for Xvfb until
# ctest's timeout (rpViewerLoadingTest, 1 of 14 loaded suite runs). While Xvfb still runs the
# SIGTERM is sent again every second (each one ends such a sleep at once); after 10 s it is
# killed.
server_running() {  # Xvfb has not exited (a zombie has; another process with its pid is not ours)
  local stat state ppid
  stat=$(cat "/proc/$server/stat" 2>/dev/null) || return 1
  read -r state ppid _ <<<"${stat##*) }"
  [ "$state" != Z ] && [ "$ppid" = "$$" ]
}
stop_server() {
  local tenths
  kill -TERM "$server" 2>/dev/null
  for ((tenths = 1; tenths <= 100; tenths++)); do
    server_running || break
    sleep 0.1
    if ((tenths % 10 == 0)) && server_running; then
      echo "run-with-xvfb: Xvfb :$display still running $((tenths / 10)) s after SIGTERM; sent it again" >&2
      kill -TERM "$server" 2>/dev/null
    fi
  done
  if server_running; then
    echo "run-with-xvfb: Xvfb :$display did not exit on SIGTERM; killed" >&2
    kill -KILL "$server" 2>/dev/null
  fi
  wait "$server" 2>/dev/null
}

tmp=$(mktemp -d "${TMPDIR:-/tmp}/rp-xvfb.XXXXXX")
fifo="$tmp/display"
mkfifo "$fifo"
Xvfb -displayfd 3 -screen 0 1920x1080x24 -nolisten tcp -noreset 3>"$fifo" 2>"$tmp/xvfb.log" &
server=$!
display=""
if ! read -r -t 20 display <"$fifo" || [ -z "$display" ]; then
  echo "run-with-xvfb: Xvfb did not start:" >&2
  cat "$tmp/xvfb.log" >&2
  stop_server
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
stop_server
rm -rf "$tmp"
exit $status
