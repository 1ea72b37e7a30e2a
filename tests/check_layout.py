#!/usr/bin/env python3
"""The layout and layer rules of docs/architecture.md, checked on every ctest run.

1. Includes of the project's own headers point only downward:
     solvers/geometry                       -> solvers/geometry, solvers/error.h
     solvers/conic (the IPM alone)          -> solvers/conic, solvers/error.h, solvers/profiling.h
     solvers (incl. step/, whole/)          -> solvers
     problems                               -> problems, solvers
     odometry/io                            -> odometry/io, solvers/geometry, solvers/error.h
     odometry/synth                         -> odometry/synth, odometry/io, solvers/geometry, solvers/error.h
     odometry/kernels                       -> odometry/kernels, odometry/weight_model.h, solvers/error.h
     odometry (the instance)                -> odometry, odometry/io, solvers
     experiments (engines, study/)          -> experiments, odometry/*, problems, solvers
     experiments/conic_files                -> experiments/conic_files, odometry/io, solvers/conic, solvers/error.h
     experiments/cli                        -> experiments/cli, experiments, odometry/*, problems, solvers
     python (the bindings)                  -> python, experiments, odometry/*, problems, solvers
   (nothing includes python/: the bindings are the top layer), the engines never include
   CLI11 (only the front ends parse flags), and outside odometry/kernels/ the kernels are
   reached through odometry/kernels/kernels.h alone (the lanes, kernel templates, pools and
   chunk loops stay behind it).
2. The namespace of a layer's files follows its folder (bivo::odometry::io, ...); plain
   `bivo` holds only the project-wide error type.
3. A source file longer than 500 lines is an error unless LONG_FILES names it with the reason
   (then a warning): split files by concept, not by size.

Usage: check_layout.py REPOSITORY_ROOT  (or --self-test: plants one violation of each kind). Prints every violation with file:line; exit 1 if any.
"""
import pathlib
import re
import sys

MAX_LINES = 500
# Files allowed past MAX_LINES, each with why it is one concept: {path: reason}.
LONG_FILES = {}

# (folder, allowed include prefixes, namespace its files open). Longest folder match wins.
LAYERS = [
    ("solvers", ["solvers/"], "bivo::solvers"),
    ("solvers/geometry", ["solvers/geometry/", "solvers/error.h"], "bivo::solvers"),
    ("solvers/conic", ["solvers/conic/", "solvers/error.h", "solvers/profiling.h"], "bivo::solvers"),
    ("problems", ["problems/", "solvers/"], "bivo::problems"),
    ("odometry/io", ["odometry/io/", "solvers/geometry/", "solvers/error.h"], "bivo::odometry::io"),
    ("odometry/synth", ["odometry/synth/", "odometry/io/", "solvers/geometry/", "solvers/error.h"],
     "bivo::odometry::synth"),
    ("odometry/kernels", ["odometry/kernels/", "odometry/weight_model.h", "solvers/error.h"], "bivo::odometry"),
    ("odometry", ["odometry/", "solvers/"], "bivo::odometry"),
    ("experiments", ["experiments/", "odometry/", "problems/", "solvers/"], "bivo::experiments"),
    ("experiments/conic_files", ["experiments/conic_files/", "odometry/io/", "solvers/conic/", "solvers/error.h"],
     "bivo::experiments"),
    ("experiments/cli", ["experiments/", "odometry/", "problems/", "solvers/"], "bivo::experiments::cli"),
    ("python", ["python/", "experiments/", "odometry/", "problems/", "solvers/"], "bivo::python"),
]
KERNELS = "odometry/kernels/"
KERNELS_INTERFACE = "odometry/kernels/kernels.h"
SOURCE_SUFFIXES = {".h", ".cpp", ".py", ".sh"}
SOURCE_FOLDERS = ["solvers", "problems", "odometry", "experiments", "python", "tests", "benchmarks", "scripts",
                  "examples"]
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]')
NAMESPACE = re.compile(r"^namespace\s+([A-Za-z_][\w:]*)\s*\{")


def layer_of(rel):
    best = None
    for folder, allowed, ns in LAYERS:
        if rel.startswith(folder + "/") and (best is None or len(folder) > len(best[0])):
            best = (folder, allowed, ns)
    return best


def include_allowed(folder, allowed, target):
    if not any(target.startswith(p) for p in allowed):
        return False
    if target.startswith(KERNELS) and folder != "odometry/kernels" and target != KERNELS_INTERFACE:
        return False  # the kernels' private headers
    # odometry/ allows odometry/*, but io and synth may not reach the instance or each other.
    if folder in ("odometry/io", "odometry/synth", "odometry/kernels") and target.startswith("odometry/"):
        return any(target.startswith(p) for p in allowed if p.startswith("odometry/"))
    if folder == "odometry" and target.startswith("odometry/synth/"):
        return False  # the instance does not render
    return True


