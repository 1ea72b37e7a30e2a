"""CVXOPT (Debian python3-cvxopt) on a problem of cbf_reader.read_cbf: the suite's second,
independent solver. conelp at tight tolerances; returns (status, file objective, seconds per
solve) with status in optimal / primal infeasible / dual infeasible / failed."""
import time

import cvxopt
from cvxopt import solvers

from cbf_reader import objective


def matrices(p):
    n = p["n"]

    def sp(trip, rows):
        if not trip:
            return cvxopt.spmatrix([], [], [], (rows, n))
        i, j, v = zip(*trip)
        return cvxopt.spmatrix(list(v), list(i), list(j), (rows, n))

    c = cvxopt.matrix(p["c"], (n, 1), "d")
    G = sp(p["G"], len(p["h"]))
    h = cvxopt.matrix(p["h"], (len(p["h"]), 1), "d")
    dims = {"l": p["l"], "q": list(p["q"]), "s": []}
    if p["b"]:
        return c, G, h, dims, sp(p["A"], len(p["b"])), cvxopt.matrix(p["b"], (len(p["b"]), 1), "d")
    return c, G, h, dims, None, None


def solve(p, tol=1e-9, repeats=1):
    args = matrices(p)
    opts = {"show_progress": False, "abstol": tol, "reltol": tol, "feastol": tol, "maxiters": 200}
    times, r = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        try:
            r = solvers.conelp(*args[:4], A=args[4], b=args[5], options=opts)
        except (ValueError, ArithmeticError) as e:  # CVXOPT needs rank(A) = p, rank([G; A]) = n
            return "failed (%s)" % e, None, time.perf_counter() - t0, None
        times.append(time.perf_counter() - t0)
    st = r["status"]
    if st == "optimal" or (st == "unknown" and r["x"] is not None and r["relative gap"] is not None
                           and abs(r["relative gap"]) < 1e-6 and r["primal infeasibility"] < 1e-6
                           and r["dual infeasibility"] < 1e-6):
        return "optimal", objective(p, r["primal objective"]), sorted(times)[len(times) // 2], r
    if st == "primal infeasible":
        return "primal infeasible", None, sorted(times)[len(times) // 2], r
    if st == "dual infeasible":
        return "dual infeasible", None, sorted(times)[len(times) // 2], r
    return "failed (%s)" % st, None, sorted(times)[len(times) // 2], r
