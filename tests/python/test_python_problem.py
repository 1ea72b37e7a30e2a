"""bivo.Problem: problems written in Python, solved by every backend and checked against
closed forms and against the same problem in C++."""
import numpy as np
import pytest

import bivo
from bivo.problems import LinearLeastSquaresPair
from conftest import IDENTITY, assert_same

WS_BACKENDS = [b["name"] for b in bivo.backends() if b["weighted_sum"]]
EPS_BACKENDS = [b["name"] for b in bivo.backends() if b["epsilon_constraint"]]
A = np.array([1.0, 2.0, -0.5])
B = np.array([-1.0, 0.5, 1.5])
D = np.linalg.norm(A - B)


class TwoTargets(bivo.Problem):
    """F_j = |x - target_j|^2 in R^3. Closed form: the front is the segment between the
    targets; weighted sum x(lam) = (a + lam b) / (1 + lam); sqrt(F1) + sqrt(F2) = |a - b|."""

    def __init__(self):
        super().__init__(3, "euclidean", "two targets")

    def residual(self, j, x):
        return x - (A if j == 1 else B)

    def jacobian(self, j, x):
        return np.eye(3)

    def weights(self, j):
        return np.ones(3)


@pytest.mark.parametrize("backend", WS_BACKENDS)
def test_weighted_sum_backends_reach_the_closed_form(backend):
    lam = 0.6
    s = bivo.solve(TwoTargets(), bivo.WeightedSum(lam), backend, np.zeros(3))
    assert_same(s.x, (A + lam * B) / (1 + lam), 1e-8)
    assert_same([s.final_f1, s.final_f2], [(lam * D / (1 + lam)) ** 2, (D / (1 + lam)) ** 2], 1e-8)


@pytest.mark.parametrize("backend", EPS_BACKENDS)
def test_epsilon_constraint_backends_reach_the_closed_form(backend):
    eps = 0.3 * D ** 2
    s = bivo.solve(TwoTargets(), bivo.EpsilonConstraint(eps), backend, np.zeros(3))
    x = B + np.sqrt(eps) * (A - B) / D  # on the segment, at distance sqrt(eps) from b
    assert_same(s.x, x, 1e-6)
    assert_same(s.final_f1, (D - np.sqrt(eps)) ** 2, 1e-6)
    assert s.final_f2 <= eps * (1 + 1e-6)
    # mu = -dF1/dF2 along the front = (D - sqrt(eps)) / sqrt(eps)
    assert_same(s.multiplier, (D - np.sqrt(eps)) / np.sqrt(eps), 1e-4)


def test_swept_front_lies_on_the_closed_form():
    front = bivo.pareto_sweep(TwoTargets(), np.zeros(3), "epsilon", points=11)
    assert len(front) >= 9
    assert_same(np.sqrt(front.f1) + np.sqrt(front.f2), np.full(len(front), D), 1e-6)
    # Both objectives range over [0, D^2]: the knee is the point farthest below the chord f1 + f2 = D^2.
    assert front.knee == np.argmin(front.f1 + front.f2)


class Linear(bivo.Problem):
    def __init__(self, A1, y1, w1, A2, y2, w2):
        super().__init__(A1.shape[1], name="linear in Python")
        self.data = {1: (A1, y1, w1), 2: (A2, y2, w2)}

    def residual(self, j, x):
        A, y, _ = self.data[j]
        return A @ x - y

    def jacobian(self, j, x):
        return self.data[j][0]

    def weights(self, j):
        return self.data[j][2]


@pytest.mark.parametrize("backend,lam_or_eps", [("gn", 0.4), ("ceres", 2.0), ("exact", None), ("ipm-full", None)])
def test_python_problem_gives_what_the_same_cpp_problem_gives(backend, lam_or_eps):
    rng = np.random.default_rng(3)
    A1, A2 = rng.normal(size=(12, 4)), rng.normal(size=(12, 4))
    y1, y2 = rng.normal(size=12), rng.normal(size=12)
    w1, w2 = rng.uniform(0.5, 2, size=12), rng.uniform(0.5, 2, size=12)
    cpp = LinearLeastSquaresPair("linear in C++", A1, y1, w1, A2, y2, w2)
    py = Linear(A1, y1, w1, A2, y2, w2)
    x0 = np.zeros(4)
    if lam_or_eps is None:
        f2 = [cpp.objectives(cpp.minimizer(j))[1] for j in (2, 1)]
        scal = bivo.EpsilonConstraint(f2[0] + 0.5 * (f2[1] - f2[0]))
    else:
        scal = bivo.WeightedSum(lam_or_eps)
    a, b = bivo.solve(cpp, scal, backend, x0), bivo.solve(py, scal, backend, x0)
    assert_same(b.x, a.x, 1e-9)
    assert_same([b.final_f1, b.final_f2], [a.final_f1, a.final_f2], 1e-9)
    assert_same(py.evaluate(a.x), cpp.evaluate(a.x), 1e-12)
    assert py.callbacks > 0


class Alignment(bivo.Problem):
    """F_j = sum_i |T p_i - q_ji|^2 on SE(3) with q_1 = T_a p exactly: argmin F1 = T_a."""

    def __init__(self, Ta, Tb, p):
        super().__init__(6, "se3", "alignment in Python")
        self.p = p
        self.q = {1: p @ Ta[:3, :3].T + Ta[:3, 3], 2: p @ Tb[:3, :3].T + Tb[:3, 3]}

    @staticmethod
    def rotation(x):
        qx, qy, qz, qw = x[3:] / np.linalg.norm(x[3:])
        return np.array([[1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)],
                         [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)],
                         [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)]])

    def moved(self, x):
        return self.p @ self.rotation(x).T + x[:3]

    def residual(self, j, x):
        return (self.moved(x) - self.q[j]).ravel()

    def jacobian(self, j, x):
        J = np.zeros((3 * len(self.p), 6))
        for i, m in enumerate(self.moved(x)):  # d(exp(d) T p)/dd = [I, -hat(T p)]
            J[3 * i:3 * i + 3, :3] = np.eye(3)
            J[3 * i:3 * i + 3, 3:] = -np.array([[0, -m[2], m[1]], [m[2], 0, -m[0]], [-m[1], m[0], 0]])
        return J


