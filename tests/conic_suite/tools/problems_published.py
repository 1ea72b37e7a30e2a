"""The suite's hand-sized problems whose data are published in other solvers' test suites and
documentation, or are textbook examples, transcribed as data (numbers only, each with its source).

Clarabel (Apache-2.0): tests/basic_lp.rs, basic_qp.rs, basic_socp.rs, basic_eq_constrained.rs,
presolve.rs of oxfordcontrol/Clarabel.rs; quadratic objectives become SOCPs through the epigraph
cone of suite_problem.quadratic_epigraph (same optimum). ECOS (GPL-3.0, data only):
test/infeasibleProblems, test/unboundedProblems, test/feasibilityProblems and
test/cvxpyProblems/githubIssue98.h of embotech/ecos. CVXOPT (GPL-3.0+, data only): the examples of
the user's guide, sections 8.3 and 8.5 (examples/doc/chap8/lp.py, socp.py of python-cvxopt-doc)."""
import numpy as np

from suite_problem import DUAL_INFEASIBLE, OPTIMAL, PRIMAL_INFEASIBLE, Problem, quadratic_epigraph

CLARABEL = "Apache-2.0 (Clarabel.rs); numbers transcribed as data"
ECOS = "GPL-3.0 (ECOS); numbers transcribed as data, no code"
CVXOPT = "GPL-3.0+ (CVXOPT); numbers transcribed as data, no code"
TEXTBOOK = "textbook example (facts, no licence)"
EXACT = "closed form"
TWO = "bivo IPM and CVXOPT agree to 1e-7"


def _clarabel(test, name, status, objective=None, source_note="", **data):
    src = "oxfordcontrol/Clarabel.rs tests/%s" % test + (" " + source_note if source_note else "")
    return Problem("clarabel_" + name, "Clarabel test problem", src, CLARABEL, status, objective=objective,
                   objective_source=EXACT if objective is not None else "", **data)


