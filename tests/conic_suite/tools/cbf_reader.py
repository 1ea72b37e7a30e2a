"""Reads the suite's CBF files into the IPM's form for the Python side (the CVXOPT cross-check
and benchmark): minimize c'x + c0 s.t. A x = b, G x + s = h, s in R^l_+ x Q^q1 x ...
The subset is what the suite stores: VAR cones F and L+, CON cones L=, L+, L-, Q (in any
order; orthant rows are gathered before the second-order blocks). MAX becomes min -c'x, so
`objective` maps the minimum back to the file's sense."""


def _lines(path):
    for raw in open(path):
        s = raw.strip()
        if s and not s.startswith("#"):
            yield s.split()


def read_cbf(path):
    it = _lines(path)
    n = m = 0
    var_cones, con_cones, c, acoord, bcoord, c0, maximize = [], [], {}, [], {}, 0.0, False

    def cones():
        total, k = map(int, next(it))
        out = [(kind, int(d)) for kind, d in (next(it) for _ in range(k))]
        return total, out

    for t in it:
        key = t[0]
        if key == "VER":
            next(it)
        elif key == "OBJSENSE":
            maximize = next(it)[0] == "MAX"
        elif key == "VAR":
            n, var_cones = cones()
        elif key == "CON":
            m, con_cones = cones()
        elif key == "OBJACOORD":
            for _ in range(int(next(it)[0])):
                j, v = next(it)
                c[int(j)] = c.get(int(j), 0.0) + float(v)
        elif key == "OBJBCOORD":
            c0 = float(next(it)[0])
        elif key == "ACOORD":
            acoord = [(int(i), int(j), float(v)) for i, j, v in (next(it) for _ in range(int(next(it)[0])))]
        elif key == "BCOORD":
            for _ in range(int(next(it)[0])):
                i, v = next(it)
                bcoord[int(i)] = bcoord.get(int(i), 0.0) + float(v)
        else:
            raise ValueError("%s: keyword %s is outside the suite's subset" % (path, key))
    rows = [[] for _ in range(m)]
    for i, j, v in acoord:
        rows[i].append((j, v))
    # Each constraint row r: a_r x + b_r in its cone.
    eq, orth, socs = [], [], []
    r = 0
    for kind, d in con_cones:
        block = [(rows[r + k], bcoord.get(r + k, 0.0)) for k in range(d)]
        if kind == "L=":
            eq += block
        elif kind == "L+":
            orth += block
        elif kind == "L-":
            orth += [([(j, -v) for j, v in a], -b0) for a, b0 in block]
        elif kind == "Q":
            socs.append(block)
        else:
            raise ValueError("%s: constraint cone %s is outside the suite's subset" % (path, kind))
        r += d
    j0 = 0
    for kind, d in var_cones:
        if kind == "L+":
            orth += [([(j0 + k, 1.0)], 0.0) for k in range(d)]
        elif kind != "F":
            raise ValueError("%s: variable cone %s is outside the suite's subset" % (path, kind))
        j0 += d
    cvec = [(-1.0 if maximize else 1.0) * c.get(j, 0.0) for j in range(n)]
    A = [(i, j, v) for i, (a, _) in enumerate(eq) for j, v in a]
    b = [-b0 for _, b0 in eq]
    G, h = [], []
    for a, b0 in orth + [row for blk in socs for row in blk]:  # s = a x + b0 = h - G x
        G += [(len(h), j, -v) for j, v in a]
        h.append(b0)
    return {"n": n, "c": cvec, "A": A, "b": b, "G": G, "h": h, "l": len(orth), "q": [len(s) for s in socs],
            "c0": c0, "maximize": maximize}


def objective(problem, conic_objective):
    """The file's objective (its sense, constant included) from min c'x of the IPM form."""
    return (-conic_objective if problem["maximize"] else conic_objective) + problem["c0"]
