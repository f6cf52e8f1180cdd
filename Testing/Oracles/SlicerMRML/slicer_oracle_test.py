#!/usr/bin/env python3
"""RoboPlan's .mrml/.mrb against 3D Slicer 5.0.3's own MRML library (the oracle program
rpSlicerMrmlOracle, built by SlicerMRML.cmake). Python 3 standard library only.

    slicer_oracle_test.py <case> --oracle PROGRAM --oracle-source DIR --roboplan PROGRAM --work DIR

Cases (README.md beside this file says what each proves):
  oracle             Slicer writes its scene (WriteToMRB) and reads it back with no error or warning,
                     with the analytic values it was built with: the oracle itself is right.
  slicer-roundtrip   Slicer's .mrb -> `roboplan convert` -> .mrb, .mrml, and via .rpscene -> .mrb;
                     each loads in MRMLCore with no error and the values MRMLCore read from Slicer's.
  roboplan-to-slicer a RoboPlan scene (the demo's, and its plan.mrb) -> .mrb: loads in MRMLCore with
                     no error or warning, with the values RoboPlan wrote.
  plan-markups       plans: Slicer writes a markups line and planes (.mrk.json each, and an .mrb);
                     `roboplan plan show` reads them as trajectories and cut planes with Slicer's
                     points; what RoboPlan writes (`plan show --out`, `plan trajectory/screw/plane
                     --out`, `convert` to .mrb) loads in MRMLCore as vtkMRMLMarkupsLineNode /
                     vtkMRMLMarkupsPlaneNode with the same points (1e-6 mm) and no error or warning.
  testing-scenes     every .mrml in Slicer's Libs/MRML/Core/Testing: `roboplan convert X.mrml
                     out.mrb` exits 0 or 1 (never a signal or a hang); what it wrote (also with
                     exit 1: a data file Slicer's test data lacks is missing) loads in
                     MRMLCore with the values MRMLCore reads from X.mrml, for the node types
                     RoboPlan supports.
Exit: 0 pass, 1 fail, 77 skipped (the oracle folder is absent; with ROBOPLAN_REQUIRE_SHARED_DATA
set that is a failure instead).
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

SKIP = 77
# The node classes RoboPlan reads and writes (issue 26), compared value by value.
SUPPORTED = {
    "vtkMRMLScalarVolumeNode", "vtkMRMLLabelMapVolumeNode", "vtkMRMLModelNode",
    "vtkMRMLLinearTransformNode", "vtkMRMLSegmentationNode", "vtkMRMLMarkupsFiducialNode",
    "vtkMRMLMarkupsLineNode", "vtkMRMLMarkupsPlaneNode",
}
MATRIX_TOL = 1e-9
POINT_TOL = 1e-6  # mm
COLOR_TOL = 1e-6


# ------------------------------------------------------------------ running programs
class Runner:
    def __init__(self, args):
        self.args = args
        self.log = []

    def run(self, argv, timeout=120, oracle=False):
        env = dict(os.environ)
        if oracle:  # Slicer's libraries leak a little at exit; not ours to report
            env["ASAN_OPTIONS"] = "detect_leaks=0:" + env.get("ASAN_OPTIONS", "")
        start = time.monotonic()
        try:
            p = subprocess.run(argv, capture_output=True, text=True, timeout=timeout, env=env)
        except subprocess.TimeoutExpired:
            return None, "", "timed out after %d s" % timeout, timeout
        return p.returncode, p.stdout, p.stderr, time.monotonic() - start

    def oracle(self, command, path):
        rc, out, err, seconds = self.run([self.args.oracle, command, path], oracle=True)
        print("  oracle %s %s: exit %s, %.2f s" % (command, os.path.basename(path), rc, seconds))
        try:
            result = json.loads(out)
        except ValueError:
            raise Failure("oracle %s %s printed no JSON (exit %s): %s" % (command, path, rc, err[-2000:]))
        return rc, result

    def convert(self, src, dst, timeout=120):
        rc, out, err, seconds = self.run([self.args.roboplan, "convert", src, dst], timeout=timeout)
        print("  roboplan convert %s %s: exit %s, %.2f s" % (os.path.basename(src), os.path.basename(dst), rc, seconds))
        return rc, out, err


class Failure(Exception):
    pass


class Checks:
    """Collects failed expectations with clear messages, and the largest differences measured."""

    def __init__(self):
        self.failures = []
        self.max_diff = {}

    def expect(self, ok, message):
        if not ok:
            self.failures.append(message)
        return ok

    def close(self, what, kind, got, want, tol):
        if got is None or want is None or len(got) != len(want):
            return self.expect(False, "%s: %s is %s, expected %s" % (what, kind, got, want))
        diff = max((abs(a - b) for a, b in zip(got, want)), default=0.0)
        self.max_diff[kind] = max(self.max_diff.get(kind, 0.0), diff)
        return self.expect(diff <= tol, "%s: %s differs by %.3g (tolerance %g): %s, expected %s" % (what, kind, diff, tol, got, want))

    def equal(self, what, kind, got, want):
        return self.expect(got == want, "%s: %s is %r, expected %r" % (what, kind, got, want))


def no_messages(checks, result, what):
    m = result["messages"]
    checks.expect(m["errors"] == 0 and m["warnings"] == 0,
                  "%s: MRMLCore logged %d errors and %d warnings: %s" % (
                      what, m["errors"], m["warnings"], "; ".join(x["text"].strip()[:300] for x in m["list"][:8])))


# ------------------------------------------------------------------ 4x4 matrices (row-major lists)
def matmul(a, b):
    return [sum(a[r * 4 + k] * b[k * 4 + c] for k in range(4)) for r in range(4) for c in range(4)]


def translate(x, y, z):
    return [1, 0, 0, x, 0, 1, 0, y, 0, 0, 1, z, 0, 0, 0, 1]


def rotate(degrees, axis):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m = [1.0 if r == k else 0.0 for r in range(4) for k in range(4)]
    m[i * 4 + i], m[i * 4 + j], m[j * 4 + i], m[j * 4 + j] = c, -s, s, c
    return m


def scale(x, y, z):
    return [x, 0, 0, 0, 0, y, 0, 0, 0, 0, z, 0, 0, 0, 0, 1]


def apply(m, p):
    return [sum(m[r * 4 + k] * (p[k] if k < 3 else 1.0) for k in range(4)) for r in range(3)]


# ------------------------------------------------------------------ case: the oracle itself
def expected_oracle_scene():
    """The values rpSlicerMrmlOracle write-mrb builds its scene with (closed form)."""
    outer = matmul(translate(5.0, -3.0, 12.0), rotate(20.0, 0))
    inner = matmul(translate(-7.0, 2.0, 4.5), rotate(35.0, 2))
    inner_world = matmul(outer, inner)
    dims = (24, 20, 16)
    values = [(-1000 + 3 * i + 50 * j + 125 * k, (i + dims[0] * (j + dims[1] * k)))
              for k in range(dims[2]) for j in range(dims[1]) for i in range(dims[0])]
    points = [("F-1", [1.0, 2.0, 3.0]), ("F-2", [-10.5, 20.25, 7.0]), ("F-3", [30.0, -4.0, -12.125])]
    return {
        "Outer": {"toParent": outer, "toWorld": outer},
        "Inner": {"toParent": inner, "toWorld": inner_world},
        "CT": {"ijkToRas": matmul(matmul(translate(-9.6, 12.0, -20.0), rotate(30.0, 2)), scale(0.8, 0.9, 1.25)),
               "dimensions": list(dims), "sum": float(sum(v for v, _ in values)),
               "weightedSum": float(sum(v * (n % 1009 + 1) for v, n in values)), "min": -1000.0,
               "max": float(-1000 + 3 * 23 + 50 * 19 + 125 * 15)},
        "Labels": {"ijkToRas": [1.5, 0, 0, 5.0, 0, 1.5, 0, -6.0, 0, 0, 2.0, 7.5, 0, 0, 0, 1],
                   "sum": float(sum((1 if i < 6 else (2 if j > 5 else 0)) for k in range(8) for j in range(10) for i in range(12)))},
        "Femur": {"points": 16 * 10 + 2, "firstPoint": [10.0, -5.0, 35.0], "color": [0.9, 0.8, 0.6], "opacity": 0.7,
                  "attributes": {"RoboPlan.tissueClass": "bone", "RoboPlan.haptic": "true", "Lab.Surgeon": "A. N. Other"}},
        "Drill": {"points": 24, "bounds": [-4.0, 6.0, -3.0, 3.5, 2.0, 12.25], "parent": "Outer"},
        "F": {"parent": "Inner", "points": [(label, p, apply(inner_world, p)) for label, p in points]},
        "Segmentation": {"segments": [("Bone", [0.9, 0.85, 0.7], 1920), ("Tumor", [1.0, 0.0, 0.0], 64)]},
    }


def by_name(dump):
    """Nodes by name; Slicer's colour tables (named Labels, Grey...) are not looked up by name."""
    nodes = {}
    for n in dump["nodes"]:
        if "Color" not in n["class"]:
            nodes.setdefault(n["name"], n)
    return nodes


