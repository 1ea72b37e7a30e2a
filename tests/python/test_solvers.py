"""The solver layer's bindings against the C++ results (bivo_oracle) to 1e-12."""
import numpy as np
import pytest

import bivo
from bivo.problems import ExponentialDecayPair, LinearLeastSquaresPair, PointAlignmentPair
from conftest import IDENTITY, assert_same

WS_BACKENDS = [b["name"] for b in bivo.backends() if b["weighted_sum"]]
EPS_BACKENDS = [b["name"] for b in bivo.backends() if b["epsilon_constraint"]]


def instance(spec):
    kind, *n = spec.split(":")
    n = list(map(int, n))
    if kind == "lls":
        return LinearLeastSquaresPair.well_conditioned(n[0], n[1]), np.zeros(n[0])
    if kind == "exp":
        return ExponentialDecayPair.synthetic(n[0], n[1]), np.ones(3)
    return PointAlignmentPair(n[0]), IDENTITY.copy()


def test_backends_list_every_registered_backend_with_its_scalarizations():
    infos = {b["name"]: b for b in bivo.backends()}
    assert set(WS_BACKENDS) == {"gn", "lm", "ceres"}
    assert set(EPS_BACKENDS) == {"exact", "ipm-full", "ipm-compressed", "ipm-full-nopolish", "ipm-compressed-nopolish",
                                 "ipopt", "nlopt", "ipopt-nlp"}
    assert set(infos) == set(WS_BACKENDS) | set(EPS_BACKENDS)
    assert {b for b in infos if infos[b]["whole_problem"]} == {"ceres", "ipopt-nlp"}


def epsilon_between(problem, x0):
    """An epsilon strictly inside [min F2, F2 at argmin F1] (from two C++ solves)."""
    f2_min = bivo.solve(problem, bivo.WeightedSum(1e6), "gn", x0).final_f2
    f2_max = bivo.solve(problem, bivo.WeightedSum(0.0), "gn", x0).final_f2
    return f2_min + 0.4 * (f2_max - f2_min)


@pytest.mark.parametrize("spec", ["lls:6:3", "exp:40:2", "se3:4"])
@pytest.mark.parametrize("backend", WS_BACKENDS + EPS_BACKENDS)
def test_solve_matches_cpp(oracle, spec, backend):
    problem, x0 = instance(spec)
    if backend in WS_BACKENDS:
        scal, kind, param = bivo.WeightedSum(0.7), "ws", 0.7
    else:
        param = float(np.format_float_positional(epsilon_between(problem, x0), precision=12))
        scal, kind = bivo.EpsilonConstraint(param), "eps"
    ref = oracle("solve", spec, backend, kind, repr(param), may_fail=True)
    if "error" in ref:  # e.g. ipm-full on a problem without full residual data: the same error
        with pytest.raises(bivo.Error) as e:
            bivo.solve(problem, scal, backend, x0)
        assert str(e.value) == ref["error"]
        return
    s = bivo.solve(problem, scal, backend, x0)
    assert s.iterations == ref["iterations"]
    assert s.termination == ref["termination"]
    assert_same(s.x, ref["x"])
    assert_same([s.final_f1, s.final_f2], [ref["final_f1"], ref["final_f2"]])
    assert_same(s.f1, ref["f1"])
    assert_same(s.f2, ref["f2"])
    assert_same(s.multipliers, ref["multipliers"])
    assert_same(s.iterates, ref["iterates"])
    assert s.iterates.shape == (len(s.f1), problem.ambient_dim)
    assert_same(s.x0, x0, 0.0)
    assert s.backend == backend and s.problem == problem.name
    assert "subproblem" in s.phases or backend in ("ceres", "ipopt-nlp")


@pytest.mark.parametrize("spec,kind,backend", [("lls:5:7", "epsilon", "exact"), ("lls:5:7", "lambda", "gn"),
                                               ("exp:30:1", "epsilon", "ipm-compressed"), ("se3:2", "lambda", "ceres")])
def test_pareto_sweep_matches_cpp(oracle, spec, kind, backend):
    problem, x0 = instance(spec)
    front = bivo.pareto_sweep(problem, x0, kind, points=9, backend=backend)
    ref = oracle("pareto", spec, kind, 9, backend)
    assert_same(front.f1, ref["f1"])
    assert_same(front.f2, ref["f2"])
    assert_same(front.parameters, ref["parameters"])
    assert front.knee == ref["knee"]
    assert_same(front.hypervolume, ref["hypervolume"])
    # The module-level helpers give the same on the arrays.
    assert bivo.knee_index(front.f1, front.f2) == front.knee
    assert_same(bivo.hypervolume(front.f1, front.f2, front.reference), front.hypervolume, 0.0)
    assert front.x.shape == (len(front), problem.ambient_dim)


def test_weighted_sum_front_of_the_linear_pair_is_its_closed_form():
    problem, x0 = instance("lls:4:11")
    front = bivo.pareto_sweep(problem, x0, "lambda", points=7, backend="gn")
    for lam, x in zip(front.parameters, front.x):
        assert_same(x, problem.weighted_sum_optimum(lam), 1e-9)


def test_problem_interface_evaluates_residuals_and_models():
    problem, _ = instance("lls:3:1")
    x = np.array([0.3, -0.2, 0.5])
    r1, J1, w1 = problem.residuals(1, x)
    r2, J2, w2 = problem.residuals(2, x)
    f = problem.evaluate(x)
    assert_same(f, [r1 @ (w1 * r1), r2 @ (w2 * r2)])
    assert_same(f, problem.objectives(x))
    lin = problem.linearize(x)
    assert_same(lin["b1"], J1.T @ (w1 * r1))
    assert_same(lin["H2"], J2.T @ (w2[:, None] * J2))
    assert problem.manifold == "euclidean" and problem.tangent_dim == 3
    assert PointAlignmentPair(1).manifold == "se3"


def test_options_reach_the_solver():
    problem, x0 = instance("exp:40:2")
    s = bivo.solve(problem, bivo.WeightedSum(1.0), "gn", x0, bivo.SolverOptions(max_iterations=2))
    assert s.iterations == 2 and s.termination == "iteration budget"
    assert not s.converged


def test_solve_releases_the_gil():
    """While a C++ problem is solved in another thread, this thread keeps running Python
    inside the solve's time span: with the GIL held it could run only between solves."""
    import threading
    import time
    rng = np.random.default_rng(1)
    m = 30000
    problem = LinearLeastSquaresPair("large", rng.normal(size=(m, 6)), rng.normal(size=m), np.ones(m),
                                     rng.normal(size=(m, 6)), rng.normal(size=m), np.ones(m))
    spans, done = [], threading.Event()

    def solve():
        for _ in range(3):
            t0 = time.perf_counter()
            bivo.solve(problem, bivo.WeightedSum(1.0), "ceres", np.zeros(6))
            spans.append((t0, time.perf_counter()))
        done.set()

    t = threading.Thread(target=solve)
    samples = []
    t.start()
    while not done.is_set():
        samples.append(time.perf_counter())
    t.join()
    samples = np.array(samples)
    for t0, t1 in spans:  # the middle half of each solve (tens of ms) holds steps of this thread
        q = 0.25 * (t1 - t0)
        assert np.count_nonzero((samples > t0 + q) & (samples < t1 - q)) > 0, (t0, t1)