def clarabel():
    out = []
    box = np.vstack([2 * np.eye(3), -2 * np.eye(3)])  # A = [2I; -2I], b = 1: |x_i| <= 1/2
    c = [3.0, -2.0, 1.0]
    out.append(_clarabel("basic_lp.rs", "lp_feasible", OPTIMAL, -3.0, c=c, G=box, h=np.ones(6), l=6))
    h = np.ones(6)
    h[0] = h[3] = -1.0
    out.append(_clarabel("basic_lp.rs", "lp_primal_infeasible", PRIMAL_INFEASIBLE, c=c, G=box, h=h, l=6))
    G = box.copy()
    G[3, 0] = 1.0  # the lower bound on x0 turned into a second upper bound
    out.append(_clarabel("basic_lp.rs", "lp_dual_infeasible", DUAL_INFEASIBLE, c=[1, 0, 0], G=G, h=np.ones(6), l=6))
    G = box.copy()
    G[0, 0], G[3, 0] = np.finfo(float).eps, 0.0
    out.append(_clarabel("basic_lp.rs", "lp_dual_infeasible_ill_cond", DUAL_INFEASIBLE, c=[1, 0, 0], G=G,
                         h=np.ones(6), l=6))
    # basic_qp.rs: P = [4 1; 1 2], c = (1, 1), 1 <= x1 + x2 <= 1, 0 <= x <= 0.7; x* = (0.3, 0.7).
    Aq = np.array([[1.0, 1.0], [1.0, 0.0], [0.0, 1.0]])
    Gq, hq = np.vstack([-Aq, Aq]), np.array([-1.0, 0, 0, 1, 0.7, 0.7])
    P = np.array([[4.0, 1.0], [1.0, 2.0]])
    out.append(_clarabel("basic_qp.rs", "qp_feasible", OPTIMAL, 1.88, **quadratic_epigraph(P, [1, 1], Gq, hq, 6, [])))
    hq2 = hq.copy()
    hq2[3] = -1.0
    out.append(_clarabel("basic_qp.rs", "qp_primal_infeasible", PRIMAL_INFEASIBLE,
                         **quadratic_epigraph(P, [1, 1], Gq, hq2, 6, [])))
    P1 = np.ones((2, 2))
    out.append(_clarabel("basic_qp.rs", "qp_dual_infeasible", DUAL_INFEASIBLE,
                         **quadratic_epigraph(P1, [1, -1], [[1, 1], [1, 0]], [1, 1], 2, [])))
    out.append(_clarabel("basic_qp.rs", "qp_dual_infeasible_ill_cond", DUAL_INFEASIBLE,
                         **quadratic_epigraph(P1, [1, -1], [[1, 1]], [1], 1, [])))
    # basic_socp.rs: P from the file, A = [2I; -2I; I], b = (1,..,1, 0, 0, 0), cones R+^3 R+^3 Q^3.
    Ps = np.array([[1.4652521089139698, 0.6137176286085666, -1.1527861771130112],
                   [0.6137176286085666, 2.219109946678485, -1.4400420548730628],
                   [-1.1527861771130112, -1.4400420548730628, 1.6014483534926371]])
    Gs = np.vstack([box, np.eye(3)])
    hs = np.concatenate([np.ones(6), np.zeros(3)])
    out.append(Problem("clarabel_socp_feasible", "Clarabel test problem", "oxfordcontrol/Clarabel.rs tests/basic_socp.rs",
                       CLARABEL, OPTIMAL, objective=None, objective_source=TWO,
                       notes="Clarabel's reference: objective -0.8459 (to 1e-4), x = (-0.5, 0.435603, -0.245459)",
                       **quadratic_epigraph(Ps, [0.1, -2.0, 1.0], Gs, hs, 6, [3])))
    hs2 = hs.copy()
    hs2[6] = -10.0
    out.append(_clarabel("basic_socp.rs", "socp_infeasible", PRIMAL_INFEASIBLE,
                         **quadratic_epigraph(Ps, [0.1, -2.0, 1.0], Gs, hs2, 6, [3])))
    # basic_eq_constrained.rs: min 1/2 ||x||^2 s.t. x1 + x2 = 2, x1 - x2 = 0; x* = (0, 1, 1).
    A1 = np.array([[0.0, 1.0, 1.0], [0.0, 1.0, -1.0]])
    none = dict(G=np.zeros((0, 3)), h=[], l=0, q=[])
    out.append(_clarabel("basic_eq_constrained.rs", "eq_feasible", OPTIMAL, 1.0,
                         **quadratic_epigraph(np.eye(3), [0, 0, 0], A=A1, b=[2.0, 0.0], **none)))
    A2 = np.array([[0.0, 1, 1], [0, 1, -1], [1, 2, -1], [2, -1, 3]])
    out.append(_clarabel("basic_eq_constrained.rs", "eq_primal_infeasible", PRIMAL_INFEASIBLE,
                         **quadratic_epigraph(np.eye(3), [0, 0, 0], A=A2, b=np.ones(4), **none)))
    out.append(_clarabel("basic_eq_constrained.rs", "eq_dual_infeasible", DUAL_INFEASIBLE,
                         **quadratic_epigraph(np.diag([0.0, 1, 1]), [1, 1, 1], A=A1, b=[2.0, 0.0], **none)))
    # presolve.rs: min 1/2 ||x||^2 + (3, -2, 1)'x over the box of basic_lp with entries 1e30.
    for name, rows, objective in [("presolve_single_unbounded", [3], -5.75),
                                  ("presolve_redundant_cone", [0, 1, 2], -3.75),
                                  ("presolve_every_row_redundant", range(6), -7.0)]:
        h = np.ones(6)
        h[list(rows)] = 1e30
        out.append(_clarabel("presolve.rs", name, OPTIMAL, objective, "(rows at 1e30 are absent bounds)",
                             **quadratic_epigraph(np.eye(3), c, box, h, 6, [])))
    # presolve.rs, single_unbounded_2: cones Zero(2) x Nonneg(4) over the same rows, b[4] = 1e30.
    h = np.ones(6)
    h[4] = 1e30
    out.append(_clarabel("presolve.rs", "presolve_zero_cone_unbounded_row", OPTIMAL, 0.375,
                         "(rows at 1e30 are absent bounds)",
                         **quadratic_epigraph(np.eye(3), c, box[2:], h[2:], 4, [], A=box[:2], b=h[:2])))
    return out


def _ecos(path, name, status, objective=None, **data):
    return Problem("ecos_" + name, "ECOS test problem", "embotech/ecos " + path, ECOS, status, objective=objective,
                   objective_source=EXACT if objective is not None else "", **data)


def ecos():
    out = [_ecos("test/infeasibleProblems/infeasible1.h", "infeasible1", PRIMAL_INFEASIBLE, c=[-1], G=[[-1], [1]],
                 h=[-2, 1], l=2)]
    G = np.zeros((3, 3))
    G[0, 1], G[1, 1], G[0, 2], G[2, 2] = 8.0, 1.0, 9.0, -1.0
    A = np.array([[1.0, 0, 0], [-1, 1, 1]])
    out.append(_ecos("test/infeasibleProblems/infeasible2.h", "infeasible2", PRIMAL_INFEASIBLE, c=[-1, 0, 0], G=G,
                     h=[25, 0, 0], l=3, A=A, b=[3, 0]))
    G = np.array([[-2.0, -0.9999999999999999], [-1.0000000000000002, -3.0], [-1.0, 0.0], [0.0, -1.0]])
    out.append(_ecos("test/unboundedProblems/unboundedLP1.h", "unbounded_lp1", DUAL_INFEASIBLE, c=[-1, -1], G=G,
                     h=[-1, -1, 0, 0], l=4))
    G = np.array([[-1.0, 0.0], [0.0, -2.0], [-1.0, 0.0]])
    out.append(_ecos("test/unboundedProblems/unboundedMaxSqrt.h", "unbounded_max_sqrt", DUAL_INFEASIBLE, c=[0, -1],
                     G=G, h=[1, 0, -1], l=0, q=[3], well_posed=False,
                     notes="max x1 s.t. x1 <= sqrt(x0): unbounded, but no ray improves the objective "
                     "(the dual is weakly infeasible), so no certificate exists"))
    out.append(_ecos("test/feasibilityProblems/feas.h", "feasibility", OPTIMAL, 0.0, c=[0], G=[[1], [-1]], h=[1, 0],
                     l=2))
    u = [0.416757847405471, 2.136196095668454, 1.793435585194863]
    w = [0.056266827226329, -1.640270808404989, 0.841747365656204]
    G = np.zeros((11, 5))
    G[0:3, 0], G[0:3, 1], G[3:6, 2], G[3:6, 3] = u, w, u, w
    G[7, 0] = G[8, 1] = G[9, 2] = G[10, 3] = G[6, 4] = -1.0
    out.append(_ecos("test/cvxpyProblems/githubIssue98.h", "github_issue98", OPTIMAL, 0.0, c=[0, 0, 0, 0, 1], G=G,
                     h=np.zeros(11), l=6, q=[5]))
    return out