def has_data(n):
    """False for a storable node whose data file MRMLCore could not read (Slicer keeps the empty
    node, RoboPlan names the file and skips it) and for volumetric meshes (RoboPlan's models are
    surfaces): nothing to compare."""
    if n["class"] in ("vtkMRMLScalarVolumeNode", "vtkMRMLLabelMapVolumeNode"):
        return "voxels" in n
    if n["class"] == "vtkMRMLModelNode":
        return n.get("meshType") == "vtkPolyData"
    if n["class"] == "vtkMRMLSegmentationNode":
        return bool(n.get("segments"))
    return True


def names_by_id(dump):
    return {n["id"]: n["name"] for n in dump["nodes"]}


def check_oracle_scene(checks, dump):
    """The analytic scene, as MRMLCore reads it from the bundle."""
    want = expected_oracle_scene()
    nodes = by_name(dump)
    ids = names_by_id(dump)
    for name in ("Outer", "Inner"):
        n = nodes.get(name)
        if checks.expect(n is not None, "transform %s missing" % name):
            checks.close(name, "matrix", n.get("toParent"), want[name]["toParent"], MATRIX_TOL)
            checks.close(name, "matrix", n.get("toWorld"), want[name]["toWorld"], MATRIX_TOL)
    for name in ("CT", "Labels"):
        n = nodes.get(name)
        if not checks.expect(n is not None and "voxels" in n, "volume %s missing or without voxels" % name):
            continue
        checks.close(name, "matrix", n["ijkToRas"], want[name]["ijkToRas"], 1e-6)  # NRRD header text
        checks.equal(name, "voxel sum", n["voxels"]["sum"], want[name]["sum"])
    ct = nodes.get("CT", {})
    if "voxels" in ct:
        checks.equal("CT", "dimensions", ct["dimensions"], want["CT"]["dimensions"])
        for key in ("weightedSum", "min", "max"):
            checks.equal("CT", "voxel " + key, ct["voxels"][key], want["CT"][key])
    femur, drill = nodes.get("Femur", {}), nodes.get("Drill", {})
    checks.equal("Femur", "point count", femur.get("points"), want["Femur"]["points"])
    checks.close("Femur", "model point", femur.get("firstPoint"), want["Femur"]["firstPoint"], POINT_TOL)
    if femur.get("display"):
        checks.close("Femur", "colour", femur["display"][0]["color"], want["Femur"]["color"], COLOR_TOL)
        checks.close("Femur", "opacity", [femur["display"][0]["opacity"]], [want["Femur"]["opacity"]], COLOR_TOL)
    for key, value in want["Femur"]["attributes"].items():
        checks.equal("Femur", "attribute " + key, femur.get("attributes", {}).get(key), value)
    checks.equal("Drill", "point count", drill.get("points"), want["Drill"]["points"])
    checks.close("Drill", "model point", drill.get("bounds"), want["Drill"]["bounds"], POINT_TOL)
    checks.equal("Drill", "parent transform", ids.get(drill.get("parentTransform")), "Outer")
    fiducials = nodes.get("F", {})
    checks.equal("F", "parent transform", ids.get(fiducials.get("parentTransform")), "Inner")
    got = fiducials.get("controlPoints", [])
    checks.equal("F", "control point count", len(got), len(want["F"]["points"]))
    for g, (label, local, world) in zip(got, want["F"]["points"]):
        checks.equal("F", "label", g["label"], label)
        checks.close("F " + label, "markup point", g["position"], local, POINT_TOL)
        checks.close("F " + label, "markup point", g["world"], world, POINT_TOL)
    segments = nodes.get("Segmentation", {}).get("segments", [])
    checks.equal("Segmentation", "segments", [s["name"] for s in segments], [s[0] for s in want["Segmentation"]["segments"]])
    for s, (name, color, voxels) in zip(segments, want["Segmentation"]["segments"]):
        checks.close("segment " + name, "colour", s["color"], color, COLOR_TOL)
        checks.equal("segment " + name, "voxel count", s.get("voxels"), voxels)


