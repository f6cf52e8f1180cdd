#!/usr/bin/env python3
"""rpXvfbTeardownTest: run-with-xvfb.sh ends when its test has ended, even when Xvfb takes the
SIGTERM that should stop it without waking up.

Xvfb tests its termination flag just before it sleeps in epoll_wait (xserver os/WaitFor.c: "keep
this check close to select() call to minimize race"); a SIGTERM whose handler runs between that
test and the call sets the flag but leaves the server asleep until its next timer, the screen
saver's, 10 minutes later. On a loaded machine this happened once after rpViewerLoadingTest had
passed: run-with-xvfb.sh waited for Xvfb until ctest's timeout.

Here the race is staged, not waited for: the "test" run under run-with-xvfb.sh attaches gdb to
its Xvfb, wakes the server with a connection, and gdb holds the server at the entry of
epoll_wait (after the flag test) once the connection is closed; the test then ends, and gdb lets
the server go only when the SIGTERM of run-with-xvfb.sh is pending, so its handler runs right
before epoll_wait. run-with-xvfb.sh must then still end within seconds, having said that it sent
the SIGTERM again (which proves the race was staged and handled).

usage: xvfb_teardown_test.py RUN_WITH_XVFB_SH WORK_DIR
Exit 77 (skipped) when gdb may not attach to a process here (no gdb, or ptrace not permitted).
"""
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

SKIP = 77
HOLD = r'''
import gdb, os, time
pid = gdb.selected_inferior().pid
work = os.environ["RP_TEARDOWN_DIR"]
baseline = int(open(os.path.join(work, "baseline")).read())

def open_fds():
    return len(os.listdir("/proc/%d/fd" % pid))

def sigterm_pending():
    for line in open("/proc/%d/status" % pid):
        if line.startswith(("SigPnd:", "ShdPnd:")) and int(line.split()[1], 16) & (1 << (15 - 1)):
            return True
    return False

class Hold(gdb.Breakpoint):
    # Stop at epoll_wait's entry once the waking connection is closed (no event pending).
    def stop(self):
        return os.path.exists(os.path.join(work, "woken")) and open_fds() <= baseline

Hold("epoll_wait")
gdb.execute("handle SIGTERM nostop noprint pass")
open(os.path.join(work, "attached"), "w").close()
gdb.execute("continue")
flag = int(gdb.parse_and_eval("*(char*)&dispatchException"))
open(os.path.join(work, "held"), "w").write("dispatchException %d\n" % flag)
start = time.time()
while not sigterm_pending() and time.time() - start < 30:
    time.sleep(0.02)
open(os.path.join(work, "released"), "w").write("SIGTERM pending %s\n" % sigterm_pending())
gdb.execute("delete")
gdb.execute("detach")
'''


def wait_for(path, seconds):
    end = time.time() + seconds
    while time.time() < end:
        if os.path.exists(path):
            return True
        time.sleep(0.02)
    return False


