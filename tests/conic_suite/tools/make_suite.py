#!/usr/bin/python3
"""Regenerates the public conic suite: tests/conic_suite/problems/*.cbf and manifest.json.

    tests/conic_suite/tools/make_suite.py --cvxopt-examples DIR [--bivo build/experiments/bivo]

Every problem is written in CBF, read back (cbf_reader.py) and solved by CVXOPT (Debian
python3-cvxopt) as the independent check; with --bivo also by `bivo conic`. An expected optimum
that no source publishes is taken from CVXOPT only when bivo's IPM and CVXOPT agree to 1e-7
(relative); a published or closed-form optimum must be matched by CVXOPT to 1e-6 (its own
accuracy), and an expected status by CVXOPT or bivo. Anything else stops the script: no
problem enters the suite with an unchecked answer. DIR: CVXOPT's examples folder as Debian's
python-cvxopt-doc installs it (see problems_recipes.py). Netlib LPs come from
tests/conic_suite/sources/netlib/*.mps (mps_to_cbf.py)."""
import argparse
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cvxopt_solve  # noqa: E402
import mps_to_cbf  # noqa: E402
from cbf_reader import read_cbf  # noqa: E402
from problems_published import all_problems  # noqa: E402
from problems_random import all_random  # noqa: E402
from problems_recipes import book  # noqa: E402
from suite_problem import OPTIMAL, Problem  # noqa: E402

SUITE = os.path.dirname(HERE)
# name: (published optimum from netlib's lp/data readme, commit of ERGO-Code/HiGHS whose
# check/instances/<name>.mps was transcribed).
NETLIB = {
    "afiro": (-4.6475314286e+02, "alexandervyatsu/simplex2 afiro.mps 8c8c840"),
    "sc50a": (-6.4575077059e+01, "ERGO-Code/HiGHS check/instances/sc50a.mps 0edab95"),
    "sc50b": (-7.0000000000e+01, "ERGO-Code/HiGHS check/instances/sc50b.mps 3592828"),
    "kb2": (-1.7499001299e+03, "ERGO-Code/HiGHS check/instances/kb2.mps 0edab95"),
    "sc105": (-5.2202061212e+01, "ERGO-Code/HiGHS check/instances/sc105.mps 5028f1d"),
    "blend": (-3.0812149846e+01, "ERGO-Code/HiGHS check/instances/blend.mps 625cd4c"),
    "share2b": (-4.1573224074e+02, "ERGO-Code/HiGHS check/instances/share2b.mps 3592828"),
}


def netlib():
    out = []
    for name, (optimum, copy) in NETLIB.items():
        n, c, A, b, G, h, c0 = mps_to_cbf.convert(os.path.join(SUITE, "sources", "netlib", name + ".mps"))
        assert c0 == 0.0
        Gd, Ad = np.zeros((len(h), n)), np.zeros((len(b), n))
        for M, trip in ((Gd, G), (Ad, A)):
            for i, j, v in trip:
                M[i, j] += v
        out.append(Problem("netlib_" + name, "netlib LP", "netlib lp/data %s (free-format transcription of %s; "
                           "tests/conic_suite/sources/netlib/%s.mps)" % (name.upper(), copy, name),
                           "netlib lp/data: freely distributed test data, no licence terms", OPTIMAL, c=c, G=Gd, h=h,
                           l=len(h), A=Ad if b else None, b=b if b else None, objective=optimum,
                           objective_source="netlib lp/data readme (11 significant digits)"))
    return out


def run_bivo(bivo, path):
    r = subprocess.run([bivo, "conic", path], capture_output=True, text=True)
    status, objective = "failed", None
    for line in r.stdout.splitlines():
        if line.startswith("status: "):
            status = line[len("status: "):]
        if line.startswith("file objective"):
            objective = float(line.split(":")[1])
    return status, objective


