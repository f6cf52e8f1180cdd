#!/usr/bin/env python3
"""The CLI descriptors cannot drift from the options: for `mesh`, `register` and
`register-volumes`, this test reads each command's Slicer Execution Model XML (`--xml`) and
Boutiques JSON (`--boutiques`), checks them against the rules of Slicer's ModuleDescriptionParser
and of the Boutiques 0.5 schema, checks that they list exactly the options `--help` lists, then
runs each command from the arguments the descriptor lists - the way Slicer (`--longflag value`,
positionals by index) and a Boutiques runner (value-key substitution) build the command line -
and checks that it succeeds and writes the outputs the descriptor names.

usage: cli_descriptor_test.py <roboplan> <work dir>"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

ROBOPLAN, WORK = sys.argv[1], os.path.abspath(sys.argv[2])
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)
    return condition


def run(args, **kw):
    return subprocess.run([ROBOPLAN] + args, capture_output=True, text=True, **kw)


# ---- sample data: the built-in phantom, two fiducial lists --------------------------------------
shutil.rmtree(WORK, ignore_errors=True)
os.makedirs(WORK)
done = run(["phantom", "--out", os.path.join(WORK, "phantom"), "--size", "small", "--format", "nrrd", "--json"])
if done.returncode != 0:
    sys.exit("cannot write the phantom: " + done.stderr)
phantom = json.loads(done.stdout)
ct, mr = phantom["ct"]["path"], phantom["mr"]["path"]
for path in (ct, mr):
    if not os.path.exists(path):
        sys.exit(f"the phantom has no {path}: {json.dumps(phantom)[:400]}")


def write_fcsv(path, points):
    with open(path, "w") as f:
        f.write("# Markups fiducial file version = 4.11\n# CoordinateSystem = LPS\n"
                "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID\n")
        for n, (x, y, z) in enumerate(points):
            f.write(f"vtkMRMLMarkupsFiducialNode_{n},{x},{y},{z},0,0,0,1,1,1,0,F-{n + 1},,\n")


moving = [(10.0, 0.0, 0.0), (0.0, 20.0, 0.0), (0.0, 0.0, 30.0), (15.0, 15.0, 5.0), (-10.0, 5.0, 12.0)]
fixed = [(-y + 5.0, x - 3.0, z + 7.0) for x, y, z in moving]  # 90 degrees about S, then a shift
write_fcsv(os.path.join(WORK, "from.fcsv"), moving)
write_fcsv(os.path.join(WORK, "to.fcsv"), fixed)

# Values for what has no default (and faster settings for the registration); the rest of each
# descriptor's parameters are passed with their declared defaults, which must be accepted.
SAMPLES = {
    "mesh": {"input": ct, "out": os.path.join(WORK, "{runner}-mesh"), "fill_holes": True, "keep_largest": True,
             "haptic_triangles": "5000"},
    "register": {"from": os.path.join(WORK, "from.fcsv"), "to": os.path.join(WORK, "to.fcsv"),
                 "out": os.path.join(WORK, "{runner}-register.tfm"), "target": "1,2,3"},
    "register-volumes": {"fixed": ct, "moving": mr, "out": os.path.join(WORK, "{runner}-register-volumes.tfm"),
                         "centre": True, "levels": "4,2", "iterations": "300", "sampling": "0.1",
                         "truth": os.path.join(WORK, "phantom", "MRToCT-truth.tfm")},
}

IDENTIFIER = re.compile(r"^[_A-Za-z][_A-Za-z0-9]*$")
TAGS = {"integer", "float", "double", "string", "boolean", "integer-vector", "float-vector", "double-vector",
        "string-vector", "point", "region", "string-enumeration", "integer-enumeration", "float-enumeration",
        "double-enumeration", "file", "directory", "transform", "image", "geometry", "table", "measurement"}
TYPE_VALUES = {"image": {"any", "scalar", "label", "tensor", "diffusion-weighted", "vector"},
               "transform": {"linear", "nonlinear", "bspline"}, "geometry": {"fiberbundle", "model"}}


def help_options(command):
    text = run([command, "--help"]).stdout
    return {m for m in re.findall(r"^  --([a-z0-9-]+)", text, re.M)} - {"help", "json", "xml"}, text


def slicer_parameters(command):
    """Checks the XML as Slicer's ModuleDescriptionParser does; returns its parameters."""
    done = run([command, "--xml"])
    check(done.returncode == 0, f"{command} --xml exits 0")
    root = ET.fromstring(done.stdout)
    check(root.tag == "executable", f"{command}: <executable> is the outermost tag")
    for tag in ("title", "description", "version", "category"):
        check(root.find(tag) is not None and (root.find(tag).text or "").strip(), f"{command}: <{tag}> given")
    params, indices = [], []
    for group in root.findall("parameters"):
        check(group.find("label") is not None and group.find("description") is not None,
              f"{command}: every <parameters> has a label and a description")
        for p in group:
            if p.tag in ("label", "description"):
                continue
            check(p.tag in TAGS, f"{command}: <{p.tag}> is a Slicer parameter type")
            name, longflag, index = p.findtext("name", ""), p.findtext("longflag"), p.findtext("index")
            check(IDENTIFIER.match(name), f"{command}: <name>{name}</name> is a valid identifier")
            check((longflag is None) != (index is None), f"{command}: {name} has a longflag or an index, not both")
            if longflag is not None:
                check(IDENTIFIER.match(longflag.lstrip("-")), f"{command}: <longflag>{longflag}</longflag> is valid")
            else:
                indices.append(int(index))
            check(p.findtext("label") and p.findtext("description") is not None, f"{command}: {name} has a label")
            if p.tag in TYPE_VALUES and p.get("type"):
                check(p.get("type") in TYPE_VALUES[p.tag], f"{command}: {name} type='{p.get('type')}' is allowed")
            if p.tag == "point":
                check(p.get("coordinateSystem") in (None, "ras", "lps", "ijk"), f"{command}: {name} coordinateSystem")
            channel = p.findtext("channel")
            check(channel in (None, "input", "output"), f"{command}: {name} channel is input or output")
            default = p.findtext("default")
            if p.tag.endswith("enumeration"):
                elements = [e.text for e in p.findall("element")]
                check(elements and default in elements, f"{command}: {name} default '{default}' is one of {elements}")
            if p.tag in ("integer", "double") and default is not None and p.find("constraints") is not None:
                c = p.find("constraints")
                lo, hi = c.findtext("minimum"), c.findtext("maximum")
                check((lo is None or float(lo) <= float(default)) and (hi is None or float(default) <= float(hi)),
                      f"{command}: {name} default {default} is within its constraints")
            params.append(p)
    check(sorted(indices) == list(range(len(indices))), f"{command}: indices run 0..n-1 ({indices})")
    return params