def cvxopt_guide():
    src = "CVXOPT user's guide, section %s (python-cvxopt-doc examples/doc/chap8/%s)"
    lp = Problem("cvxopt_guide_lp", "CVXOPT documentation example", src % ("8.3", "lp.py"), CVXOPT, OPTIMAL,
                 c=[-4, -5], G=[[2, 1], [1, 2], [-1, 0], [0, -1]], h=[3, 3, 0, 0], l=4, objective=-9.0,
                 objective_source=EXACT + ": x = (1, 1)")
    G = np.array([[12, 6, -5], [13, -3, -5], [12, -12, 6], [3, -6, 10], [3, -6, -2], [-1, -9, -2], [1, 19, -3]])
    socp = Problem("cvxopt_guide_socp", "CVXOPT documentation example", src % ("8.5", "socp.py"), CVXOPT, OPTIMAL,
                   c=[-2, 1, 5], G=G, h=[-12, -3, -2, 27, 0, 3, -42], l=0, q=[3, 4], objective_source=TWO,
                   notes="the guide prints x = (-5.02, -5.77, -8.52)")
    return [lp, socp]


def textbook():
    out = [Problem("wyndor_glass_lp", "textbook LP", "Hillier & Lieberman, Introduction to Operations Research, "
                   "the Wyndor Glass Co. example (max 3x1 + 5x2; optimum 36 at (2, 6))", TEXTBOOK, OPTIMAL,
                   c=[-3, -5], G=[[1, 0], [0, 2], [3, 2], [-1, 0], [0, -1]], h=[4, 12, 18, 0, 0], l=5,
                   objective=-36.0, objective_source=EXACT + " (as min -3x1 - 5x2)")]
    for n in (3, 7):
        # Klee-Minty: max sum 2^(n-j) x_j s.t. 2 sum_{j<i} 2^(i-j) x_j + x_i <= 5^i, x >= 0; optimum 5^n.
        G = np.zeros((2 * n, n))
        for i in range(n):
            for j in range(i):
                G[i, j] = 2.0 ** (i - j + 1)
            G[i, i] = 1.0
            G[n + i, i] = -1.0
        h = np.concatenate([[5.0 ** (i + 1) for i in range(n)], np.zeros(n)])
        c = [-(2.0 ** (n - 1 - j)) for j in range(n)]
        out.append(Problem("klee_minty_%d" % n, "textbook LP", "Klee & Minty (1972) cube in the form of Chvatal, "
                           "Linear Programming (1983): max sum 2^(n-j) x_j, optimum 5^n", TEXTBOOK, OPTIMAL, c=c, G=G,
                           h=h, l=2 * n, objective=-(5.0 ** n), objective_source=EXACT + " (as a minimum)"))
    return out


def huge_bounds():
    """The examples of the infinite-bound presolve: absent bounds written as 1e12 .. 1e30."""
    out = [Problem("bound_1e20_lp", "huge bounds", "min x s.t. x >= 2, x <= 1e20 (a modelling tool's absent bound)",
                   "written for this suite", OPTIMAL, c=[1], G=[[-1], [1]], h=[-2, 1e20], l=2, objective=2.0,
                   objective_source=EXACT)]
    G = np.zeros((6, 3))
    G[0, 1] = G[1, 2] = 1.0
    G[2, 1] = -1.0
    G[3, 0] = G[4, 1] = G[5, 2] = -1.0
    for B in (1e12, 1e19, 1e30):
        out.append(Problem("bound_1e%d_socp" % round(np.log10(B)), "huge bounds",
                           "min x0 s.t. x1 <= 1, x2 <= B, -x1 <= B, x0 >= ||(x1 - 3, x2 - 4)||, B = %.0e" % B,
                           "written for this suite", OPTIMAL, c=[1, 0, 0], G=G, h=[1, B, B, 0, -3, -4], l=3, q=[3],
                           objective=2.0, objective_source=EXACT + ": x = (2, 1, 4)"))
    return out


def all_problems():
    return clarabel() + ecos() + cvxopt_guide() + textbook() + huge_bounds()
