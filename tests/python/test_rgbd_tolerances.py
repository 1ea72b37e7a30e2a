"""Single-level solves of the RGB-D problem with the tracker's tolerances (docs/python.md):
they stop on a tolerance in fewer iterations than the tracker allows, where the default
SolverOptions run out their iteration budget, and land as close to the ground truth."""
import numpy as np
import pytest

import bivo
from conftest import IDENTITY


def tracker_solver_options():
    t = bivo.odometry.tracker_options()
    return bivo.SolverOptions(max_iterations=t["max_iterations"], step_tolerance=t["step_tolerance"],
                              relative_decrease_tolerance=t["relative_decrease_tolerance"])


@pytest.mark.parametrize("level", [1, 2])
def test_tracker_tolerances_converge_on_a_pair(synthetic_sequence, level):
    pair = bivo.odometry.load_frame_pair(synthetic_sequence, 0, 1)
    problem = pair.problem(level)
    scalarization = bivo.WeightedSum(pair.lam())
    options = tracker_solver_options()
    assert (options.max_iterations, options.step_tolerance, options.relative_decrease_tolerance) == (20, 1e-4, 1e-3)
    tuned = bivo.solve(problem, scalarization, "gn", IDENTITY, options)
    default = bivo.solve(problem, scalarization, "gn", IDENTITY)
    assert tuned.termination in ("step tolerance", "relative decrease"), tuned.termination
    assert tuned.iterations < options.max_iterations
    # The defaults (steps of 1e-10) are finer than the single-precision image residuals resolve.
    assert default.termination == "iteration budget" and default.iterations == bivo.SolverOptions().max_iterations
    # The oracle: the rendering's exact relative pose (T_21, x y z qx qy qz qw).
    truth = np.asarray(pair.groundtruth_T21)
    tuned_error = np.linalg.norm(np.asarray(tuned.x)[:3] - truth[:3])
    default_error = np.linalg.norm(np.asarray(default.x)[:3] - truth[:3])
    assert tuned_error < 1e-3, tuned_error
    assert tuned_error < default_error + 5e-4, (tuned_error, default_error)
