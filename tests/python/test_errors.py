"""Bad inputs to the solver layer: ValueError for arrays, bivo.Error (C++ message) otherwise."""
import numpy as np
import pytest

import bivo
from bivo.problems import LinearLeastSquaresPair


@pytest.fixture
def problem():
    return LinearLeastSquaresPair.well_conditioned(3, 1)


@pytest.mark.parametrize("x0,match", [
    (np.zeros(4), "x0: expected 3 entries, got 4"),
    (np.zeros((3, 1)), "x0: expected a 1-D array, got 2-D"),
    (np.array([0, np.nan, 0]), "x0: entry 1"),
    (np.array([0, np.inf, 0]), "NaN/Inf"),
    (np.array(["a", "b", "c"]), "x0: expected real numbers, got dtype <U1"),
    (np.array([1j, 0, 0]), "dtype complex128"),
    ("abc", "expected real numbers"),
    (None, "x0"),
])
def test_bad_start_points_are_value_errors(problem, x0, match):
    with pytest.raises(ValueError, match=match):
        bivo.solve(problem, bivo.WeightedSum(1.0), "gn", x0)


def test_integer_arrays_are_accepted(problem):
    s = bivo.solve(problem, bivo.WeightedSum(1.0), "gn", np.zeros(3, dtype=np.int64))
    assert s.converged


def test_cpp_errors_carry_their_message(problem):
    with pytest.raises(bivo.Error, match="unknown solver backend 'newton'; valid backends") as e:
        bivo.solve(problem, bivo.WeightedSum(1.0), "newton", np.zeros(3))
    assert "ipm-compressed" in str(e.value)
    with pytest.raises(bivo.Error, match="does not support"):
        bivo.solve(problem, bivo.WeightedSum(1.0), "exact", np.zeros(3))
    with pytest.raises(bivo.Error, match="lambda"):
        bivo.WeightedSum(-1.0)
    with pytest.raises(bivo.Error, match="epsilon"):
        bivo.EpsilonConstraint(float("nan"))
    assert issubclass(bivo.Error, RuntimeError)


def test_bad_arguments_of_the_other_entry_points(problem):
    with pytest.raises(ValueError, match="scalarization: 'epsilon'"):
        bivo.pareto_sweep(problem, np.zeros(3), "chebyshev")
    with pytest.raises(ValueError, match="options"):
        bivo.solve(problem, bivo.WeightedSum(1.0), "gn", np.zeros(3), {"max_iterations": 3})
    with pytest.raises(ValueError, match="not a non-dominated front"):
        bivo.knee_index([1, 2, 3], [3, 4, 1])
    with pytest.raises(ValueError, match="reference: expected 2 entries"):
        bivo.hypervolume([1, 2], [2, 1], [3, 3, 3])
    with pytest.raises(ValueError, match="A2: expected shape"):
        LinearLeastSquaresPair("x", np.eye(3), np.ones(3), np.ones(3), np.eye(2), np.ones(2), np.ones(2))
    with pytest.raises(ValueError, match="j: objective index"):
        problem.residuals(3, np.zeros(3))
