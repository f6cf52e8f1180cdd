#!/usr/bin/env python3
"""Snakemake --cluster-status for Slurm: prints running, success or failed for a job id.
Asks sacct (accounting), then scontrol (jobs the controller still remembers). A job neither
knows is reported as finished: Snakemake then checks that its outputs exist."""
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING", "STAGE_OUT"}
FAILED = {"FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY", "PREEMPTED", "BOOT_FAIL", "DEADLINE"}


def state_from(command, parse):
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return ""
    return parse(done.stdout) if done.returncode == 0 else ""


def main():
    job = sys.argv[1]
    state = state_from(["sacct", "-j", job, "-X", "-n", "-P", "-o", "State"],
                       lambda out: out.split("\n")[0].split(" ")[0].strip())
    if not state:
        state = state_from(["scontrol", "show", "job", "-o", job],
                           lambda out: next((f.split("=", 1)[1] for f in out.split() if f.startswith("JobState=")), ""))
    if state in RUNNING:
        print("running")
    elif state in FAILED:
        print("failed")
    else:
        print("success")


if __name__ == "__main__":
    main()