def staged_test(work):
    """The command run under run-with-xvfb.sh: stages the race on its Xvfb, then ends."""
    parent = os.getppid()
    xvfb = None
    for pid in os.listdir("/proc"):
        if pid.isdigit():
            try:
                with open("/proc/%s/stat" % pid) as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                with open("/proc/%s/comm" % pid) as f:
                    comm = f.read().strip()
            except OSError:
                continue
            if comm == "Xvfb" and int(fields[1]) == parent:
                xvfb = int(pid)
    if xvfb is None:
        print("no Xvfb beside this test", file=sys.stderr)
        return 1
    with open(os.path.join(work, "baseline"), "w") as f:
        f.write(str(len(os.listdir("/proc/%d/fd" % xvfb))))
    with open(os.path.join(work, "hold.py"), "w") as f:
        f.write(HOLD)
    gdb_log = open(os.path.join(work, "gdb.log"), "w")
    subprocess.Popen(["gdb", "-nx", "-p", str(xvfb), "-batch", "-x", os.path.join(work, "hold.py")],
                     stdout=gdb_log, stderr=subprocess.STDOUT, env=dict(os.environ, RP_TEARDOWN_DIR=work))
    if not wait_for(os.path.join(work, "attached"), 60):
        print("gdb did not attach to Xvfb", file=sys.stderr)
        return 1
    # Wake the server: a connection it accepts, reads to its end and closes.
    open(os.path.join(work, "woken"), "w").close()
    display = os.environ["DISPLAY"].lstrip(":").split(".")[0]
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as s:
        try:
            s.connect("/tmp/.X11-unix/X" + display)
        except OSError:
            s.connect("\0/tmp/.X11-unix/X" + display)
    if not wait_for(os.path.join(work, "held"), 60):
        print("gdb did not hold Xvfb at epoll_wait", file=sys.stderr)
        return 1
    return 0  # the test passed; run-with-xvfb.sh now stops Xvfb


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--staged-test":
        return staged_test(sys.argv[2])
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    script, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    if shutil.which("gdb") is None:
        print("SKIPPED: gdb is not installed (SuperBuild/install-dependencies.sh installs it)")
        return SKIP
    probe = subprocess.run(["gdb", "-nx", "-batch", "-ex", "run", "--args", "/bin/true"],
                           capture_output=True, text=True)
    if "ptrace" in probe.stdout + probe.stderr or probe.returncode != 0:
        print("SKIPPED: gdb cannot trace processes here:\n" + probe.stdout + probe.stderr)
        return SKIP
    # Staging needs the server to sleep in epoll_wait with the SIGTERM taken just before it; on a
    # loaded machine another wake-up can come first and the server exits on the first SIGTERM
    # (nothing wrong with the script, but nothing proven). Such attempts are tried again; a hang
    # or a failing script fails at once.
    attempts = 3
    for attempt in range(1, attempts + 1):
        result = stage_once(script, os.path.join(work, "attempt-%d" % attempt))
        if result != "not staged":
            return 0 if result == "passed" else 1
        print("attempt %d of %d: the race was not staged; trying again" % (attempt, attempts))
    print("FAILED: the race could not be staged in %d attempts" % attempts)
    return 1


def stage_once(script, work):
    """One run of run-with-xvfb.sh with the race staged: "passed", "failed" or "not staged"."""
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    # The sanitizer builds' preload (libasan, Mesa) is for our instrumented GUI tests, not Python.
    env = dict(os.environ)
    env.pop("ROBOPLAN_GUI_TEST_PRELOAD", None)
    start = time.time()
    run = subprocess.Popen([script, sys.executable, os.path.abspath(__file__), "--staged-test", work],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                           start_new_session=True)
    limit = 30.0
    try:
        output, _ = run.communicate(timeout=limit)
    except subprocess.TimeoutExpired:
        os.killpg(run.pid, signal.SIGKILL)  # the script, its Xvfb and gdb
        output, _ = run.communicate()
        print(output)
        print("FAILED: run-with-xvfb.sh still waiting for its Xvfb %.0f s after the test ended" % limit)
        return "failed"
    seconds = time.time() - start
    print(output, end="")
    for name in ("held", "released", "gdb.log"):
        path = os.path.join(work, name)
        if os.path.exists(path):
            print("--- %s:\n%s" % (name, open(path).read().strip()))
    if run.returncode != 0:
        print("FAILED: run-with-xvfb.sh exited %d" % run.returncode)
        return "failed"
    released = os.path.join(work, "released")
    if not os.path.exists(released) or "True" not in open(released).read():
        print("the race was not staged (gdb did not release Xvfb with the SIGTERM pending)")
        return "not staged"
    if "after SIGTERM; sent it again" not in output:
        print("the race was not hit: Xvfb was woken by something else and exited on the first SIGTERM")
        return "not staged"
    print("run-with-xvfb.sh ended %.1f s after it started, the staged race included" % seconds)
    return "passed"

if __name__ == "__main__":
    sys.exit(main())