def case_oracle(runner, checks):
    bundle = os.path.join(runner.args.work, "slicer.mrb")
    rc, written = runner.oracle("write-mrb", bundle)
    checks.expect(rc == 0, "Slicer's WriteToMRB failed: %s" % written["messages"])
    no_messages(checks, written, "WriteToMRB")
    rc, dump = runner.oracle("dump", bundle)
    checks.expect(rc == 0, "Slicer's ReadFromMRB failed on its own bundle")
    no_messages(checks, dump, "ReadFromMRB of Slicer's own bundle")
    check_oracle_scene(checks, dump)


# ------------------------------------------------------------------ comparing two MRMLCore dumps
def node_key(n):
    return (n["class"], n["name"])


def compare_node(checks, what, a, b, ids_a, ids_b):
    """b (RoboPlan's rewrite, read by MRMLCore) against a (the original, read by MRMLCore)."""
    for key, value in a.get("attributes", {}).items():
        checks.equal(what, "attribute " + key, b.get("attributes", {}).get(key), value)
    checks.equal(what, "parent transform", ids_b.get(b.get("parentTransform")), ids_a.get(a.get("parentTransform")))
    for key in ("toParent", "toWorld"):
        if key in a:
            checks.close(what, "matrix", b.get(key), a[key], MATRIX_TOL)
    if "ijkToRas" in a:
        checks.close(what, "matrix", b.get("ijkToRas"), a["ijkToRas"], MATRIX_TOL)
    for key in ("dimensions", "scalarType", "components", "voxels"):
        if key in a:
            checks.equal(what, key, b.get(key), a[key])
    if "points" in a:
        checks.equal(what, "point count", b.get("points"), a["points"])
        checks.equal(what, "cell count", b.get("cells"), a.get("cells"))
        for key in ("firstPoint", "lastPoint", "bounds"):
            if key in a:
                checks.close(what, "model point", b.get(key), a[key], POINT_TOL)
    if "controlPoints" in a:
        pa, pb = a["controlPoints"], b.get("controlPoints", [])
        checks.equal(what, "control point labels", [p["label"] for p in pb], [p["label"] for p in pa])
        for p, q in zip(pa, pb):
            checks.close(what + " " + p["label"], "markup point", q["position"], p["position"], POINT_TOL)
            checks.close(what + " " + p["label"], "markup point", q["world"], p["world"], POINT_TOL)
    if "plane" in a:
        compare_plane(checks, what, a["plane"], b.get("plane"))
    if "segments" in a:
        sa, sb = a["segments"], b.get("segments", [])
        checks.equal(what, "segment names", [s["name"] for s in sb], [s["name"] for s in sa])
        for s, t in zip(sa, sb):
            checks.close(what + " segment " + s["name"], "colour", t["color"], s["color"], COLOR_TOL)
            checks.equal(what + " segment " + s["name"], "voxel count", t.get("voxels"), s.get("voxels"))
    compare_display(checks, what, a, b)