def check(root):
    problems = []
    files = [p for top in SOURCE_FOLDERS if (root / top).is_dir() for p in (root / top).rglob("*")
             if p.is_file() and p.suffix in SOURCE_SUFFIXES]
    for path in sorted(files):
        rel = path.relative_to(root).as_posix()
        text = path.read_text(errors="replace").splitlines()
        if len(text) > MAX_LINES:
            if rel in LONG_FILES:
                print(f"warning: {rel}: {len(text)} lines (allowed: {LONG_FILES[rel]})")
            else:
                problems.append(f"{rel}: {len(text)} lines (more than {MAX_LINES}): split it by concept, "
                                "or name it in LONG_FILES with the reason")
        layer = layer_of(rel)
        if layer is None or path.suffix not in (".h", ".cpp"):
            continue
        folder, allowed, ns = layer
        for no, line in enumerate(text, 1):
            m = INCLUDE.match(line)
            if m:
                target = m.group(1)
                ours = target.split("/")[0] in ("solvers", "problems", "odometry", "experiments", "python")
                if ours and not include_allowed(folder, allowed, target):
                    problems.append(f"{rel}:{no}: includes {target}, which layer {folder}/ may not use")
                if folder == "experiments" and target.startswith("CLI/"):
                    problems.append(f"{rel}:{no}: the engines must not depend on CLI11 ({target})")
            m = NAMESPACE.match(line)
            # Plain `bivo` is the project-wide error type (solvers/error.h).
            if m and m.group(1).startswith("bivo") and m.group(1) not in (ns, "bivo"):
                # solvers/conic etc. may nest deeper (bivo::solvers::conic).
                if not (folder.startswith("solvers") and m.group(1).startswith(ns + "::")):
                    problems.append(f"{rel}:{no}: namespace {m.group(1)}, but files of {folder}/ use {ns}")
    return files, problems


def self_test():
    """The checker must fail on each kind of violation: a tree with one of each."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        root = pathlib.Path(tmp)
        bad = {
            "odometry/io/a.h": '#include "odometry/tracker.h"\nnamespace bivo::odometry::io {\n}\n',
            "odometry/b.cpp": '#include "experiments/x.h"\nnamespace bivo::odometry {\n}\n',
            "experiments/c.cpp": "#include <CLI/CLI.hpp>\nnamespace bivo::experiments {\n}\n",
            "odometry/synth/d.cpp": "namespace bivo::odometry {\n}\n",
            "solvers/e.cpp": "\n" * (MAX_LINES + 1),
            "odometry/f.cpp": '#include "odometry/io/png_io.h"\n#include "solvers/geometry/se3.h"\n',  # fine
            "experiments/g.cpp": '#include "python/bindings.h"\n',
            "odometry/h.cpp": '#include "odometry/kernels/simd_lanes.h"\n#include "odometry/kernels/kernels.h"\n',
            "odometry/kernels/i.cpp": '#include "odometry/tracker.h"\n#include "odometry/weight_model.h"\n',
            "odometry/io/j.cpp": '#include "solvers/conic/ipm_solver.h"\n#include "solvers/geometry/se3.h"\n',
            "solvers/conic/k.cpp": '#include "solvers/problem.h"\n',
        }
        for rel, text in bad.items():
            (root / rel).parent.mkdir(parents=True, exist_ok=True)
            (root / rel).write_text(text)
        _, problems = check(root)
        expected = ["odometry/io/a.h:1", "odometry/b.cpp:1", "experiments/c.cpp:1", "odometry/synth/d.cpp:1",
                    "solvers/e.cpp:", "experiments/g.cpp:1", "odometry/h.cpp:1", "odometry/kernels/i.cpp:1",
                    "odometry/io/j.cpp:1", "solvers/conic/k.cpp:1"]
        missing = [e for e in expected if not any(p.startswith(e) for p in problems)]
        extra = [p for p in problems if p.startswith("odometry/f.cpp")]
        if missing or extra or len(problems) != len(expected):
            print("check_layout self-test FAILED: missing", missing, "unexpected", extra, "all", problems)
            return 1
    print(f"check_layout self-test: all {len(expected)} planted violations found")
    return 0


def main():
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    files, problems = check(root)
    for p in problems:
        print(p)
    print(f"check_layout: {len(files)} files, {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
