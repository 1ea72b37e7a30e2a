"""Writes a conic program in CBF (version 3) from the IPM's form, as the suite stores it.

    minimize c'x + c0   s.t.   A x = b,   G x + s = h,   s in R^l_+ x Q^q1 x ... x Q^qk

becomes VAR n (free), CON rows [A x - b in L=; h - G x in L+ x Q ...]: the file holds the data
as given, so a reader that maps it back gets c, A, b, G, h bit for bit (floats as repr, the
shortest string that reads back to the same double). Matrices are triplet lists (i, j, v).
"""


def _num(v):
    v = float(v)
    return repr(int(v)) if v == int(v) and abs(v) < 1e15 else repr(v)


def cbf_text(header, n, c, A, b, G, h, l, q, c0=0.0, maximize=False):
    """header: comment lines (without '#'); c: dense list of n; A, G: (i, j, v) triplets;
    b, h: dense lists; l: orthant rows; q: list of SOC dimensions."""
    p, m = len(b), len(h)
    assert l + sum(q) == m, "cone sizes must sum to the rows of G"
    out = ["# " + line if line else "#" for line in header]
    out += ["VER", "3", "", "OBJSENSE", "MAX" if maximize else "MIN", "", "VAR", "%d 1" % n, "F %d" % n, ""]
    cones = ([("L=", p)] if p else []) + ([("L+", l)] if l else []) + [("Q", d) for d in q]
    out += ["CON", "%d %d" % (p + m, len(cones))] + ["%s %d" % kd for kd in cones] + [""]
    obj = [(j, v) for j, v in enumerate(c) if v != 0]
    out += ["OBJACOORD", str(len(obj))] + ["%d %s" % (j, _num(v)) for j, v in obj] + [""]
    if c0:
        out += ["OBJBCOORD", _num(c0), ""]
    rows = [(i, j, v) for i, j, v in A if v != 0] + [(p + i, j, -v) for i, j, v in G if v != 0]
    rows.sort()
    out += ["ACOORD", str(len(rows))] + ["%d %d %s" % (i, j, _num(v)) for i, j, v in rows] + [""]
    rhs = [(i, -v) for i, v in enumerate(b) if v != 0] + [(p + i, v) for i, v in enumerate(h) if v != 0]
    out += ["BCOORD", str(len(rhs))] + ["%d %s" % (i, _num(v)) for i, v in rhs]
    return "\n".join(out) + "\n"


def write_cbf(path, *args, **kwargs):
    with open(path, "w") as f:
        f.write(cbf_text(*args, **kwargs))


def dense_triplets(M):
    """(i, j, v) of the nonzeros of a dense matrix (list of rows or a numpy array)."""
    return [(i, j, float(v)) for i, row in enumerate(M) for j, v in enumerate(row) if v != 0]