def compare_display(checks, what, a, b):
    da, db = a.get("display", []), b.get("display", [])
    if not da:
        return
    if not checks.expect(len(db) > 0, "%s: no display node (the original has %s)" % (what, da[0]["class"])):
        return
    x, y = da[0], db[0]
    checks.equal(what, "display class", y["class"], x["class"])
    if "Markups" in x["class"]:
        checks.close(what, "colour", y["selectedColor"], x["selectedColor"], COLOR_TOL)
    elif "Volume" not in x["class"] and "Segmentation" not in x["class"]:
        checks.close(what, "colour", y["color"], x["color"], COLOR_TOL)
    checks.close(what, "opacity", [y["opacity"]], [x["opacity"]], COLOR_TOL)
    for key in ("visibility", "visibility2D", "visibility3D"):
        checks.equal(what, "display " + key, y[key], x[key])
    for key in ("window", "level"):
        if key in x:
            checks.close(what, "window/level", [y.get(key)], [x[key]], 1e-6)


def compare_dumps(checks, original, rewrite, label):
    """Every supported node of `original` is in `rewrite` (by class and name) with equal values."""
    ids_a, ids_b = names_by_id(original), names_by_id(rewrite)
    nodes_b = {}
    for n in rewrite["nodes"]:
        nodes_b.setdefault(node_key(n), n)
    compared = 0
    for a in original["nodes"]:
        what = "%s: %s '%s'" % (label, a["class"], a["name"])
        if a["class"] not in SUPPORTED:
            continue
        if not has_data(a):
            print("  %s: MRMLCore read no data for it (file missing, or a volumetric mesh): not compared" % what)
            continue
        b = nodes_b.get(node_key(a))
        if checks.expect(b is not None, "%s is missing after RoboPlan's rewrite (nodes there: %s)" % (
                what, sorted("%s '%s'" % k for k in nodes_b if k[0] in SUPPORTED))):
            compare_node(checks, what, a, b, ids_a, ids_b)
            compared += 1
    return compared


# ------------------------------------------------------------------ case: Slicer -> RoboPlan -> Slicer
def case_slicer_roundtrip(runner, checks):
    work = runner.args.work
    bundle = os.path.join(work, "slicer.mrb")
    rc, written = runner.oracle("write-mrb", bundle)
    if not checks.expect(rc == 0, "Slicer's WriteToMRB failed: %s" % written["messages"]):
        return
    _, original = runner.oracle("dump", bundle)
    no_messages(checks, original, "Slicer's bundle read by MRMLCore")
    routes = [("rp.mrb", [("slicer.mrb", "rp.mrb")]),
              ("rp.mrml", [("slicer.mrb", "rp-mrml/rp.mrml")]),
              ("rpscene", [("slicer.mrb", "rp-scene/rp.rpscene"), ("rp-scene/rp.rpscene", "rp-scene.mrb")])]
    for label, steps in routes:
        ok = True
        for src, dst in steps:
            os.makedirs(os.path.dirname(os.path.join(work, dst)), exist_ok=True)
            rc, out, err = runner.convert(os.path.join(work, src), os.path.join(work, dst))
            ok = checks.expect(rc == 0, "%s: roboplan convert %s %s exited %s: %s" % (label, src, dst, rc, (out + err).strip()[-1500:]))
            if not ok:
                break
        if not ok:
            continue
        rc, rewrite = runner.oracle("dump", os.path.join(work, steps[-1][1]))
        checks.expect(rc == 0, "%s: MRMLCore could not read RoboPlan's %s" % (label, steps[-1][1]))
        no_messages(checks, rewrite, "%s: RoboPlan's %s read by MRMLCore" % (label, steps[-1][1]))
        compared = compare_dumps(checks, original, rewrite, label)
        print("  %s: %d nodes compared" % (label, compared))


