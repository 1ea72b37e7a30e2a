#!/usr/bin/env python3
"""What a problem written in Python costs against the same problem in C++ (docs/python.md).

The same weighted linear least-squares pair, F_j = (A_j x - y_j)^T W_j (A_j x - y_j), once as
the C++ problems.LinearLeastSquaresPair and once as a bivo.Problem subclass whose residual /
jacobian / weights are numpy one-liners, solved by several backends from the same start: the
solutions agree (checked), the time per solve and per Python callback is printed. Then the
GIL: two threads solving C++ problems run in parallel (solve() releases the GIL), two
threads solving Python problems take turns in the callbacks.

    PYTHONPATH=build/python /usr/bin/python3 benchmarks/python_problem_overhead.py [--repeat 20]
Not a test: run it on an otherwise idle machine.
"""
import argparse
import threading
import time

import numpy as np

import bivo
from bivo.problems import LinearLeastSquaresPair


class Linear(bivo.Problem):
    def __init__(self, data):
        super().__init__(data[1][0].shape[1], name="linear (Python)")
        self.data = data

    def residual(self, j, x):
        A, y, _ = self.data[j]
        return A @ x - y

    def jacobian(self, j, x):
        return self.data[j][0]

    def weights(self, j):
        return self.data[j][2]


def instance(m, n, seed):
    rng = np.random.default_rng(seed)
    data = {j: (rng.normal(size=(m, n)), rng.normal(size=m), rng.uniform(0.5, 2.0, size=m)) for j in (1, 2)}
    cpp = LinearLeastSquaresPair("linear (C++)", *data[1], *data[2])
    return cpp, Linear(data)


def best_time(f, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def overhead_table(repeat):
    n = 6
    print("| backend | rows per objective | C++ problem [ms/solve] | Python problem [ms/solve] | ratio | "
          "Python calls per solve | extra us per call |")
    print("|---|---|---|---|---|---|---|")
    for m in (30, 300, 3000, 30000):
        cpp, py = instance(m, n, seed=m)
        x0 = np.zeros(n)
        f2 = [cpp.objectives(cpp.minimizer(j))[1] for j in (2, 1)]
        cases = [("gn", bivo.WeightedSum(1.0)), ("ceres", bivo.WeightedSum(1.0)),
                 ("exact", bivo.EpsilonConstraint(0.5 * (f2[0] + f2[1]))),
                 ("ipopt-nlp", bivo.EpsilonConstraint(0.5 * (f2[0] + f2[1])))]
        for backend, scal in cases:
            a, b = bivo.solve(cpp, scal, backend, x0), bivo.solve(py, scal, backend, x0)
            assert np.allclose(a.x, b.x, rtol=1e-8, atol=1e-10), (backend, m)
            calls0 = py.callbacks
            bivo.solve(py, scal, backend, x0)
            calls = py.callbacks - calls0
            t_cpp = best_time(lambda: bivo.solve(cpp, scal, backend, x0), repeat)
            t_py = best_time(lambda: bivo.solve(py, scal, backend, x0), repeat)
            print(f"| {backend} | {m} | {1e3 * t_cpp:.3f} | {1e3 * t_py:.3f} | {t_py / t_cpp:.1f} | {calls} | "
                  f"{1e6 * (t_py - t_cpp) / calls:.1f} |")


def threads_table(repeat):
    print("\n| problem | 2 solves in sequence [ms] | 2 solves in 2 threads [ms] | speed-up |")
    print("|---|---|---|---|")
    pairs = [instance(20000, 6, seed=1), instance(20000, 6, seed=2)]  # one problem per thread
    for k, label in enumerate(("C++", "Python")):
        scal, x0 = bivo.WeightedSum(1.0), np.zeros(6)

        def one(problem):
            for _ in range(5):
                bivo.solve(problem, scal, "gn", x0)

        def two_threads():
            ts = [threading.Thread(target=one, args=(pair[k],)) for pair in pairs]
            for t in ts:
                t.start()
            for t in ts:
                t.join()

        seq = best_time(lambda: (one(pairs[0][k]), one(pairs[1][k])), repeat)
        par = best_time(two_threads, repeat)
        print(f"| {label} | {1e3 * seq:.1f} | {1e3 * par:.1f} | {seq / par:.2f} |")


def main():
    parser = argparse.ArgumentParser(description="Python-defined problem vs C++ problem")
    parser.add_argument("--repeat", type=int, default=20, help="best of this many runs per case")
    args = parser.parse_args()
    overhead_table(args.repeat)
    threads_table(max(3, args.repeat // 4))


if __name__ == "__main__":
    main()
