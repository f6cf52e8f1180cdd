#!/usr/bin/env python3
"""One case of the cohort. Every step is a `roboplan` command run with --json; this script runs
it, times it, keeps its JSON and log in the case folder and gathers metrics.json. It holds no
imaging code. It always writes metrics.json and exits 0, so that a case that fails is a row with
its error (the step and roboplan's message) and the other cases finish."""
import argparse
import glob
import json
import os
import re
import shlex
import subprocess
import sys
import time


PROGRESS = re.compile(r"^\[[\w-]+\]\s+\d+%")


def error_message(text, limit=600):
    """roboplan's error: from its first 'roboplan <command>:' line on, progress lines left out,
    on one line (a library's own detail lines follow the first)."""
    lines = [l.strip() for l in text.splitlines() if l.strip() and not PROGRESS.match(l.strip())]
    start = next((n for n, l in enumerate(lines) if l.startswith("roboplan ")), max(len(lines) - 1, 0))
    message = re.sub(r"\(0x[0-9a-f]+\)", "", " ".join(lines[start:])) or "no message"
    return message if len(message) <= limit else message[: limit - 1] + "…"


class Case:
    def __init__(self, args):
        self.args = args
        self.out = os.path.abspath(args.out)
        os.makedirs(self.out, exist_ok=True)
        self.metrics = {"case": args.case, "ok": False, "error": "", "failedStep": "", "input": args.image,
                        "truth": args.truth, "steps": {}, "warnings": []}

    def run(self, step, arguments, required=True):
        """Runs `roboplan <arguments> --json`; returns its JSON or None (and records the failure)."""
        command = [self.args.roboplan] + arguments + ["--json"]
        log_path = os.path.join(self.out, f"{step}.log")
        start = time.monotonic()
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=self.args.timeout,
                                  env=dict(os.environ, OMP_NUM_THREADS=str(self.args.threads)))
            code, stdout, stderr = done.returncode, done.stdout, done.stderr
        except subprocess.TimeoutExpired as e:
            code, stdout, stderr = -1, e.stdout or "", (e.stderr or "") + f"\ntimed out after {self.args.timeout} s"
            stdout = stdout.decode() if isinstance(stdout, bytes) else stdout
            stderr = stderr.decode() if isinstance(stderr, bytes) else stderr
        seconds = time.monotonic() - start
        with open(log_path, "w") as f:
            f.write("$ " + shlex.join(command) + "\n" + stderr)
        result = None
        try:
            result = json.loads(stdout) if stdout.strip() else None
        except json.JSONDecodeError:
            pass
        if result is not None:
            with open(os.path.join(self.out, f"{step}.json"), "w") as f:
                json.dump(result, f, indent=2)
        self.metrics["steps"][step] = {"seconds": round(seconds, 3), "exitCode": code}
        if code != 0:
            message = f"{step}: {error_message(stderr)}" if code != -1 else f"{step}: timed out after {self.args.timeout} s"
            if code < -1 or code > 2:
                message += f" (exit code {code})"
            if required:
                self.metrics.update(error=message, failedStep=step)
                return None
            self.metrics["warnings"].append(message)
        return result

    def process(self):
        a = self.args
        if not os.path.exists(a.image):
            self.metrics.update(error=f"read: no such file or folder '{a.image}'", failedStep="read")
            return
        volume = os.path.join(self.out, "volume.nrrd")
        read = self.run("read", ["convert", a.image, volume])
        if read is None:
            return
        self.metrics["volume"] = {k: read.get(k) for k in ("dimensions", "spacing", "modality", "scalarRange")}
        models = os.path.join(self.out, "models")
        mesh = self.run("mesh", ["mesh", volume, "--out", models] + shlex.split(a.mesh_args))
        if mesh is None:
            return
        self.metrics["segments"] = [self.segment(s) for s in mesh.get("segments", [])]
        display = sorted(s["display"]["file"] for s in mesh.get("segments", []) if s.get("ok") and "display" in s)
        if display:
            self.run("thumbnail", ["screenshot"] + display +
                     ["--out", os.path.join(self.out, "thumbnail.png"), "--layout", "3d", "--size", a.thumbnail_size],
                     required=False)
        if a.truth:
            segmentation = os.path.join(models, "segmentation.seg.nrrd")
            truth = self.run("truth", ["compare-labels", segmentation, a.truth])
            if truth is None:
                return
            self.metrics["truthMetrics"] = truth.get("segments", [])
        self.metrics["ok"] = True

    @staticmethod
    def segment(s):
        d, h = s.get("display", {}), s.get("haptic", {})
        return {"id": s.get("id"), "name": s.get("name"), "tissueClass": s.get("tissueClass"), "ok": s.get("ok"),
                "error": s.get("error", ""), "labelVolumeMm3": d.get("labelVolumeMm3"),
                "meshVolumeMm3": d.get("meshVolumeMm3"), "volumeErrorPercent": d.get("volumeErrorPercent"),
                "displayTriangles": d.get("triangles"), "hapticTriangles": h.get("triangles"),
                "watertight": d.get("watertight"), "seconds": d.get("seconds")}

    def write(self, total):
        self.metrics["seconds"] = round(total, 3)
        self.metrics["host"] = os.uname().nodename
        self.metrics["slurmJobId"] = os.environ.get("SLURM_JOB_ID", "")
        thumbnail = os.path.join(self.out, "thumbnail.png")
        self.metrics["thumbnail"] = "thumbnail.png" if os.path.exists(thumbnail) else ""
        path = os.path.join(self.out, "metrics.json")
        with open(path + ".part", "w") as f:
            json.dump(self.metrics, f, indent=2)
        os.replace(path + ".part", path)


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--roboplan", required=True)
    p.add_argument("--case", required=True)
    p.add_argument("--image", required=True)
    p.add_argument("--truth", default="")
    p.add_argument("--out", required=True)
    p.add_argument("--mesh-args", default="")
    p.add_argument("--timeout", type=float, default=1800)
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--thumbnail-size", default="320x320")
    args = p.parse_args()
    start = time.monotonic()
    case = Case(args)
    try:
        case.process()
    except Exception as e:  # a bug here must still leave the case's row, not stop the cohort
        case.metrics.update(ok=False, error=f"workflow: {type(e).__name__}: {e}", failedStep="workflow")
    case.write(time.monotonic() - start)
    print(f"{args.case}: {'ok' if case.metrics['ok'] else 'FAILED ' + case.metrics['error']} "
          f"({case.metrics['seconds']:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