# ------------------------------------------------------------------ case: RoboPlan -> Slicer
def case_roboplan_to_slicer(runner, checks):
    work = runner.args.work
    made = os.path.join(work, "made", "scene.rpscene")
    rc, out, err, _ = runner.run([runner.args.scene_maker, made])
    if checks.expect(rc == 0, "rpSlicerOracleSceneMaker failed (exit %s): %s" % (rc, (out + err)[-1500:])):
        bundle = os.path.join(work, "made.mrb")
        rc, out, err = runner.convert(made, bundle)
        if checks.expect(rc == 0, "every-node-class scene: roboplan convert exited %s: %s" % (rc, (out + err).strip()[-1500:])):
            rc, dump = runner.oracle("dump", bundle)
            checks.expect(rc == 0, "every-node-class scene: MRMLCore could not read it")
            no_messages(checks, dump, "every-node-class scene")
            check_roboplan_scene(checks, dump, made, "every-node-class scene")
    demo = runner.args.demo_dir
    if demo:  # rpDemoSystemTest's small demo (its fixture), not run twice
        print("  the small demo's output: %s" % demo)
    else:
        demo = os.path.join(work, "demo")
        rc, out, err, seconds = runner.run([runner.args.roboplan, "demo", "--size", "small", "--haptic-seconds", "1",
                                            "--no-screenshots", "--out", demo], timeout=600)
        print("  roboplan demo --size small: exit %s, %.1f s" % (rc, seconds))
        if not checks.expect(rc == 0, "roboplan demo failed (exit %s): %s" % (rc, (out + err)[-1500:])):
            return
    scene = os.path.join(demo, "scene.rpscene")
    targets = [("demo scene.rpscene -> .mrb", scene, os.path.join(work, "demo-scene.mrb"))]
    plan = os.path.join(demo, "plan.mrb")
    if checks.expect(os.path.exists(plan), "roboplan demo wrote no %s" % plan):
        targets.append(("demo plan.mrb", None, plan))
    for label, src, bundle in targets:
        if src:
            rc, out, err = runner.convert(src, bundle)
            if not checks.expect(rc == 0, "%s: roboplan convert exited %s: %s" % (label, rc, (out + err).strip()[-1500:])):
                continue
        rc, dump = runner.oracle("dump", bundle)
        checks.expect(rc == 0, "%s: MRMLCore could not read it" % label)
        no_messages(checks, dump, label)
        check_roboplan_scene(checks, dump, scene, label)


# RoboPlan's node classes and the MRML classes they are written as.
RP_TO_MRML = {
    "vtkRPScalarVolumeNode": ("vtkMRMLScalarVolumeNode", "vtkMRMLLabelMapVolumeNode"),
    "vtkRPLinearTransformNode": ("vtkMRMLLinearTransformNode",),
    "vtkRPTrackedToolNode": ("vtkMRMLLinearTransformNode",),
    "vtkRPModelNode": ("vtkMRMLModelNode",),
    "vtkRPSegmentationNode": ("vtkMRMLSegmentationNode",),
    "vtkRPFiducialListNode": ("vtkMRMLMarkupsFiducialNode",),
    "vtkRPTrajectoryNode": ("vtkMRMLMarkupsLineNode",),
    "vtkRPScrewNode": ("vtkMRMLMarkupsLineNode",),
    "vtkRPCutPlaneNode": ("vtkMRMLMarkupsPlaneNode",),
    "vtkRPSliceNode": ("vtkMRMLSliceNode",),
    "vtkRPLayoutNode": ("vtkMRMLLayoutNode",),
}


def numbers(text):
    return [float(x) for x in text.split()]


def control_points_of(path):
    """Control points (RAS) of a Slicer markups JSON file RoboPlan wrote."""
    with open(path) as f:
        doc = json.load(f)
    markup = doc["markups"][0]
    flip = [-1.0, -1.0, 1.0] if markup.get("coordinateSystem", "LPS") == "LPS" else [1.0, 1.0, 1.0]
    return [(p.get("label", ""), [a * b for a, b in zip(p["position"], flip)]) for p in markup.get("controlPoints", [])]


def check_roboplan_scene(checks, dump, rpscene, label):
    """What MRMLCore reads is what RoboPlan's scene file (and its data files) hold, node by node."""
    with open(rpscene) as f:
        scene = json.load(f)
    folder = os.path.dirname(rpscene)
    rp_names = {n["id"]: n["name"] for n in scene.get("nodes", [])}
    mrml_names = names_by_id(dump)
    compared = 0
    for n in scene.get("nodes", []):
        classes = RP_TO_MRML.get(n["class"])
        what = "%s: %s '%s'" % (label, n["class"], n["name"])
        if classes is None:
            print("  %s: no MRML class expected, not compared" % what)
            continue
        got = [m for m in dump["nodes"] if m["class"] in classes and m["name"] == n["name"]]
        if not checks.expect(len(got) == 1, "%s: %d MRML nodes of class %s with that name" % (what, len(got), "/".join(classes))):
            continue
        check_roboplan_node(checks, what, n, got[0], folder, rp_names, mrml_names)
        compared += 1
    print("  %s: %d RoboPlan nodes compared" % (label, compared))


