#!/usr/bin/env python3
"""`roboplan <path>`: an argument that is an existing file or folder is data, not a command.

A DICOM series folder whose path has no dot (the phantom's CT/) opens the viewer with that
series: the process is still running (the viewer's event loop) after the load, and nothing on
stderr says it was taken for a command or failed to load. A path that exists nowhere and has no
dot is still an unknown command (exit 2).

usage: open_data_argument_test.py <roboplan> <run-with-xvfb.sh> <work dir>
"""
import os
import shutil
import subprocess
import sys
import time

roboplan, xvfb, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
phantom = os.path.join(work, "phantom")
subprocess.run([roboplan, "phantom", "--out", phantom, "--size", "small", "--anatomy", "analytic"],
               check=True, stdout=subprocess.DEVNULL)
series = os.path.join(phantom, "CT")
assert os.path.isdir(series) and "." not in os.path.basename(series)

missing = subprocess.run([roboplan, os.path.join(work, "no-such-folder")], capture_output=True, text=True)
assert missing.returncode == 2, missing
assert "unknown command" in missing.stderr, missing.stderr

stderr_path = os.path.join(work, "viewer.stderr")
with open(stderr_path, "w") as stderr:
    viewer = subprocess.Popen([xvfb, roboplan, series], stdout=subprocess.DEVNULL, stderr=stderr,
                              start_new_session=True)
    try:
        viewer.wait(timeout=15)
        failed = f"the viewer exited ({viewer.returncode}) instead of showing {series}"
    except subprocess.TimeoutExpired:
        failed = None
    finally:
        if viewer.poll() is None:
            os.killpg(viewer.pid, 15)
            viewer.wait(timeout=20)
log = open(stderr_path).read()
print(log)
assert failed is None, failed + "\n" + log
lines = [line for line in log.splitlines() if line.startswith("roboplan")]
assert not lines, "stderr: " + "\n".join(lines)
print("roboplan", series, "opened the viewer with the series")
