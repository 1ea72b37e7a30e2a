#!/usr/bin/python3
"""bivo's IPM next to CVXOPT on the public conic suite (tests/conic_suite), ECOS-style timings.

Runs bivo_bench's BM_ConicSuite cases (each iteration a whole solve_conic call on data read
once: set-up excluded) and CVXOPT's conelp (Debian python3-cvxopt) on the same data (matrices
built once outside the timing), each solve repeated; reports per problem the median CPU time
of a solve, the exit of each solver against the manifest, the ratio CVXOPT time / bivo time,
the geometric mean of that ratio over the problems both answer right, the median bivo time
per solve over the problems bivo solves in under 1 ms, and the polish's time over the rest of
the solve's (set-up and iterations; "rejected" when the answer is not the polished point). Both run single-threaded (BLAS threads
set to 1) at the same tolerances (1e-8 absolute, relative and feasibility).

  benchmarks/conic_suite_vs_cvxopt.py [--bench build/benchmarks/bivo_bench] [--repetitions 5]
                                      [--min-time 0.5] [--filter REGEX] [--json out.json]
                                      [--markdown out.md]
On the ill-posed problem (manifest well_posed false) an answer is right when it is not "optimal".
"""
import argparse
import json
import math
import os
import re
import statistics
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
HERE = os.path.dirname(os.path.abspath(__file__))
SUITE = os.path.join(HERE, "..", "tests", "conic_suite")
sys.path.insert(0, os.path.join(SUITE, "tools"))
sys.path.insert(0, HERE)
import cvxopt_solve  # noqa: E402
from gbench_runs import gbench_runs  # noqa: E402
from cbf_reader import read_cbf  # noqa: E402


def bivo_times(bench, repetitions, filt, min_time):
    runs = gbench_runs([bench, "--benchmark_filter=BM_ConicSuite(_NoPolish)?/.*(%s)" % filt,
                        "--benchmark_repetitions=%d" % repetitions, "--benchmark_min_time=%g" % min_time])
    out = {}
    for name, bs in runs.items():
        kind, problem = name.split("/", 1)
        last = bs[-1]
        out[(problem, kind == "BM_ConicSuite")] = {
            "ms": statistics.median(b["cpu_time"] for b in bs) / 1e3,  # microseconds -> ms
            "iterations": int(last["iterations"]), "right": bool(last["right"]),
            "polish_share": statistics.median(b.get("polish_share", 0.0) for b in bs),
            "polished": bool(last.get("polished", 0)),
            "exit": last.get("label", ""), "objective_error": last.get("objective_error")}
    return out


def cvxopt_time(problem, entry, repetitions):
    status, objective, _, _ = cvxopt_solve.solve(problem, tol=1e-8, repeats=1)
    times = []
    for _ in range(repetitions):
        t0 = time.process_time()
        cvxopt_solve.solve(problem, tol=1e-8, repeats=1)
        times.append(time.process_time() - t0)
    right = status == entry["status"] if entry.get("well_posed", True) else status != "optimal"
    if right and entry["objective"] is not None:
        right = abs(objective - entry["objective"]) <= 1e-6 * max(1.0, abs(entry["objective"]))
    return {"ms": 1e3 * statistics.median(times), "status": status, "right": right}


