#!/usr/bin/env python3
"""Lines per function in RoboPlan's production C++ (the house rule: none over 150).

usage: function-lengths.py [--over N] [--top K] [root]
Counts each definition that starts at column 0 (clang-format: namespaces are not indented) from
its first signature line to its closing brace, comments and blank lines included. Testing/, tests
and benchmarks are not production code and are skipped. Exit 1 when a function is over --limit.
"""
import argparse
import os
import re
import sys

SKIP_DIRS = {"Testing", "build", ".git", "workflow", "Templates"}
SIGNATURE_START = re.compile(r"^[A-Za-z_~][\w:<>,*&~ \[\]]*\(")
NOT_FUNCTION = re.compile(r"^(namespace|struct|class|enum|using|typedef|template\s*<[^>]*>\s*(struct|class)|#|//|})")


def functions(path):
    lines = open(path, encoding="utf-8", errors="replace").read().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        if SIGNATURE_START.match(line) and not NOT_FUNCTION.match(line):
            start = i
            signature = ""
            while i < len(lines) and "{" not in lines[i] and not lines[i].rstrip().endswith(";"):
                signature += lines[i]
                i += 1
            if i >= len(lines) or lines[i].rstrip().endswith(";") and "{" not in lines[i]:
                i += 1
                continue
            signature += lines[i]
            depth = 0
            end = i
            for j in range(i, len(lines)):
                code = re.sub(r'"(\\.|[^"\\])*"|\'(\\.|[^\'\\])*\'|//.*', "", lines[j])
                depth += code.count("{") - code.count("}")
                if depth <= 0:
                    end = j
                    break
            name = re.match(r"^.*?([\w:~]+)\s*\(", signature)
            yield (name.group(1) if name else signature[:40]), start + 1, end - start + 1
            i = end + 1
            continue
        i += 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(__file__), "..", ".."))
    parser.add_argument("--over", type=int, default=100, help="list functions longer than this")
    parser.add_argument("--limit", type=int, default=150, help="exit 1 when one is longer than this")
    args = parser.parse_args()
    found = []
    for folder in ("Libs", "Modules"):
        for dirpath, dirnames, filenames in os.walk(os.path.join(args.root, folder)):
            dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS]
            for f in filenames:
                if f.endswith(".cxx") and not f.endswith("Test.cxx"):
                    path = os.path.join(dirpath, f)
                    for name, line, length in functions(path):
                        found.append((length, os.path.relpath(path, args.root), line, name))
    found.sort(reverse=True)
    over = [f for f in found if f[0] > args.over]
    for length, path, line, name in over:
        print(f"{length:5d}  {name}  {path}:{line}")
    print(f"{len(over)} functions over {args.over} lines, {sum(1 for f in found if f[0] > args.limit)} over "
          f"{args.limit}, of {len(found)}")
    return 1 if any(f[0] > args.limit for f in found) else 0


if __name__ == "__main__":
    sys.exit(main())