def rel(a, b):
    return abs(a - b) / max(1.0, abs(b))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cvxopt-examples", required=True)
    ap.add_argument("--bivo", help="the bivo binary: cross-check with its IPM (needed for optima without a source)")
    a = ap.parse_args()
    problems = netlib() + all_problems() + book(a.cvxopt_examples) + all_random()
    names = [p.name for p in problems]
    assert len(set(names)) == len(names), "duplicate names"
    os.makedirs(os.path.join(SUITE, "problems"), exist_ok=True)
    manifest, errors = [], []
    for p in problems:
        rel_path = os.path.join("problems", p.name + ".cbf")
        path = os.path.join(SUITE, rel_path)
        text = p.cbf()
        cv_status, cv_obj, _, _ = cvxopt_solve.solve(read_cbf_text(text, path))
        bv_status, bv_obj = run_bivo(a.bivo, path) if a.bivo else ("not run", None)
        entry_obj = p.objective
        if p.status == OPTIMAL and p.objective is None and cv_status != OPTIMAL:
            cv_status, cv_obj, p.objective_source = second_oracle(p)
        if p.status == OPTIMAL and p.objective is None:
            if cv_status != OPTIMAL or not bv_status.startswith(OPTIMAL) or rel(bv_obj, cv_obj) > 1e-7:
                errors.append("%s: no agreed optimum (CVXOPT %s %s, bivo %s %s)" % (p.name, cv_status, cv_obj,
                                                                                  bv_status, bv_obj))
                continue
            entry_obj = cv_obj
        elif p.status == OPTIMAL and cv_status == OPTIMAL and rel(cv_obj, p.objective) > 1e-6:
            errors.append("%s: CVXOPT finds %r, the source says %r" % (p.name, cv_obj, p.objective))
        if not p.well_posed:
            pass  # no certificate exists for its status: the manifest says so, the test checks no false claim
        elif cv_status != p.status and not bv_status.startswith(p.status):
            errors.append("%s: expected %s, CVXOPT %s, bivo %s" % (p.name, p.status, cv_status, bv_status))
        p.objective = entry_obj
        with open(path, "w") as f:
            f.write(p.cbf())
        manifest.append({"name": p.name, "file": rel_path, "family": p.family, "source": p.source,
                         "licence": p.licence, "status": p.status, "objective": entry_obj,
                         "objective_source": p.objective_source, "size": p.size_text(),
                         "well_posed": p.well_posed, "notes": p.notes,
                         "cvxopt": {"status": cv_status, "objective": cv_obj},
                         "bivo_at_generation": {"status": bv_status, "objective": bv_obj}})
        print("%-48s %-18s %-22s cvxopt %-18s bivo %s" % (p.name, p.status, entry_obj, cv_status, bv_status))
    with open(os.path.join(SUITE, "manifest.json"), "w") as f:
        json.dump({"about": "The public conic test suite: see docs/conic.md, 'The public test suite'.",
                   "problems": manifest}, f, indent=1)
        f.write("\n")
    print("%d problems, %d errors" % (len(manifest), len(errors)))
    for e in errors:
        print("ERROR " + e)
    sys.exit(1 if errors else 0)


def second_oracle(p):
    """When CVXOPT's conelp fails on the stored form: SciPy's HiGHS for an LP, CVXOPT's qp on the
    original quadratic program for an epigraph-reformulated QP (Problem.qp)."""
    if p.qp is not None:
        from cvxopt import matrix, solvers
        P, q, G, h = (matrix(np.asarray(v, dtype=float)) for v in p.qp)
        r = solvers.qp(P, q, G, h, options={"show_progress": False, "abstol": 1e-10, "reltol": 1e-10,
                                             "feastol": 1e-10, "maxiters": 200})
        ok = r["status"] == "optimal"
        return (OPTIMAL if ok else r["status"]), (r["primal objective"] if ok else None), \
            "bivo IPM and CVXOPT's qp on the original QP agree to 1e-7"
    if not p.q:
        from scipy.optimize import linprog
        r = linprog(p.c, A_ub=p.G, b_ub=p.h, A_eq=p.A if p.b.size else None, b_eq=p.b if p.b.size else None,
                    bounds=(None, None), method="highs")
        return (OPTIMAL if r.status == 0 else "failed"), (r.fun if r.status == 0 else None), \
            "bivo IPM and SciPy's HiGHS agree to 1e-7"
    return "failed", None, ""


def read_cbf_text(text, path):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    try:
        return read_cbf(tmp)
    finally:
        os.replace(tmp, path)


if __name__ == "__main__":
    main()
