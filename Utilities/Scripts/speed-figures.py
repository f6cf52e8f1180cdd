#!/usr/bin/env python3
"""Where RoboPlan stands beside VTK and Slicer (issue 41), three runs in a row, with conditions.

Runs, from a build with the benchmarks (plain `SuperBuild/setup.sh`, or
`cmake --build build --target benchmarks` after `--test`), each --runs times into its own folder:
  - rpDrillingBenchmark: the whole bone re-contoured by our block mesher against vtkFlyingEdges3D
    (same volume, same VTK SMP threads) at 0.2-0.5 mm, surface error of each, and the per-frame
    dirty-block re-contour p95 (targets: ours faster at 0.2 mm at equal or lower error; p95 < 1 ms);
  - rpMeshWholeProcessBenchmark: `roboplan mesh` of a 512x512x300 labelmap start to exit against
    Slicer's pipeline's compute alone (target: no slower), and `roboplan <command> --help` start to
    exit for every command (target <= 30 ms);
  - rpSegmentationToMeshBenchmark: labelmap to closed surface in process against Slicer's default
    pipeline (target: >= 8x at equal or lower mean surface error).
Each run keeps the benchmark's own JSON/CSV/PNG charts in --out/run-<i>/; this script prints one
Markdown table (a column per run) and writes figures.json beside them. Quote it only from an idle
machine: the load average before and after each run is in the table.

usage: speed-figures.py [--build build] [--out speed-figures] [--runs 3]
"""
import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

BENCHMARKS = ["rpDrillingBenchmark", "rpMeshWholeProcessBenchmark", "rpSegmentationToMeshBenchmark"]


def load():
    return float(open("/proc/loadavg").read().split()[0])


def run_benchmark(build, name, folder):
    folder.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, ROBOPLAN_BENCHMARK_OUTPUT=str(folder))
    env.pop("ROBOPLAN_BENCHMARK_QUICK", None)
    with open(folder / f"{name}.txt", "w") as log:
        result = subprocess.run([str(build / "bin" / name)], stdout=log, stderr=subprocess.STDOUT, env=env)
    if result.returncode != 0:
        sys.exit(f"speed-figures: {name} failed ({result.returncode}); see {folder / (name + '.txt')}")


def read(path):
    return json.loads(Path(path).read_text()) if Path(path).exists() else {}


def results(doc):
    return doc.get("results", doc) if isinstance(doc, dict) else doc


def drilling(folder):
    doc = read(folder / "drilling_benchmark.json")
    grid = next((g for g in doc.get("grids", []) if abs(g["gridMm"] - 0.2) < 1e-9), None)
    if not grid:
        return {}
    w, t = grid["wholeBone"], grid["tunnel"]
    return {"wholeBone02OursMs": w["recontourOursMs"], "wholeBone02VtkMs": w["recontourVtkFlyingEdgesMs"],
            "wholeBone02OursOverVtk": w["recontourOursMs"] / max(w["recontourVtkFlyingEdgesMs"], 1e-9),
            "surfaceErrorMeanMm": w.get("surfaceErrorMeanMm"), "surfaceErrorMeanMmVtk": w.get("surfaceErrorMeanMmVtk"),
            "surfaceErrorOursOverVtk": (w["surfaceErrorMeanMm"] / max(w["surfaceErrorMeanMmVtk"], 1e-300)
                                        if w.get("surfaceErrorMeanMm") is not None and w.get("surfaceErrorMeanMmVtk") else None),
            "threads": w.get("threads"), "dirtyRecontourP95Ms": t["dirtyBlockRecontourP95Ms"]}


def whole_process(folder):
    rows = {r["config"]: r for r in results(read(folder / "whole_process.json"))}
    startup = read(folder / "startup.json")
    startup = results(startup) if "commands" not in startup else startup
    mesh, slicer = rows.get("roboplan_mesh", {}).get("seconds"), rows.get("slicer_compute", {}).get("seconds")
    worst = max(startup.get("commands", []), key=lambda c: c["p50Ms"], default={})
    return {"meshProcessS": mesh, "slicerComputeS": slicer,
            "meshOverSlicer": mesh / slicer if mesh and slicer else None,
            "startupWorstP50Ms": worst.get("p50Ms"), "startupWorstCommand": worst.get("command"),
            "startupHelpP50Ms": next((c["p50Ms"] for c in startup.get("commands", []) if c["command"] == "--help"), None)}