def pose(angle, axis, t):
    axis = np.asarray(axis) / np.linalg.norm(axis)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    T = np.eye(4)
    T[:3, :3] = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
    T[:3, 3] = t
    return T


@pytest.mark.parametrize("backend,scal", [("gn", "ws"), ("lm", "ws"), ("ceres", "ws"), ("exact", "eps"),
                                          ("ipm-compressed", "eps"), ("ipopt-nlp", "eps")])
def test_se3_python_problem_reaches_the_exact_pose(backend, scal):
    rng = np.random.default_rng(8)
    Ta, Tb = pose(0.3, [1, 2, 3], [0.1, -0.2, 0.05]), pose(0.35, [1, 2, 2.5], [0.15, -0.2, 0.0])
    problem = Alignment(Ta, Tb, rng.normal(size=(10, 3)) + [0, 0, 3])
    # lambda = 0 / epsilon above F2(T_a): the optimum is T_a itself (F1 = 0).
    s = bivo.solve(problem, bivo.WeightedSum(0.0) if scal == "ws" else bivo.EpsilonConstraint(1e6), backend,
                   IDENTITY)
    R = Alignment.rotation(s.x)
    assert np.abs(R - Ta[:3, :3]).max() < 1e-6 and np.abs(s.x[:3] - Ta[:3, 3]).max() < 1e-6
    assert s.final_f1 < 1e-10


class Failing(TwoTargets):
    def __init__(self, fail):
        super().__init__()
        self.fail = fail
        self.calls = 0

    def residual(self, j, x):
        self.calls += 1
        if self.fail == "raise" and self.calls > 8:  # inside the solver, past its set-up
            raise ZeroDivisionError("user code failed")
        if self.fail == "shape":
            return np.zeros(2)
        if self.fail == "dtype":
            return np.array(["a", "b", "c"])
        return super().residual(j, x)

    def jacobian(self, j, x):
        return np.eye(2) if self.fail == "jacobian" else np.eye(3)


@pytest.mark.parametrize("backend", ["gn", "ceres", "ipopt-nlp", "ipm-full"])
def test_exceptions_in_callbacks_reach_python_unchanged(backend):
    scal = bivo.WeightedSum(1.0) if backend in WS_BACKENDS else bivo.EpsilonConstraint(1.0)
    with pytest.raises(ZeroDivisionError, match="user code failed"):
        bivo.solve(Failing("raise"), scal, backend, np.zeros(3))


@pytest.mark.parametrize("fail,match", [("jacobian", r"jacobian\(1, x\): expected shape \(3, 3\)"),
                                        ("dtype", "expected real numbers")])
def test_bad_arrays_from_callbacks_are_value_errors(fail, match):
    with pytest.raises(ValueError, match=match):
        bivo.solve(Failing(fail), bivo.WeightedSum(1.0), "gn", np.zeros(3))


def test_a_residual_of_changing_length_is_a_value_error():
    class Changing(TwoTargets):
        calls = 0

        def residual(self, j, x):
            Changing.calls += 1
            return np.zeros(3 if Changing.calls < 3 else 4)

    with pytest.raises(ValueError, match="expected 3 entries, got 4"):
        bivo.solve(Changing(), bivo.WeightedSum(1.0), "gn", np.ones(3))


def test_missing_methods_and_bad_construction():
    class NoJacobian(bivo.Problem):
        def __init__(self):
            super().__init__(2)

        def residual(self, j, x):
            return x

    with pytest.raises(TypeError, match="must define jacobian"):
        bivo.solve(NoJacobian(), bivo.WeightedSum(1.0), "gn", np.zeros(2))
    with pytest.raises(ValueError, match="manifold must be"):
        bivo.Problem(2, "sphere")
    with pytest.raises(ValueError, match="dim 6"):
        bivo.Problem(3, "se3")


class InflatedJacobian(bivo.Problem):
    """F_1 = |x - a|^2, but a Jacobian 5 times too large: Gauss-Newton steps cover a fifth of
    the way (rho = 0.8), so extrapolated steps must get there in fewer iterations."""

    def __init__(self):
        super().__init__(3, "euclidean", "inflated jacobian")

    def residual(self, j, x):
        return x - A if j == 1 else np.zeros(3)

    def jacobian(self, j, x):
        return np.sqrt(5.0) * np.eye(3) if j == 1 else np.zeros((3, 3))

    def weights(self, j):
        return np.ones(3)


def test_extrapolated_steps_reach_the_same_point_in_fewer_iterations():
    options = bivo.SolverOptions(max_iterations=200, step_tolerance=1e-10, relative_decrease_tolerance=0.0)
    plain = bivo.solve(InflatedJacobian(), bivo.WeightedSum(0.0), "gn", np.zeros(3), options)
    options.max_step_extrapolation = 1.9
    fast = bivo.solve(InflatedJacobian(), bivo.WeightedSum(0.0), "gn", np.zeros(3), options)
    assert_same(plain.x, A, 1e-8)
    assert_same(fast.x, A, 1e-8)
    assert plain.extrapolated_steps == 0 and fast.extrapolated_steps > 0
    assert max(fast.step_scales) == pytest.approx(1.9)
    assert fast.iterations < 0.6 * plain.iterations, (plain.iterations, fast.iterations)