def check_roboplan_node(checks, what, n, m, folder, rp_names, mrml_names):
    props, attributes = n.get("properties", {}), m.get("attributes", {})
    for key, value in n.get("attributes", {}).items():
        checks.equal(what, "attribute " + key, attributes.get(key), value)
    for key in ("tissueClass", "haptic"):  # issue 26: survive a trip through Slicer as attributes
        if key in props:
            checks.equal(what, "attribute RoboPlan." + key, attributes.get("RoboPlan." + key), props[key])
    parent = dict(n.get("references", {})).get("transform", [None])
    parent = rp_names.get(parent[0]) if isinstance(parent, list) and parent else None
    checks.equal(what, "parent transform", mrml_names.get(m.get("parentTransform")), parent)
    if "matrixToParent" in props:
        checks.close(what, "matrix", m.get("toParent"), numbers(props["matrixToParent"]), MATRIX_TOL)
    if "ijkToRAS" in props and "ijkToRas" in m:
        checks.close(what, "matrix", m.get("ijkToRas"), numbers(props["ijkToRAS"]), MATRIX_TOL)
    display = (m.get("display") or [{}])[0]
    if "color" in props and display:
        key = "selectedColor" if "Markups" in display.get("class", "") else "color"
        checks.close(what, "colour", display.get(key), numbers(props["color"]), COLOR_TOL)
    if "opacity" in props and display:
        checks.close(what, "opacity", [display.get("opacity")], [float(props["opacity"])], COLOR_TOL)
    if "visibility" in props and display:
        checks.equal(what, "visibility", bool(display.get("visibility")), props["visibility"] == "true")
    for key in ("window", "level"):
        if key in props and display:
            checks.close(what, "window/level", [display.get(key)], [float(props[key])], 1e-6)
    if "segments" in props:
        want = json.loads(props["segments"])
        got = m.get("segments", [])
        checks.equal(what, "segment names", [s["name"] for s in got], [s["name"] for s in want])
        for s, t in zip(want, got):
            checks.close(what + " segment " + s["name"], "colour", t["color"], s["color"], COLOR_TOL)
    for key in ("orientation", "layoutName"):  # slice views
        if key in props:
            checks.equal(what, key, m.get(key), props[key])
    if n["class"] in ("vtkRPFiducialListNode", "vtkRPTrajectoryNode", "vtkRPScrewNode", "vtkRPCutPlaneNode") and n.get("dataFile"):
        want = control_points_of(os.path.join(folder, n["dataFile"]))
        got = m.get("controlPoints", [])
        checks.equal(what, "control point labels", [p["label"] for p in got], [p[0] for p in want])
        for (lab, p), q in zip(want, got):
            checks.close(what + " " + lab, "markup point", q["position"], p, POINT_TOL)


# ------------------------------------------------------------------ case: plans (markups lines and planes)
def compare_plane(checks, what, want, got):
    """A plane's geometry: origin (mm) and unit normal and x axis, world too; size."""
    if not checks.expect(got is not None, "%s: no plane geometry" % what):
        return
    for key in ("origin", "originWorld"):
        checks.close(what, "markup point", got[key], want[key], POINT_TOL)
    for key in ("normal", "normalWorld", "xAxis"):
        checks.close(what, "plane axis", got[key], want[key], 1e-9)
    checks.close(what, "plane size", got["size"], want["size"], 1e-9)


def roboplan_json(runner, argv, what, checks):
    rc, out, err, _ = runner.run([runner.args.roboplan] + argv)
    print("  roboplan %s: exit %s" % (" ".join(os.path.basename(a) for a in argv[:3]), rc))
    if not checks.expect(rc == 0, "%s: roboplan %s exited %s: %s" % (what, " ".join(argv), rc, (out + err).strip()[-1500:])):
        return None
    try:
        return json.loads(out)
    except ValueError:
        checks.expect(False, "%s: no JSON from roboplan: %s" % (what, out[-500:]))
        return None


def check_show(checks, shown, slicer_node, what):
    """`roboplan plan show --json` of a Slicer file against what MRMLCore wrote."""
    plans = shown["plans"] if shown else []
    if not checks.expect(len(plans) == 1, "%s: %d plans read" % (what, len(plans))):
        return
    p = plans[0]
    want_class = "vtkRPCutPlaneNode" if "plane" in slicer_node else "vtkRPTrajectoryNode"
    checks.equal(what, "RoboPlan class", p["class"], want_class)
    if "plane" in slicer_node:
        g = slicer_node["plane"]
        checks.close(what, "markup point", p["origin"], g["origin"], POINT_TOL)
        checks.close(what, "plane axis", p["normal"], g["normal"], 1e-9)
        checks.close(what, "plane axis", p["xAxis"], g["xAxis"], 1e-9)
        checks.close(what, "plane size", p["sizeMm"], g["size"], 1e-9)
    else:
        pts = slicer_node["controlPoints"]
        checks.close(what, "markup point", p["entry"], pts[0]["position"], POINT_TOL)
        checks.close(what, "markup point", p["target"], pts[1]["position"], POINT_TOL)


def check_loaded_markups(checks, loaded, want_class, what, points=None, plane=None):
    """MRMLCore's load-markups of a file RoboPlan wrote."""
    no_messages(checks, loaded, what)
    nodes = loaded.get("nodes", [])
    if not checks.expect(len(nodes) == 1, "%s: MRMLCore loaded %d nodes" % (what, len(nodes))):
        return
    n = nodes[0]
    checks.equal(what, "MRML class", n["class"], want_class)
    if points is not None:
        got = [p["position"] for p in n.get("controlPoints", [])]
        checks.equal(what, "control point count", len(got), len(points))
        for g, w in zip(got, points):
            checks.close(what, "markup point", g, w, POINT_TOL)
    if plane is not None:
        compare_plane(checks, what, plane, n.get("plane"))


