#!/usr/bin/env python3
"""The seed's real-time figures, three runs each, with the conditions they were measured under.

Runs, from a build made by `SuperBuild/setup.sh` (the benchmarks built: plain setup.sh, or
`cmake --build build --target benchmarks` after `--test`):
  - rpViewerBenchmark's display-rate run (4-up 1400x1100, proxy moving, slices following): p95 <= 33 ms;
  - `roboplan drill --block` with 2 and 3 mm burrs at 0.2 mm: servo tick p99 < 100 us;
  - the demo's tibial tunnel (real tibia at 0.3 mm, 4 mm burr; `roboplan demo --no-screenshots`):
    servo tick p99 < 100 us;
  - `roboplan haptics --seconds 10` idle, and with two busy loops on the machine's CPUs: lateness
    p99 < 50 us, at most 0.1 % missed deadlines; both again with the servo's CPU shielded from the
    other processes (`--cpu N --shield`, the last CPU).
Prints a Markdown table and writes every run's output and `figures.json` to --out. Quote what
it prints only from an idle machine: the load average and steal time are printed beside it.

usage: performance-figures.py [--build build] [--out performance-figures] [--runs 3]
"""
import argparse
import json
import multiprocessing
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

DRILL_STROKE = ["--from", "0,0,10", "--to", "0,0,-20", "--speed", "5", "--voxel", "0.2", "--json"]


def run(cmd, out_file, env=None):
    """Runs cmd, keeps its stdout in out_file and its stderr beside it; returns stdout."""
    started = time.time()
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)
    Path(out_file).write_text(result.stdout)
    Path(str(out_file) + ".err").write_text(result.stderr)
    if result.returncode != 0:
        sys.exit(f"performance-figures: {' '.join(map(str, cmd))} failed ({result.returncode}) after "
                 f"{time.time() - started:.0f} s; see {out_file}.err")
    return result.stdout


def conditions(build):
    cache = {}
    cache_file = build / "CMakeCache.txt"
    if cache_file.exists():
        for line in cache_file.read_text().splitlines():
            if "=" in line and ":" in line.split("=", 1)[0]:
                key, value = line.split("=", 1)
                cache[key.split(":")[0]] = value
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    commit = subprocess.run(["git", "-C", str(build.parent), "rev-parse", "--short", "HEAD"],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True).stdout.strip()
    return {"date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "commit": commit or "?",
            "buildType": cache.get("CMAKE_BUILD_TYPE", "?"), "compiler": cache.get("CMAKE_CXX_COMPILER", "?"),
            "cpu": cpu, "cpus": multiprocessing.cpu_count(), "kernel": platform.release(),
            "loadAverage": open("/proc/loadavg").read().split()[:3]}


def busy_loops(seconds):
    """One busy process per CPU, for `seconds` (the "machine loaded" runs)."""
    code = f"import time\nend = time.time() + {seconds}\nwhile time.time() < end: pass\n"
    return [subprocess.Popen([sys.executable, "-c", code]) for _ in range(multiprocessing.cpu_count())]


def viewer(build, out, i):
    json_file = out / f"viewer-{i}.json"
    env = dict(os.environ, ROBOPLAN_BENCHMARK_OUTPUT=str(out / "bench"))
    run([str(build / "bin" / "rpViewerBenchmark"), "--benchmark_filter=DisplayRate",
         f"--benchmark_out={json_file}", "--benchmark_out_format=json"], out / f"viewer-{i}.txt", env)
    data = json.loads(json_file.read_text())
    b = data["benchmarks"][0]
    ctx = data["context"]
    return {"p50Ms": b["p50_ms"], "p95Ms": b["p95_ms"], "maxMs": b["max_ms"], "fps": b["fps"],
            "slicesMovingFrames": b.get("slices_moving_frames", 0), "slicesMovingP95Ms": b.get("slices_moving_p95_ms", 0),
            "processCpuMsPerFrame": b.get("process_cpu_ms_per_frame", 0),
            "gl": ctx.get("gl renderer", "?"), "screen": ctx.get("screen", "?"), "load": ctx.get("load average before", "?")}


def drill(build, out, radius, i):
    text = run([str(build / "bin" / "roboplan"), "drill", "--block", "--burr-radius", str(radius)] + DRILL_STROKE,
               out / f"drill-r{radius}-{i}.json")
    d = json.loads(text)
    s = d["servo"]
    return {"p50Us": s["tickP50Us"], "p99Us": s["tickP99Us"], "maxUs": s["tickMaxUs"],
            "removedVsAnalyticPercent": 100 * (d["removedVolumeMm3"] / d["expectedVolumeMm3"] - 1),
            "load": s.get("conditions", {}).get("loadAverage1min", "?")}


def tunnel(build, out, i):
    folder = out / f"demo-{i}"
    run([str(build / "bin" / "roboplan"), "demo", "--out", str(folder), "--no-screenshots", "--json"], out / f"demo-{i}.json")
    report = json.loads((folder / "report.json").read_text())
    figures = []

    def walk(o):
        if isinstance(o, dict):
            if "name" in o and "value" in o:
                figures.append(o)
            for v in o.values():
                walk(v)
        elif isinstance(o, list):
            for v in o:
                walk(v)

    walk(report)
    by_name = {f["name"]: f for f in figures}
    tick = by_name.get("servo tick p99 while drilling (thread CPU)", {})
    load = by_name.get("servo thread preempted while drilling", {})
    return {"p99Us": tick.get("value"), "result": tick.get("result"), "note": load.get("note", "")}


