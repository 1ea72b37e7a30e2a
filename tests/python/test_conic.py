"""bivo.solve_conic against `bivo_oracle conic` (the JSON reader + C++ IPM) and a closed form."""
import json

import numpy as np
import pytest
import scipy.sparse

import bivo
from conftest import assert_same

# min -x1 - x2 + x3  s.t.  x3 = 2,  x1 <= 0.6,  ||(x1, x2)|| <= 1:  x = (0.6, 0.8, 2), value 0.6.
C = np.array([-1.0, -1.0, 1.0])
G = np.array([[1.0, 0, 0], [0, 0, 0], [-1, 0, 0], [0, -1, 0]])
H = np.array([0.6, 1.0, 0, 0])
A = np.array([[0, 0, 1.0]])
B = np.array([2.0])
CONES = {"l": 1, "q": [3]}


@pytest.fixture
def problem_file(tmp_path):
    path = tmp_path / "socp.json"
    path.write_text(json.dumps({"c": C.tolist(), "G": G.tolist(), "h": H.tolist(), "A": A.tolist(), "b": B.tolist(),
                                "cones": CONES}))
    return path


@pytest.mark.parametrize("sparse", [False, True])
def test_solution_matches_cpp_and_the_closed_form(oracle, problem_file, sparse):
    g = scipy.sparse.csr_matrix(G) if sparse else G
    a = scipy.sparse.coo_matrix(A) if sparse else A
    r = bivo.solve_conic(C, g, H, CONES, a, B)
    ref = oracle("conic", problem_file)
    assert r.status == ref["status"] == "optimal"
    assert r.iterations == ref["iterations"]
    for k in "xyzs":
        assert_same(getattr(r, k), ref[k])
    assert_same(r.primal_objective, ref["primal_objective"])
    assert_same(r.x, [0.6, 0.8, 2.0], 1e-7)
    assert_same(r.primal_objective, 0.6, 1e-7)


def test_linear_program_agrees_with_scipy():
    from scipy.optimize import linprog
    rng = np.random.default_rng(2)
    Gl = rng.normal(size=(12, 4))
    h = Gl @ rng.normal(size=4) + rng.uniform(0.1, 1, size=12)  # feasible
    c = -Gl.T @ rng.uniform(0.1, 1, size=12)                      # bounded (dual feasible)
    r = bivo.solve_conic(c, Gl, h, {"l": 12})
    ref = linprog(c, A_ub=Gl, b_ub=h, bounds=[(None, None)] * 4, method="highs")
    assert r.status == "optimal"
    assert_same(r.primal_objective, ref.fun, 1e-7)


def test_infeasibility_is_a_status_not_an_exception():
    # x <= -1 and -x <= -1 (x >= 1)
    r = bivo.solve_conic([1.0], [[1.0], [-1.0]], [-1.0, -1.0], {"l": 2})
    assert r.status == "primal infeasible"


@pytest.mark.parametrize("kwargs,match", [
    (dict(cones={"l": 1, "q": [2]}), "cones: dimensions sum to 3"),
    (dict(cones={"l": 1, "p": [3]}), "unknown key 'p'"),
    (dict(h=[0.6, 1.0, np.nan, 0]), "h: entry 2"),
    (dict(G=G[:, :2]), r"G: expected shape \(4, 3\)"),
    (dict(G=scipy.sparse.csc_matrix(np.where(G == 1, np.inf, G))), r"G \(nonzeros\)"),
    (dict(c=["a", "b", "c"]), "expected real numbers"),
    (dict(A=A, b=None), "give both or neither"),
])
def test_bad_inputs_are_value_errors(kwargs, match):
    args = dict(c=C, G=G, h=H, cones=CONES)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        bivo.solve_conic(**args)
