#!/usr/bin/python3
"""Two builds of bivo_bench side by side: the same cases, run in turn (A, B, A, B, ...) so a
shared machine's drift hits both alike; prints per case the median CPU time per solve of each
and the ratio B/A, then each build's median over its cases under 1 ms. Quote the ratios: the
absolute figures move with the machine's load.

  benchmarks/bench_side_by_side.py --a OLD/bivo_bench --b NEW/bivo_bench
                                   [--filter 'BM_Conic(Small|Huber)'] [--rounds 3] [--repetitions 5]
"""
import argparse
import json
import statistics
import subprocess
import sys


def run(binary, bench_filter, repetitions):
    out = subprocess.run([binary, "--benchmark_filter=" + bench_filter, "--benchmark_format=json",
                          "--benchmark_repetitions=%d" % repetitions, "--benchmark_min_time=0.1"],
                         check=True, capture_output=True, text=True).stdout
    times = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        # Time per solve where the case reports it, else the CPU time per iteration.
        seconds = b["s_per_solve"] if "s_per_solve" in b else b["cpu_time"] * {"ns": 1e-9, "us": 1e-6, "ms": 1e-3,
                                                                               "s": 1.0}[b["time_unit"]]
        times.setdefault(b["run_name"], []).append(seconds)
    return times


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True, help="the reference bivo_bench")
    ap.add_argument("--b", required=True, help="the bivo_bench to compare")
    ap.add_argument("--filter", default="BM_Conic(Small|Huber)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repetitions", type=int, default=5)
    args = ap.parse_args()
    a, b = {}, {}
    for _ in range(args.rounds):
        for binary, acc in ((args.a, a), (args.b, b)):
            for name, t in run(binary, args.filter, args.repetitions).items():
                acc.setdefault(name, []).extend(t)
    print("| case | A median ms/solve | B median ms/solve | B/A |")
    print("|---|---:|---:|---:|")
    for name in a:
        if name not in b:
            continue
        ma, mb = statistics.median(a[name]), statistics.median(b[name])
        print("| %s | %.4f | %.4f | %.3f |" % (name, 1e3 * ma, 1e3 * mb, mb / ma))
    for label, acc in (("A", a), ("B", b)):
        small = [statistics.median(t) for t in acc.values() if statistics.median(t) < 1e-3]
        if small:
            print("%s: median ms/solve over its %d cases under 1 ms: %.4f" % (label, len(small),
                                                                           1e3 * statistics.median(small)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