def case_plan_markups(runner, checks):
    work = runner.args.work
    folder = os.path.join(work, "slicer-plan")
    rc, written = runner.oracle("write-plan", folder)
    if not checks.expect(rc == 0, "Slicer could not write its plan: %s" % written["messages"]):
        return
    no_messages(checks, written, "Slicer writing its plan")
    by = {n["name"]: n for n in written["nodes"]}
    # 1. Slicer's files read as our plan nodes, with Slicer's points.
    for name, fname in (("Tunnel", "slicer-line.mrk.json"), ("Resection", "slicer-plane.mrk.json"),
                        ("ThreePoint", "slicer-plane-3points.mrk.json")):
        path = os.path.join(folder, fname)
        shown = roboplan_json(runner, ["plan", "show", path, "--json"], fname, checks)
        # A standalone file has no parent transform: compare the node's own (local) points.
        local = dict(by[name])
        if "plane" in local:
            local["plane"] = dict(local["plane"], originWorld=local["plane"]["origin"], normalWorld=local["plane"]["normal"])
        check_show(checks, shown, local, "Slicer's " + fname)
        # 2. ... and written back by RoboPlan, they load in MRMLCore as Slicer's own classes.
        back = os.path.join(work, "rp-" + fname)
        if roboplan_json(runner, ["plan", "show", path, "--out", back, "--json"], "rewrite " + fname, checks) is None:
            continue
        rc, loaded = runner.oracle("load-markups", back)
        checks.expect(rc == 0, "MRMLCore could not load RoboPlan's %s" % back)
        if "plane" in by[name]:
            want = dict(by[name]["plane"], originWorld=by[name]["plane"]["origin"], normalWorld=by[name]["plane"]["normal"])
            if name == "ThreePoint":  # ours is point-normal: origin, normal, x axis and size kept
                want["planeType"] = "pointNormal"
            check_loaded_markups(checks, loaded, "vtkMRMLMarkupsPlaneNode", "RoboPlan's " + fname, plane=want)
        else:
            check_loaded_markups(checks, loaded, "vtkMRMLMarkupsLineNode", "RoboPlan's " + fname,
                                 points=[p["position"] for p in by[name]["controlPoints"]])
    # 3. Slicer's bundle through `roboplan convert` to .mrb: MRMLCore reads the same plans.
    bundle = os.path.join(folder, "slicer-plan.mrb")
    _, original = runner.oracle("dump", bundle)
    no_messages(checks, original, "Slicer's plan bundle read by MRMLCore")
    rewrite = os.path.join(work, "rp-plan.mrb")
    rc, out, err = runner.convert(bundle, rewrite)
    if checks.expect(rc == 0, "roboplan convert of Slicer's plan bundle exited %s: %s" % (rc, (out + err)[-1500:])):
        rc, dump = runner.oracle("dump", rewrite)
        checks.expect(rc == 0, "MRMLCore could not read RoboPlan's plan bundle")
        no_messages(checks, dump, "RoboPlan's plan bundle read by MRMLCore")
        compared = compare_dumps(checks, original, dump, "plan bundle")
        checks.expect(compared >= 3, "plan bundle: only %d nodes compared (the transform, the line, the plane)" % compared)
    # 4. Plans RoboPlan makes, written as .mrk.json, load in MRMLCore with their points.
    ct = write_small_ct(os.path.join(work, "ct.nrrd"))
    made = [("trajectory", ["plan", "trajectory", "--entry", "10.5,-20.25,30.125", "--target", "-5,12.5,-8.75",
                            "--diameter", "4.5"], "vtkMRMLMarkupsLineNode"),
            ("screw", ["plan", "screw", "--entry", "1,2,3", "--target", "4,-5,36", "--diameter", "3.2",
                       "--screw-length", "30"], "vtkMRMLMarkupsLineNode"),
            ("plane", ["plan", "plane", "--origin", "3,-4,25", "--normal", "0.2,-0.3,0.9", "--size", "80,60"],
             "vtkMRMLMarkupsPlaneNode")]
    for what, argv, mrml_class in made:
        path = os.path.join(work, "made-%s.mrk.json" % what)
        if roboplan_json(runner, argv + ["--volume", ct, "--out", path, "--json"], "plan " + what, checks) is None:
            continue
        shown = roboplan_json(runner, ["plan", "show", path, "--json"], "show " + what, checks)
        if not shown or not checks.expect(len(shown["plans"]) == 1, "%s: %s holds no plan" % (what, path)):
            continue
        ours = shown["plans"][0]
        rc, loaded = runner.oracle("load-markups", path)
        checks.expect(rc == 0, "MRMLCore could not load RoboPlan's %s" % path)
        if what == "plane":
            want = {"origin": ours["origin"], "originWorld": ours["origin"], "normal": ours["normal"],
                    "normalWorld": ours["normal"], "xAxis": ours["xAxis"], "size": ours["sizeMm"]}
            check_loaded_markups(checks, loaded, mrml_class, "RoboPlan's " + what, plane=want)
        else:
            check_loaded_markups(checks, loaded, mrml_class, "RoboPlan's " + what, points=[ours["entry"], ours["target"]])
    # 5. A scene of RoboPlan's plans to .mrb: every plan node is there with its points and fields.
    scene = os.path.join(work, "made-scene", "plan.rpscene")
    os.makedirs(os.path.dirname(scene), exist_ok=True)
    if roboplan_json(runner, ["plan", "screw", "--entry", "1,2,3", "--target", "4,-5,36", "--diameter", "3.2",
                              "--volume", ct, "--out", scene, "--json"], "screw into a scene", checks) is not None:
        bundle = os.path.join(work, "made-scene.mrb")
        rc, out, err = runner.convert(scene, bundle)
        if checks.expect(rc == 0, "convert of the plan scene exited %s: %s" % (rc, (out + err)[-1500:])):
            rc, dump = runner.oracle("dump", bundle)
            checks.expect(rc == 0, "MRMLCore could not read RoboPlan's plan scene")
            no_messages(checks, dump, "RoboPlan's plan scene")
            check_roboplan_scene(checks, dump, scene, "RoboPlan's plan scene")