def geomean(xs):
    xs = [x for x in xs if x and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(HERE, "..", "build", "benchmarks", "bivo_bench"))
    ap.add_argument("--repetitions", type=int, default=5, help="runs per case; the median CPU time is reported")
    ap.add_argument("--filter", default=".*", help="regular expression on problem names")
    ap.add_argument("--min-time", type=float, default=0.5, help="Google Benchmark's minimum time per run [s]")
    ap.add_argument("--json", help="also write the rows here")
    ap.add_argument("--markdown", help="also write the table here")
    a = ap.parse_args()
    if not os.access(a.bench, os.X_OK):
        sys.exit("error: %s is not an executable (build it: ninja -C build bivo_bench)" % a.bench)
    manifest = json.load(open(os.path.join(SUITE, "manifest.json")))["problems"]
    manifest = [e for e in manifest if re.search(a.filter, e["name"])]
    bivo = bivo_times(a.bench, a.repetitions, a.filter, a.min_time)
    rows = []
    for e in manifest:
        cv = cvxopt_time(read_cbf(os.path.join(SUITE, e["file"])), e, a.repetitions)
        b, bn = bivo.get((e["name"], True)), bivo.get((e["name"], False))
        if b is None or bn is None:
            sys.exit("error: bivo_bench has no case for %s (rebuild bivo_bench)" % e["name"])
        if not e.get("well_posed", True):  # no certificate exists: right is claiming no optimum
            b["right"] = not b["exit"].startswith("optimal")
            bn["right"] = not bn["exit"].startswith("optimal")
        expected = e["status"] + ("" if e.get("well_posed", True) else " (ill-posed)")
        rows.append({"name": e["name"], "size": e["size"], "expected": expected, "bivo_ms": b["ms"],
                     "bivo_no_polish_ms": bn["ms"], "iterations": b["iterations"], "bivo_exit": b["exit"],
                     "polish_share": b["polish_share"], "polished": b["polished"],
                     "bivo_right": b["right"], "bivo_no_polish_right": bn["right"],
                     "bivo_objective_error": b["objective_error"], "cvxopt_ms": cv["ms"],
                     "cvxopt_status": cv["status"], "cvxopt_right": cv["right"],
                     "ratio": cv["ms"] / b["ms"] if b["ms"] > 0 else None})
    lines = ["| problem | size | expected | bivo ms | no polish ms | polish/rest | iter. | bivo exit | CVXOPT ms "
             "| CVXOPT exit | CVXOPT/bivo |", "|---|---|---|---:|---:|---:|---:|---|---:|---|---:|"]
    for r in rows:
        lines.append("| %s | %s | %s | %.3f | %.3f | %.2f%s | %d | %s%s | %.3f | %s%s | %.2f |" % (
            r["name"], r["size"], r["expected"], r["bivo_ms"], r["bivo_no_polish_ms"], r["polish_share"],
            "" if r["polished"] else " (rejected)", r["iterations"],
            r["bivo_exit"], "" if r["bivo_right"] else " **WRONG**", r["cvxopt_ms"], r["cvxopt_status"],
            "" if r["cvxopt_right"] else " (wrong)", r["ratio"]))
    both = [r for r in rows if r["bivo_right"] and r["cvxopt_right"]]
    small = [r["bivo_ms"] for r in rows if r["bivo_ms"] < 1.0]
    summary = [
        "problems: %d; bivo right %d (no polish %d), CVXOPT right %d" % (
            len(rows), sum(r["bivo_right"] for r in rows), sum(r["bivo_no_polish_right"] for r in rows),
            sum(r["cvxopt_right"] for r in rows)),
        "geometric mean of CVXOPT time / bivo time over the %d problems both answer right: %.2f" % (
            len(both), geomean([r["ratio"] for r in both])),
        "same, bivo without the polish: %.2f" % geomean([r["cvxopt_ms"] / r["bivo_no_polish_ms"] for r in both]),
        "median bivo time per solve on the %d problems under 1 ms: %.4f ms (without the polish: %.4f ms)" % (
            len(small), statistics.median(small) if small else float("nan"),
            statistics.median([r["bivo_no_polish_ms"] for r in rows if r["bivo_ms"] < 1.0]) if small else float("nan")),
        "median bivo time per solve over all problems: %.4f ms; CVXOPT: %.4f ms" % (
            statistics.median(r["bivo_ms"] for r in rows), statistics.median(r["cvxopt_ms"] for r in rows)),
    ]
    worst = max(rows, key=lambda r: r["polish_share"])
    summary.append("largest polish time / rest of the solve's time: %.2f (%s, %s); above 1 on %d problems" % (
        worst["polish_share"], worst["name"], "polished" if worst["polished"] else "polish rejected",
        sum(r["polish_share"] > 1.0 for r in rows)))
    text = "\n".join(lines + [""] + summary) + "\n"
    print(text)
    if a.markdown:
        with open(a.markdown, "w") as f:
            f.write(text)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
