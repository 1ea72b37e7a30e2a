"""One problem of the suite in the IPM's form (dense numpy data; the writer keeps nonzeros):
    minimize c'x   s.t.   A x = b,   G x + s = h,   s in R^l_+ x Q^q1 x ... x Q^qk
with what the manifest says about it."""
import numpy as np

from cbf_writer import cbf_text, dense_triplets

# Expected-status words of the manifest (what `bivo conic` prints first).
OPTIMAL, PRIMAL_INFEASIBLE, DUAL_INFEASIBLE = "optimal", "primal infeasible", "dual infeasible"


class Problem:
    def __init__(self, name, family, source, licence, status, c, G, h, l, q=(), A=None, b=None, objective=None,
                 objective_source="", notes="", well_posed=True, qp=None):
        self.name, self.family, self.source, self.licence = name, family, source, licence
        self.status, self.objective, self.objective_source, self.notes = status, objective, objective_source, notes
        # well_posed False: the status holds but no certificate for it exists (weak infeasibility),
        # so no solver can prove it; qp: (P, q, G, h) of a QP stated here as an SOCP.
        self.well_posed, self.qp = well_posed, qp
        self.c = np.asarray(c, dtype=float).ravel()
        n = self.c.size
        self.G = np.asarray(G, dtype=float).reshape(-1, n)
        self.h = np.asarray(h, dtype=float).ravel()
        self.A = np.zeros((0, n)) if A is None else np.asarray(A, dtype=float).reshape(-1, n)
        self.b = np.zeros(0) if b is None else np.asarray(b, dtype=float).ravel()
        self.l, self.q = int(l), [int(d) for d in q]
        assert self.G.shape[0] == self.h.size == self.l + sum(self.q), name
        assert self.A.shape[0] == self.b.size, name

    def size_text(self):
        return "n=%d eq=%d l=%d soc=%s" % (self.c.size, self.b.size, self.l, ",".join(map(str, self.q)) or "-")

    def cbf(self):
        header = ["%s: %s" % (self.name, self.family), "source: " + self.source, "licence: " + self.licence,
                  "expected: %s%s" % (self.status, "" if self.objective is None else
                                      ", objective %.12g (%s)" % (self.objective, self.objective_source))]
        if self.notes:
            header.append(self.notes)
        header.append("written by tests/conic_suite/tools/make_suite.py")
        return cbf_text(header, self.c.size, list(self.c), dense_triplets(self.A), list(self.b),
                        dense_triplets(self.G), list(self.h), self.l, self.q)


def quadratic_epigraph(P, c, G, h, l, q, A=None, b=None):
    """min 1/2 x'Px + c'x as an SOCP in (x, t): min c'x + t with 2t >= ||F x||^2, F'F = P,
    written as the cone (t + 1/2, t - 1/2, F x) (since (t+1/2)^2 - (t-1/2)^2 = 2t): exact data
    apart from F. F is the upper Cholesky factor of P, or P's nonzero rows when P is a 0/1 diagonal
    or rank one [1 1; 1 1]. The epigraph cone goes after the problem's own cones."""
    P = np.asarray(P, dtype=float)
    n = P.shape[0]
    F = _factor(P)
    k = F.shape[0]
    G = np.asarray(G, dtype=float).reshape(-1, n)
    Gx = np.hstack([G, np.zeros((G.shape[0], 1))])
    cone = np.zeros((k + 2, n + 1))
    cone[0, n] = cone[1, n] = -1.0
    cone[2:, :n] = -F
    Gx = np.vstack([Gx, cone])
    hx = np.concatenate([np.asarray(h, dtype=float).ravel(), [0.5, -0.5], np.zeros(k)])
    cx = np.concatenate([np.asarray(c, dtype=float).ravel(), [1.0]])
    Ax = None if A is None else np.hstack([np.asarray(A, dtype=float).reshape(-1, n), np.zeros((len(b), 1))])
    return dict(c=cx, G=Gx, h=hx, l=l, q=list(q) + [k + 2], A=Ax, b=b)


def _factor(P):
    d = np.diag(P)
    if np.count_nonzero(P - np.diag(d)) == 0 and set(d.tolist()) <= {0.0, 1.0}:
        return np.eye(P.shape[0])[d == 1.0]
    if np.linalg.matrix_rank(P) == 1:
        w, V = np.linalg.eigh(P)
        v = V[:, -1] * np.sqrt(w[-1])
        v = np.round(v, 12) if np.allclose(v, np.round(v)) else v
        return v.reshape(1, -1) * (1 if v.sum() >= 0 else -1)
    return np.linalg.cholesky(P).T
