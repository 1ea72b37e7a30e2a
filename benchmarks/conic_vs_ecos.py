#!/usr/bin/python3
"""The paper's SOCP (eq. `SOCP in our method`) against the ECOS yardstick.

Runs bivo_bench's BM_PaperSocp cases (make_paper_step instances: raw units, t-distribution
weights, 10 % invalid pixels kept as zero rows, constraint active and inactive, 3 seeds per
size, 40x30 .. 640x480) and prints per instance: CPU ms per solve, iterations, the step's
relative error against the exact QCQP step, the exit, the ratio to the ECOS CPU time measured
on such instances, and the time by phase. The project has no ECOS; the yardstick is the
measured ECOS 2.0.10 CPU ms per solve (rescaled data, its more reliable configuration).

  benchmarks/conic_vs_ecos.py [--bench build/benchmarks/bivo_bench] [--sizes 40,80,160]
                              [--repetitions 3] [--json out.json]
"""
import argparse
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gbench_runs import gbench_runs  # noqa: E402

# ECOS CPU ms per solve (active, inactive); 640x480: ECOS did not converge on any instance.
ECOS_MS = {40: (8.2, 5.0), 80: (44.0, 25.0), 160: (279.0, 131.0), 320: (9700.0, 1500.0)}
PHASES = ["validation", "equilibration", "kkt_setup", "ordering", "symbolic", "residuals", "g_passes",
          "kkt_factor", "kkt_solve", "refinement", "cones", "polish", "other"]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=os.path.join(here, "..", "build", "benchmarks", "bivo_bench"))
    ap.add_argument("--sizes", default="40,80,160,320,640", help="image widths (4:3)")
    ap.add_argument("--repetitions", type=int, default=3, help="runs per case; the median CPU time is reported")
    ap.add_argument("--json", help="also write the rows here")
    a = ap.parse_args()
    if not os.access(a.bench, os.X_OK):
        sys.exit(f"error: {a.bench} is not an executable (build it: cmake --build build --target bivo_bench)")
    widths = [int(w) for w in a.sizes.split(",")]
    filt = "BM_PaperSocp/(" + "|".join(str(w) for w in widths) + ")/"
    runs = gbench_runs([a.bench, "--benchmark_filter=" + filt, "--benchmark_repetitions=%d" % a.repetitions,
                        "--benchmark_report_aggregates_only=false"])
    rows = []
    for name, bs in runs.items():
        _, width, active, seed = name.split("/")[:4]
        width, active, seed = int(width), int(active), int(seed)
        cpu = statistics.median(b["cpu_time"] for b in bs)  # ms (Unit kMillisecond)
        last = bs[-1]
        ecos = ECOS_MS.get(width, (None, None))[0 if active else 1]
        rows.append({"width": width, "height": width * 3 // 4, "active": active, "seed": seed, "cpu_ms": cpu,
                     "iterations": int(last["iterations"]), "step_error": last["step_error"],
                     "optimal": bool(last["optimal"]), "polished": bool(last["polished"]),
                     "fallback": bool(last.get("fallback", 0)),
                     "exit": last.get("label", ""), "ecos_ms": ecos, "x_ecos": ecos / cpu if ecos else None,
                     "phases_ms": {p: last.get("ms_" + p, 0.0) for p in PHASES}})
    rows.sort(key=lambda r: (r["width"], -r["active"], r["seed"]))
    print("| size | constraint | seed | CPU ms/solve | iterations | step error | exit | ECOS ms | x ECOS |")
    print("|---|---|---:|---:|---:|---:|---|---:|---:|")
    for r in rows:
        x = "%.1f" % r["x_ecos"] if r["x_ecos"] else "n/a"
        e = "%.0f" % r["ecos_ms"] if r["ecos_ms"] else "failed"
        print("| %dx%d | %s | %d | %.3f | %d | %.1e | %s%s | %s | %s |" % (
            r["width"], r["height"], "active" if r["active"] else "inactive", r["seed"], r["cpu_ms"],
            r["iterations"], r["step_error"], "optimal" if r["optimal"] else "NOT optimal",
            " (compressed-form fallback)" if r["fallback"] else (" (polished)" if r["polished"] else ""), e, x))
    print("\nTime by phase of one solve [ms] (the last repetition):\n")
    print("| size | constraint | seed | " + " | ".join(PHASES) + " |")
    print("|---|---|---:|" + "---:|" * len(PHASES))
    for r in rows:
        print("| %dx%d | %s | %d | " % (r["width"], r["height"], "active" if r["active"] else "inactive", r["seed"]) +
              " | ".join("%.3f" % r["phases_ms"][p] for p in PHASES) + " |")
    bad = [r for r in rows if r["step_error"] > 1e-6 or not r["optimal"]]
    short = [r for r in rows if r["x_ecos"] is not None and r["x_ecos"] < 10]
    print("\nexit texts:")
    for r in rows:
        print("  %dx%d %s seed %d: %s" % (r["width"], r["height"], "active" if r["active"] else "inactive", r["seed"],
                                          r["exit"]))
    print("\nsteps off the exact step by > 1e-6 or not a clean optimum: %d of %d" % (len(bad), len(rows)))
    print("instances below 10x the ECOS yardstick: %d of %d" % (len(short), sum(r["x_ecos"] is not None for r in rows)))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