def slicer_command_line(command, params, samples):
    """The command line as Slicer builds it: flagged parameters, then positionals by index."""
    flags, positional = [], {}
    for p in params:
        name = p.findtext("name")
        value = samples.get(name, p.findtext("default"))
        if p.findtext("index") is not None:
            positional[int(p.findtext("index"))] = value
        elif p.tag == "boolean":
            if value is True or value == "true":
                flags.append("--" + p.findtext("longflag"))
        elif value not in (None, ""):
            flags += ["--" + p.findtext("longflag"), str(value)]
    return [command] + flags + [positional[i] for i in sorted(positional)]


BOUTIQUES_TOP = {"name", "tool-version", "description", "deprecated-by-doi", "author", "url", "descriptor-url", "doi",
                 "shell", "tool-doi", "command-line", "container-image", "schema-version", "environment-variables",
                 "groups", "inputs", "tests", "online-platform-urls", "output-files", "invocation-schema",
                 "suggested-resources", "tags", "error-codes", "custom"}
BOUTIQUES_INPUT = {"id", "name", "type", "description", "value-key", "list", "list-separator", "optional",
                   "command-line-flag", "requires-inputs", "disables-inputs", "command-line-flag-separator",
                   "default-value", "value-choices", "value-requires", "value-disables", "integer", "minimum",
                   "maximum", "exclusive-minimum", "exclusive-maximum", "min-list-entries", "max-list-entries",
                   "uses-absolute-path"}
BOUTIQUES_OUTPUT = {"id", "name", "description", "value-key", "path-template", "conditional-path-template",
                    "path-template-stripped-extensions", "list", "optional", "command-line-flag",
                    "command-line-flag-separator", "uses-absolute-path", "file-template"}
BOUTIQUES_ID = re.compile(r"^[0-9,_,a-z,A-Z]*$")


