"""Finds the cases of a cohort and the roboplan executable (no imaging: names and paths only)."""
import csv
import os
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET


def find_roboplan(configured, workflow_dir):
    """The executable: the config's, $ROBOPLAN, the build tree beside workflow/, then PATH."""
    candidates = [configured, os.environ.get("ROBOPLAN", ""),
                  os.path.join(workflow_dir, "..", "build", "bin", "roboplan"), shutil.which("roboplan") or ""]
    for path in candidates:
        if path and os.access(path, os.X_OK):
            return os.path.abspath(path)
    raise SystemExit("cohort: no roboplan executable (set --config roboplan=PATH or $ROBOPLAN)")


def mesh_options(roboplan):
    """The longflags `roboplan mesh` declares (its Slicer descriptor), with '-' as on the command line."""
    xml = subprocess.run([roboplan, "mesh", "--xml"], check=True, capture_output=True, text=True).stdout
    return {flag.text.replace("_", "-") for flag in ET.fromstring(xml).iter("longflag")}


def mesh_args(configured, roboplan):
    """The per-case mesh options: the config's, or bones one by one when roboplan has --split-bones
    (else the bone preset's largest component)."""
    if configured and configured != "auto":
        return configured
    if "split-bones" in mesh_options(roboplan):
        return "--preset bone --split-bones"
    return "--preset bone --keep-largest --fill-holes"


def volume_extensions(roboplan):
    """What roboplan reads as a volume, from its own Slicer descriptor (the one list of formats)."""
    xml = subprocess.run([roboplan, "mesh", "--xml"], check=True, capture_output=True, text=True).stdout
    for image in ET.fromstring(xml).iter("image"):
        return [e for e in image.get("fileExtensions", "").split(",") if e and not e.endswith(".seg.nrrd")]
    raise SystemExit("cohort: `roboplan mesh --xml` lists no image input")


def existing(path):
    """[path] when it exists, else [] (Snakemake inputs)."""
    return [path] if path and os.path.exists(path) else []


def case_id(name):
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "case"


def _strip_extension(name, extensions):
    for ext in sorted(extensions, key=len, reverse=True):
        if name.lower().endswith(ext):
            return name[: -len(ext)]
    return None


def discover(cohort, roboplan):
    """{case id: {"image": path, "truth": path or ""}}, in a stable order."""
    if not cohort:
        raise SystemExit("cohort: give --config cohort=<folder or CSV>")
    cohort = os.path.abspath(cohort)
    cases = {}

    def add(name, image, truth=""):
        key = case_id(name)
        if key in cases:
            raise SystemExit(f"cohort: two cases are named '{key}' ({cases[key]['image']} and {image})")
        cases[key] = {"image": image, "truth": truth}

    if os.path.isfile(cohort) and cohort.lower().endswith(".csv"):
        base = os.path.dirname(cohort)
        with open(cohort, newline="") as f:
            for row_number, row in enumerate(csv.DictReader(f), start=2):
                if not row.get("case") or not row.get("image"):
                    raise SystemExit(f"cohort: {cohort}:{row_number}: needs the columns case,image[,truth]")
                resolve = lambda p: os.path.normpath(os.path.join(base, p.strip())) if p and p.strip() else ""
                add(row["case"].strip(), resolve(row["image"]), resolve(row.get("truth", "")))
    elif os.path.isdir(cohort):
        extensions = volume_extensions(roboplan)
        for entry in sorted(os.listdir(cohort)):
            path = os.path.join(cohort, entry)
            if entry.startswith("."):
                continue
            if os.path.isdir(path):
                add(entry, path)  # a DICOM series folder
            elif (stem := _strip_extension(entry, extensions)) is not None:
                add(stem, path)
    else:
        raise SystemExit(f"cohort: '{cohort}' is neither a folder nor a .csv file")
    if not cases:
        raise SystemExit(f"cohort: no cases in '{cohort}'")
    return cases