def in_process(folder):
    rows = results(read(folder / "segmentation_to_mesh.json"))
    slicer = next((r for r in rows if r["config"] == "slicer_default"), None)
    if not slicer:
        return {}
    fair = [r for r in rows if r.get("speedupVsSlicer", 0) > 0 and r["meanErrorMm"] <= slicer["meanErrorMm"]
            and r["config"] != "slicer_default"]
    best = max(fair, key=lambda r: r["speedupVsSlicer"], default={})
    return {"bestSpeedupAtEqualOrLowerError": best.get("speedupVsSlicer"), "bestConfig": best.get("config"),
            "bestMeanErrorMm": best.get("meanErrorMm"), "slicerMeanErrorMm": slicer["meanErrorMm"],
            "slicerSeconds": slicer["seconds"]}


ROWS = [  # (label, key, format, target test)
    ("whole bone 0.2 mm, ours (ms)", "wholeBone02OursMs", "{:.1f}", None),
    ("whole bone 0.2 mm, vtkFlyingEdges3D (ms)", "wholeBone02VtkMs", "{:.1f}", None),
    ("ours / VTK (target < 1)", "wholeBone02OursOverVtk", "{:.2f}", lambda v: v < 1),
    ("surface error mean over the surface, ours (mm)", "surfaceErrorMeanMm", "{:.6f}", None),
    ("surface error mean over the surface, VTK (mm)", "surfaceErrorMeanMmVtk", "{:.6f}", None),
    ("surface error ours / VTK (target <= 1)", "surfaceErrorOursOverVtk", "{:.4f}", lambda v: v <= 1),
    ("SMP threads", "threads", "{}", None),
    ("dirty-block re-contour p95 (ms, target < 1)", "dirtyRecontourP95Ms", "{:.3f}", lambda v: v < 1),
    ("roboplan mesh, start to exit (s)", "meshProcessS", "{:.3f}", None),
    ("Slicer pipeline, compute alone (s)", "slicerComputeS", "{:.3f}", None),
    ("mesh / Slicer (target <= 1)", "meshOverSlicer", "{:.2f}", lambda v: v <= 1),
    ("roboplan --help p50 (ms)", "startupHelpP50Ms", "{:.1f}", None),
    ("slowest command --help p50 (ms, target <= 30)", "startupWorstP50Ms", "{:.1f}", lambda v: v <= 30),
    ("  that command", "startupWorstCommand", "{}", None),
    ("in process, x Slicer at <= its error (target >= 8)", "bestSpeedupAtEqualOrLowerError", "{:.1f}", lambda v: v >= 8),
    ("  that configuration", "bestConfig", "{}", None),
    ("  its mean error / Slicer's (mm)", "errors", "{}", None),
    ("load average before / after", "load", "{}", None),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--out", default="speed-figures")
    parser.add_argument("--runs", type=int, default=3)
    args = parser.parse_args()
    build, out = Path(args.build).resolve(), Path(args.out).resolve()
    for name in BENCHMARKS:
        if not (build / "bin" / name).exists():
            sys.exit(f"speed-figures: {build / 'bin' / name} is missing: build the benchmarks "
                     "(`cmake --build build --target benchmarks`)")
    runs = []
    for i in range(1, args.runs + 1):
        folder = out / f"run-{i}"
        before = load()
        started = time.time()
        for name in BENCHMARKS:
            print(f"run {i}: {name} ...", flush=True)
            run_benchmark(build, name, folder)
        figures = {**drilling(folder), **whole_process(folder), **in_process(folder)}
        figures["errors"] = f"{figures.get('bestMeanErrorMm', 0):.3f} / {figures.get('slicerMeanErrorMm', 0):.3f}"
        figures["load"] = f"{before:.2f} / {load():.2f}"
        figures["seconds"] = time.time() - started
        runs.append(figures)
    conditions = read(out / "run-1" / "rpDrillingBenchmark-conditions.json")
    print("\n| figure | " + " | ".join(f"run {i + 1}" for i in range(len(runs))) + " | target met |")
    print("|---|" + "---|" * (len(runs) + 1))
    for label, key, fmt, target in ROWS:
        values = [r.get(key) for r in runs]
        cells = [fmt.format(v) if v is not None else "—" for v in values]
        met = "" if target is None else ("yes" if all(v is not None and target(v) for v in values) else "no")
        print(f"| {label} | " + " | ".join(cells) + f" | {met} |")
    print("\nconditions (run 1):", json.dumps({k: conditions.get(k) for k in
                                                ("date", "git commit", "build type", "cpu model", "threads", "load average before", "load average after", "steal")}))
    (out / "figures.json").write_text(json.dumps({"runs": runs, "conditions": conditions}, indent=2) + "\n")
    print(f"wrote {out / 'figures.json'}; each run's JSON, CSV and PNG charts in {out}/run-<i>/")


if __name__ == "__main__":
    main()