def boutiques_descriptor(command):
    """Checks the descriptor against the Boutiques 0.5 schema's rules; returns it."""
    done = run([command, "--boutiques"])
    check(done.returncode == 0, f"{command} --boutiques exits 0")
    d = json.loads(done.stdout)
    check(set(d) <= BOUTIQUES_TOP, f"{command}: no property outside the schema ({set(d) - BOUTIQUES_TOP})")
    for key in ("name", "description", "command-line", "schema-version", "inputs", "tool-version"):
        check(key in d, f"{command}: Boutiques '{key}' given")
    check(d.get("schema-version") == "0.5", f"{command}: schema-version 0.5")
    ids = [i["id"] for i in d["inputs"]]
    check(len(ids) == len(set(ids)), f"{command}: input ids are unique")
    for i in d["inputs"]:
        what = f"{command}: input {i.get('id')}"
        check(set(i) <= BOUTIQUES_INPUT, f"{what}: no property outside the schema ({set(i) - BOUTIQUES_INPUT})")
        check({"id", "name", "type"} <= set(i) and BOUTIQUES_ID.match(i["id"]), f"{what}: id, name and type")
        check(i["type"] in ("String", "File", "Flag", "Number"), f"{what}: type {i['type']}")
        check(i.get("value-key", "") in d["command-line"], f"{what}: value-key in the command line")
        if i["type"] == "Flag":
            check("command-line-flag" in i and not i.get("list"), f"{what}: a Flag has a flag and is no list")
        for key in ("integer", "minimum", "maximum"):
            check(key not in i or i["type"] == "Number", f"{what}: {key} only on a Number")
        check("value-choices" not in i or i["type"] in ("String", "Number"), f"{what}: value-choices on String/Number")
        check("list-separator" not in i or "list" in i, f"{what}: list-separator needs list")
        for key in ("exclusive-minimum", "exclusive-maximum"):
            check(key not in i or key.split("-")[1] in i, f"{what}: {key} needs its bound")
        if "value-choices" in i and "default-value" in i:
            defaults = i["default-value"] if i.get("list") else [i["default-value"]]
            check(all(v in i["value-choices"] for v in defaults), f"{what}: default is one of the choices")
    for o in d.get("output-files", []):
        check(set(o) <= BOUTIQUES_OUTPUT and {"id", "name", "path-template"} <= set(o), f"{command}: output {o.get('id')}")
    return d


def boutiques_command_line(d, samples):
    """What a Boutiques runner (bosh) runs for an invocation: value-keys substituted."""
    line, values = d["command-line"], {}
    for i in d["inputs"]:
        value = samples.get(i["id"], i.get("default-value"))
        if i["type"] == "Flag":
            text = i["command-line-flag"] if value is True else ""
        elif value in (None, ""):
            text = ""
        else:
            items = value if isinstance(value, list) else [value]
            joined = i.get("list-separator", " ").join(str(v) for v in items) if i.get("list") else str(value)
            values[i["value-key"]] = joined
            flag = i.get("command-line-flag")
            text = f"{flag}{i.get('command-line-flag-separator', ' ')}{joined}" if flag else joined
        line = line.replace(i["value-key"], text)
    outputs = []
    for o in d.get("output-files", []):
        path = o["path-template"]
        for key, value in values.items():
            path = path.replace(key, value)
        outputs.append((o, path))
    return shlex.split(line), outputs


for command, samples in SAMPLES.items():
    declared, help_text = help_options(command)
    # -- Slicer
    params = slicer_parameters(command)
    listed = {p.findtext("longflag").replace("_", "-") for p in params if p.findtext("longflag")}
    check(listed == declared, f"{command}: the XML lists the --help options (missing {declared - listed}, "
                              f"extra {listed - declared})")
    slicer_samples = {k: (v.format(runner="slicer") if isinstance(v, str) else v) for k, v in samples.items()}
    argv = slicer_command_line(command, params, slicer_samples)
    print("slicer:", shlex.join(argv))
    done = run(argv, timeout=300)
    check(done.returncode == 0, f"{command} run from its XML exits 0: {done.stderr[-600:]}")
    for p in params:
        if p.findtext("channel") == "output" and p.findtext("name") in slicer_samples:
            path = slicer_samples[p.findtext("name")]
            check(os.path.exists(path), f"{command}: the XML's output {p.findtext('name')} was written ({path})")
    # -- Boutiques
    d = boutiques_descriptor(command)
    flags = {i["command-line-flag"][2:] for i in d["inputs"] if "command-line-flag" in i}
    check(flags == declared, f"{command}: Boutiques lists the --help options (missing {declared - flags}, "
                             f"extra {flags - declared})")
    b_samples = {k: (v.format(runner="boutiques") if isinstance(v, str) else v) for k, v in samples.items()}
    argv, outputs = boutiques_command_line(d, b_samples)
    print("boutiques:", shlex.join(argv))
    check(argv[:2] == ["roboplan", command], f"{command}: the Boutiques command line starts 'roboplan {command}'")
    done = subprocess.run([ROBOPLAN] + argv[1:], capture_output=True, text=True, timeout=300)
    check(done.returncode == 0, f"{command} run from its Boutiques descriptor exits 0: {done.stderr[-600:]}")
    for o, path in outputs:
        check(os.path.exists(path), f"{command}: Boutiques output {o['id']} was written ({path})")

# A repeated option through the Boutiques list separator (`--seed a --seed b`), and Slicer's
# underscore longflags, reach the parser as the same option.
done = run(["mesh", ct, "--out", os.path.join(WORK, "seeds"), "--method", "region-grow", "--seed", "0,0,0",
            "--seed", "5,5,5", "--haptic_triangles", "2000", "--no_haptic", "--json"], timeout=300)
check(done.returncode in (0, 1) and "unknown option" not in done.stderr, "repeated seeds and _ longflags parse")

print(f"{len(failures)} failed" if failures else "all descriptor checks passed")
sys.exit(1 if failures else 0)
