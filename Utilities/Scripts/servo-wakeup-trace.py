#!/usr/bin/env python3
"""Why was the servo late? Traces one `roboplan haptics` run with the kernel's own events.

For each of the servo's sleeps (its clock_nanosleep timer, one a tick) it finds when the timer was
due, when its interrupt really fired and which task the CPU was running at that moment, then sorts
the late ones (interrupt more than --late-us after the timer was due) by that task:
  - `<idle>`: the CPU was idle and still took the interrupt late: the host did not run this
    virtual CPU (or woke it late); nothing in the guest can change that;
  - another task (e.g. a daemon): it held interrupts off on the servo's CPU. Keep it off that CPU:
    `roboplan haptics --cpu N --shield` for a run, isolcpus= or a cpuset for good.
Interrupts that fired on time but woke the servo late would be the guest's scheduler: counted too.

Needs root (tracefs at /sys/kernel/tracing, mounted here when it is not) and changes nothing
permanently: the events, clock and buffer size are put back. Prints a summary and writes
the raw trace and a JSON summary to --out.

usage: sudo servo-wakeup-trace.py [--build build] [--seconds 10] [--out servo-trace] [-- haptics args]
"""
import argparse
import collections
import json
import os
import re
import subprocess
import sys
from pathlib import Path

TRACING = Path("/sys/kernel/tracing")
EVENTS = ["timer/hrtimer_start", "timer/hrtimer_expire_entry", "sched/sched_wakeup", "sched/sched_switch"]
LINE = re.compile(r"^\s*(.+?)-(\d+)\s+\[(\d+)\]\s+\S+\s+([\d.]+):\s+(\w+):\s+(.*)$")


def write(name, value):
    (TRACING / name).write_text(str(value))


def ensure_tracefs():
    if (TRACING / "trace").exists():
        return
    if subprocess.run(["mount", "-t", "tracefs", "nodev", str(TRACING)]).returncode != 0 or not (TRACING / "trace").exists():
        sys.exit("servo-wakeup-trace: tracefs is not available (run as root on a kernel with tracing)")


def record(command, trace_file):
    clock_before = re.search(r"\[(\w+)\]", (TRACING / "trace_clock").read_text()).group(1)
    buffer_before = (TRACING / "buffer_size_kb").read_text().split()[0]
    try:
        write("tracing_on", 0)
        write("trace", "")
        write("buffer_size_kb", 40960)
        write("trace_clock", "mono")  # the clock of the timers' `expires` and `now`
        for e in EVENTS:
            write(f"events/{e}/enable", 1)
        write("tracing_on", 1)
        result = subprocess.run(command, capture_output=True, text=True)
        write("tracing_on", 0)
        trace_file.write_text((TRACING / "trace").read_text())
    finally:
        for e in EVENTS:
            write(f"events/{e}/enable", 0)
        write("trace_clock", clock_before)
        write("buffer_size_kb", buffer_before)
        write("trace", "")
    return result


def analyse(trace_file, late_us):
    events = []
    for line in trace_file.read_text().splitlines():
        m = LINE.match(line)
        if m:
            events.append((m.group(1), int(m.group(2)), int(m.group(3)), round(float(m.group(4)) * 1e9), m.group(5), m.group(6)))
    # The servo: the thread that arms the most sleep timers (one per tick).
    arms = collections.Counter(p for c, p, cpu, t, name, rest in events
                               if name == "hrtimer_start" and "function=hrtimer_wakeup" in rest)
    if not arms:
        return None
    servo = arms.most_common(1)[0][0]
    due = {}  # timer -> expiry (ns)
    ticks, late = 0, []
    waiting = None  # the servo's fired timer, waiting for its wake-up
    for c, p, cpu, t, name, rest in events:
        if name == "hrtimer_start" and p == servo and "function=hrtimer_wakeup" in rest:
            timer = re.search(r"hrtimer=(\w+)", rest).group(1)
            due[timer] = int(re.search(r"expires=(\d+)", rest).group(1))
        elif name == "hrtimer_expire_entry" and "function=hrtimer_wakeup" in rest:
            timer = re.search(r"hrtimer=(\w+)", rest).group(1)
            if timer in due:
                ticks += 1
                now = int(re.search(r"now=(\d+)", rest).group(1))
                # Armed already past due (the tick after a late one): the servo itself catching up.
                running = "(the servo catching up after a late tick)" if p == servo else c.strip()
                waiting = {"due": due.pop(timer), "fired": now, "cpu": cpu, "running": running}
        elif name == "sched_wakeup" and waiting and f"pid={servo} " in rest:
            waiting["woken"] = t
            interrupt_us = (waiting["fired"] - waiting["due"]) / 1e3
            wake_us = (t - waiting["fired"]) / 1e3
            if interrupt_us > late_us or wake_us > late_us:
                late.append({"dueS": waiting["due"] / 1e9, "interruptLateUs": round(interrupt_us, 1),
                             "wakeAfterInterruptUs": round(wake_us, 1), "cpu": waiting["cpu"],
                             "runningWhenItFired": waiting["running"]})
            waiting = None
    by_task = collections.Counter()
    for x in late:
        if x["interruptLateUs"] > late_us:
            by_task[x["runningWhenItFired"]] += 1
        else:
            by_task["(interrupt on time, the guest woke the servo late)"] += 1
    return {"servoThread": servo, "sleeps": ticks, "lateUs": late_us, "late": late, "lateByTask": dict(by_task)}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--seconds", default="10")
    parser.add_argument("--out", default="servo-trace")
    parser.add_argument("--late-us", type=float, default=300.0)
    parser.add_argument("haptics", nargs="*", help="more `roboplan haptics` arguments (after --)")
    args = parser.parse_args()
    if os.geteuid() != 0:
        sys.exit("servo-wakeup-trace: run as root (the kernel's trace events need it)")
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    ensure_tracefs()
    command = [str(Path(args.build).resolve() / "bin" / "roboplan"), "haptics", "--seconds", args.seconds, "--json"] + args.haptics
    result = record(command, out / "trace.txt")
    if result.returncode != 0:
        sys.exit(f"servo-wakeup-trace: {' '.join(command)} failed:\n{result.stderr}")
    servo = json.loads(result.stdout)["servo"]
    summary = analyse(out / "trace.txt", args.late_us)
    if summary is None:
        sys.exit("servo-wakeup-trace: no servo sleeps in the trace (were the timer events recorded?)")
    summary["command"] = command
    summary["missedDeadlines"] = servo["missedDeadlines"]
    summary["missesReading"] = servo.get("missesReading", "")
    (out / "summary.json").write_text(json.dumps(summary, indent=2))
    print(f"{' '.join(command[1:])}: {servo['missedDeadlines']} missed deadlines; {summary['sleeps']} servo sleeps traced, "
          f"{len(summary['late'])} woken more than {args.late_us:.0f} us late")
    for task, n in sorted(summary["lateByTask"].items(), key=lambda kv: -kv[1]):
        why = ("the CPU was idle: the host ran this virtual CPU late" if task == "<idle>"
               else "interrupts held off by this task on the servo's CPU" if not task.startswith("(") else "")
        print(f"  {n:4d}  {task}{': ' + why if why else ''}")
    for x in summary["late"][:20]:
        print(f"    at {x['dueS']:.4f} s: interrupt {x['interruptLateUs']:.0f} us late on CPU {x['cpu']} "
              f"while {x['runningWhenItFired']} ran; servo woken {x['wakeAfterInterruptUs']:.0f} us after it")
    print(f"trace and summary: {out}")


if __name__ == "__main__":
    main()