def write_small_ct(path):
    """A 41^3 CT of 2 mm voxels covering RAS -40..40 mm (NRRD, LPS header): a block of bone
    (700 HU) over RAS -36..36 mm in air (-1000 HU), so a screw fits and a plane cuts bone."""
    header = ("NRRD0004\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 41 41 41\n"
              "space directions: (-2,0,0) (0,-2,0) (0,0,2)\nkinds: domain domain domain\nendian: little\n"
              "encoding: raw\nspace origin: (40,40,-40)\n\n")
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        air, bone = (-1000).to_bytes(2, "little", signed=True), (700).to_bytes(2, "little", signed=True)
        for k in range(41):
            for j in range(41):
                inner = 2 <= k <= 38 and 2 <= j <= 38
                f.write(air * 2 + (bone if inner else air) * 37 + air * 2)
    return path

# ------------------------------------------------------------------ case: Slicer's Testing scenes
def case_testing_scenes(runner, checks):
    testing = os.path.join(runner.args.oracle_source, "Libs", "MRML", "Core", "Testing")
    scenes = sorted(f for f in os.listdir(testing) if f.endswith(".mrml"))
    checks.expect(len(scenes) > 0, "no .mrml scenes in %s" % testing)
    summary = []
    for name in scenes:
        src = os.path.join(testing, name)
        out = os.path.join(runner.args.work, os.path.splitext(name)[0] + ".mrb")
        rc, stdout, stderr = runner.convert(src, out, timeout=60)
        crashed = rc is None or rc < 0 or rc not in (0, 1)
        checks.expect(not crashed, "%s: roboplan convert %s (exit %s; only 0 or 1 allowed): %s" % (
            name, "hung" if rc is None else "crashed", rc, (stdout + stderr).strip()[-800:]))
        if rc == 1:
            checks.expect((stdout + stderr).strip() != "", "%s: roboplan convert exited 1 without a message" % name)
        _, original = runner.oracle("dump", src)
        if rc not in (0, 1) or not os.path.exists(out):  # exit 1 with a bundle: what could be read
            summary.append((name, rc, 0))
            continue
        rc2, rewrite = runner.oracle("dump", out)
        checks.expect(rc2 == 0, "%s: MRMLCore could not read RoboPlan's rewrite" % name)
        summary.append((name, rc, compare_dumps(checks, original, rewrite, name)))
    for name, rc, compared in summary:
        print("  %-40s convert exit %s, %d supported nodes compared" % (name, rc, compared))


# ------------------------------------------------------------------ main
CASES = {"oracle": case_oracle, "slicer-roundtrip": case_slicer_roundtrip,
         "roboplan-to-slicer": case_roboplan_to_slicer, "testing-scenes": case_testing_scenes,
         "plan-markups": case_plan_markups}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("case", choices=sorted(CASES))
    parser.add_argument("--oracle", required=True)
    parser.add_argument("--oracle-source", required=True)
    parser.add_argument("--roboplan", required=True)
    parser.add_argument("--scene-maker", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--demo-dir", help="roboplan-to-slicer: the output folder of a finished "
                        "`roboplan demo --size small` to read, instead of running the demo")
    args = parser.parse_args()
    if not os.path.isdir(args.oracle_source):
        if os.environ.get("ROBOPLAN_REQUIRE_SHARED_DATA", "0") not in ("", "0"):
            print("shared data missing although ROBOPLAN_REQUIRE_SHARED_DATA is set: %s" % args.oracle_source)
            return 1
        print("shared data absent: %s (put ../shared/oracles beside the repository to run this test)" % args.oracle_source)
        return SKIP
    if not os.path.exists(args.oracle):
        print("the oracle program %s is not built (target rpSlicerMRMLBuild)" % args.oracle)
        return 1
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    runner, checks = Runner(args), Checks()
    try:
        CASES[args.case](runner, checks)
    except Failure as e:
        checks.failures.append(str(e))
    print("largest differences measured: %s" % json.dumps({k: float("%.3g" % v) for k, v in sorted(checks.max_diff.items())}))
    for f in checks.failures:
        print("FAIL " + f)
    print("%s: %s" % (args.case, "passed" if not checks.failures else "%d failed expectations" % len(checks.failures)))
    return 0 if not checks.failures else 1


if __name__ == "__main__":
    sys.exit(main())
