#!/usr/bin/python3
"""Converts a linear program in (free or fixed) MPS to CBF, the suite's format.

    tests/conic_suite/tools/mps_to_cbf.py IN.mps OUT.cbf [--header "line" ...]

Sections NAME, ROWS, COLUMNS, RHS, RANGES, BOUNDS, ENDATA (names without blanks, tokens split
on whitespace, any number of row/value pairs on a COLUMNS, RHS or RANGES line; '*' lines are
comments). The first N row is the objective (its RHS entry r gives the constant -r, the
usual MPS convention); other N rows are dropped. Rows: E -> A x = b, L -> a'x <= b,
G -> a'x >= b, RANGES as in the MPS definition (E with R > 0: [b, b + R], R < 0: [b + R, b];
L: [b - |R|, b]; G: [b, b + |R|]). BOUNDS UP, LO, FX, FR, MI, PL; default 0 <= x < inf. Every
finite bound is a row of the orthant block. Integer markers and BV/LI/UI bounds are refused.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cbf_writer import cbf_text  # noqa: E402


def fail(path, line, what):
    sys.exit("%s:%d: %s" % (path, line, what))


def read_mps(path):
    rows, kinds, obj = {}, [], None
    cols, col_entries, rhs, ranges, lo, up = {}, [], {}, {}, {}, {}
    section, c0 = None, 0.0
    for number, raw in enumerate(open(path), 1):
        if not raw.strip() or raw.startswith("*"):
            continue
        t = raw.split()
        if not raw[0].isspace():
            section = t[0]
            if section not in ("NAME", "ROWS", "COLUMNS", "RHS", "RANGES", "BOUNDS", "ENDATA"):
                fail(path, number, "unsupported section '%s'" % section)
            continue
        if section == "ROWS":
            kind, name = t[0], t[1]
            if kind == "N":
                obj = obj or name
                continue
            if kind not in ("E", "L", "G"):
                fail(path, number, "row type '%s'" % kind)
            rows[name] = len(kinds)
            kinds.append(kind)
        elif section == "COLUMNS":
            if "'MARKER'" in t:
                fail(path, number, "integer markers are not supported")
            j = cols.setdefault(t[0], len(cols))
            for r, v in zip(t[1::2], t[2::2]):
                if r in rows:
                    col_entries.append((rows[r], j, float(v)))
                elif r == obj:
                    col_entries.append((-1, j, float(v)))
                else:  # a free row other than the objective
                    pass
        elif section in ("RHS", "RANGES"):
            pairs = list(zip(t[1::2], t[2::2])) if len(t) % 2 == 1 else list(zip(t[0::2], t[1::2]))
            for r, v in pairs:
                if section == "RHS" and r == obj:
                    c0 = -float(v)
                elif r in rows:
                    (rhs if section == "RHS" else ranges)[rows[r]] = float(v)
                else:
                    fail(path, number, "unknown row '%s'" % r)
        elif section == "BOUNDS":
            kind = t[0]
            # "KIND [SET] COLUMN [VALUE]": the set name is optional, the value absent for FR/MI/PL.
            name, v = (t[-1], None) if kind in ("FR", "MI", "PL") else (t[-2], float(t[-1]))
            if name not in cols:
                fail(path, number, "unknown column '%s'" % name)
            j = cols[name]
            if kind == "UP":
                if v < 0 and lo.get(j, 0.0) == 0.0:
                    fail(path, number, "UP bound < 0 with lower bound 0 is ambiguous")
                up[j] = v
            elif kind == "LO":
                lo[j] = v
            elif kind == "FX":
                lo[j] = up[j] = v
            elif kind == "FR":
                lo[j], up[j] = -math.inf, math.inf
            elif kind == "MI":
                lo[j] = -math.inf
            elif kind == "PL":
                up[j] = math.inf
            else:
                fail(path, number, "bound type '%s' is not supported" % kind)
    return kinds, obj, cols, col_entries, rhs, ranges, lo, up, c0


def convert(path):
    kinds, obj, cols, entries, rhs, ranges, lo, up, c0 = read_mps(path)
    n = len(cols)
    c = [0.0] * n
    by_row = {}
    for i, j, v in entries:
        if i < 0:
            c[j] += v
        else:
            by_row.setdefault(i, []).append((j, v))
    A, b, G, h = [], [], [], []

    def ineq(coefs, rhs_value, sign):  # sign * (a'x) <= sign * rhs_value
        r = len(h)
        G.extend((r, j, sign * v) for j, v in coefs)
        h.append(sign * rhs_value)

    for i, kind in enumerate(kinds):
        a, r = by_row.get(i, []), rhs.get(i, 0.0)
        if i in ranges:
            R = ranges[i]
            low, high = {"E": (r, r + R) if R > 0 else (r + R, r), "L": (r - abs(R), r), "G": (r, r + abs(R))}[kind]
            if low == high:
                A.extend((len(b), j, v) for j, v in a)
                b.append(r)
            else:
                ineq(a, high, 1.0)
                ineq(a, low, -1.0)
        elif kind == "E":
            A.extend((len(b), j, v) for j, v in a)
            b.append(r)
        else:
            ineq(a, r, 1.0 if kind == "L" else -1.0)
    for j in range(n):
        if math.isfinite(lo.get(j, 0.0)):
            ineq([(j, 1.0)], lo.get(j, 0.0), -1.0)
        if math.isfinite(up.get(j, math.inf)):
            ineq([(j, 1.0)], up[j], 1.0)
    return n, c, A, b, G, h, c0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mps")
    ap.add_argument("cbf")
    ap.add_argument("--header", action="append", default=[], help="a comment line for the CBF file")
    a = ap.parse_args()
    n, c, A, b, G, h, c0 = convert(a.mps)
    with open(a.cbf, "w") as f:
        f.write(cbf_text(a.header, n, c, A, b, G, h, len(h), [], c0=c0))


if __name__ == "__main__":
    main()