def haptics(build, out, i, loaded, shielded=False):
    name = f"haptics-{'loaded' if loaded else 'idle'}{'-shielded' if shielded else ''}-{i}.json"
    loops = busy_loops(12) if loaded else []
    # Shielded: the servo alone on the last CPU, every other process's threads (the busy loops
    # too) moved off it for the run, as a real-time set-up isolates a core.
    shield = ["--cpu", str(os.cpu_count() - 1), "--shield"] if shielded else []
    try:
        text = run([str(build / "bin" / "roboplan"), "haptics", "--seconds", "10", "--json"] + shield, out / name)
    finally:
        for p in loops:
            p.wait()
    s = json.loads(text)["servo"]
    return {"latenessP99Us": s["lateness"]["p99Us"], "latenessMaxUs": s["lateness"]["maxUs"],
            "missed": s["missedDeadlines"], "missedPercent": s["missedPercent"],
            "reading": s.get("missesReading", ""), "priority": s.get("priorityNote", "")}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="performance-figures")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    build, out = Path(args.build).resolve(), Path(args.out).resolve()
    if not (build / "bin" / "rpViewerBenchmark").exists():
        sys.exit(f"performance-figures: {build}/bin/rpViewerBenchmark is missing: build the benchmarks "
                 "(SuperBuild/setup.sh, or cmake --build build --target benchmarks)")
    out.mkdir(parents=True, exist_ok=True)
    figures = {"conditions": conditions(build), "viewer": [], "drillR2": [], "drillR3": [], "tunnel": [],
               "hapticsIdle": [], "hapticsLoaded": [], "hapticsIdleShielded": [], "hapticsLoadedShielded": []}
    steps = [("viewer", lambda i: viewer(build, out, i)), ("drillR2", lambda i: drill(build, out, 2, i)),
             ("drillR3", lambda i: drill(build, out, 3, i)), ("tunnel", lambda i: tunnel(build, out, i)),
             ("hapticsIdle", lambda i: haptics(build, out, i, False)),
             ("hapticsLoaded", lambda i: haptics(build, out, i, True)),
             ("hapticsIdleShielded", lambda i: haptics(build, out, i, False, True)),
             ("hapticsLoadedShielded", lambda i: haptics(build, out, i, True, True))]
    with open("/proc/stat") as f:
        steal_before = int(f.readline().split()[8])
    for key, step in steps:
        for i in range(1, args.runs + 1):
            print(f"[performance-figures] {key} run {i}/{args.runs} (load {open('/proc/loadavg').read().split()[0]})",
                  file=sys.stderr, flush=True)
            figures[key].append(step(i))
    with open("/proc/stat") as f:
        steal = (int(f.readline().split()[8]) - steal_before) / os.sysconf("SC_CLK_TCK")
    figures["conditions"]["stealSecondsDuringRuns"] = steal
    figures["conditions"]["loadAverageAfter"] = open("/proc/loadavg").read().split()[:3]
    (out / "figures.json").write_text(json.dumps(figures, indent=2))

    c = figures["conditions"]
    v = figures["viewer"]
    print(f"Conditions: commit {c['commit']}, {c['date']}, {c['buildType']} build ({c['compiler']}), {c['cpu']}, "
          f"{c['cpus']} CPUs, load average {' '.join(c['loadAverage'])} before and {' '.join(c['loadAverageAfter'])} after, "
          f"steal {steal:.2f} s during the runs; GL {v[0]['gl']}, screen {v[0]['screen']}.\n")
    join = lambda xs, f: ", ".join(f.format(x) for x in xs)
    print("| what | target | runs |")
    print("|---|---|---|")
    print(f"| viewer display rate, 4-up 1400x1100 | p95 <= 33 ms | p95 {join([r['p95Ms'] for r in v], '{:.1f}')} ms; "
          f"p50 {join([r['p50Ms'] for r in v], '{:.1f}')}; max {join([r['maxMs'] for r in v], '{:.1f}')}; "
          f"{join([r['fps'] for r in v], '{:.1f}')} fps; frames whose slices moved: p95 "
          f"{join([r['slicesMovingP95Ms'] for r in v], '{:.1f}')} ms; process CPU per frame "
          f"{join([r['processCpuMsPerFrame'] for r in v], '{:.1f}')} ms |")
    for key, r in (("drillR2", 2), ("drillR3", 3)):
        d = figures[key]
        print(f"| drill --block, {r} mm burr radius, 0.2 mm | tick p99 < 100 us | p99 {join([x['p99Us'] for x in d], '{:.1f}')} us; "
              f"p50 {join([x['p50Us'] for x in d], '{:.1f}')}; max {join([x['maxUs'] for x in d], '{:.0f}')}; "
              f"removed vs analytic {join([x['removedVsAnalyticPercent'] for x in d], '{:+.2f}')} % |")
    t = figures["tunnel"]
    print(f"| demo tibial tunnel, real tibia 0.3 mm | tick p99 < 100 us | p99 {join([x['p99Us'] for x in t], '{:.1f}')} us |")
    for key, label in (("hapticsIdle", "idle"), ("hapticsLoaded", "two busy loops"),
                       ("hapticsIdleShielded", "idle, --cpu N --shield"),
                       ("hapticsLoadedShielded", "two busy loops, --cpu N --shield")):
        h = figures[key]
        print(f"| haptics --seconds 10, {label} | lateness p99 < 50 us, <= 0.1 % missed | p99 "
              f"{join([x['latenessP99Us'] for x in h], '{:.0f}')} us; missed {join([x['missed'] for x in h], '{}')} "
              f"({join([x['missedPercent'] for x in h], '{:.2f}')} %); {h[0]['reading']} |")
    print(f"\nEvery run's output: {out}")


if __name__ == "__main__":
    main()
