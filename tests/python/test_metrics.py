"""bivo.metrics against `bivo_oracle metrics` (the C++ evaluation of `bivo eval`)."""
import os

import numpy as np
import pytest

import bivo
from conftest import assert_same


@pytest.fixture(scope="module")
def trajectories(synthetic_sequence, tmp_path_factory):
    estimate = str(tmp_path_factory.mktemp("est") / "estimate.txt")
    bivo.track(synthetic_sequence, max_frames=4).write_trajectory(estimate)
    return os.path.join(synthetic_sequence, "groundtruth.txt"), estimate


def test_files_and_arrays_match_cpp(oracle, trajectories):
    gt, est = trajectories
    # Four frames at 30 Hz: windows of 0.03 s (one frame; the last is not a window start: two windows).
    ref = oracle("metrics", gt, est, 0.03)
    e = bivo.metrics.evaluate_files(gt, est, delta=0.03)
    assert_same(e["rpe"]["trans_rmse"], ref["rpe_trans_rmse"])
    assert_same(e["rpe"]["rot_rmse_deg"], ref["rpe_rot_rmse_deg"])
    assert_same(e["ate"]["rmse"], ref["ate_rmse"])
    assert len(e["rpe"]["trans"]) == ref["rpe_pairs"]
    # The same through arrays.
    (tg, pg), (te, pe) = bivo.metrics.read_trajectory(gt), bivo.metrics.read_trajectory(est)
    rpe = bivo.metrics.rpe(tg, pg, te, pe, delta=0.03)
    ate = bivo.metrics.ate(tg, pg, te, pe)
    assert_same(rpe["trans_rmse"], ref["rpe_trans_rmse"])
    assert_same(ate["rmse"], ref["ate_rmse"])
    assert_same(np.sqrt(np.mean(ate["errors"] ** 2)), ate["rmse"])


def test_ate_of_a_rigidly_moved_trajectory_is_zero():
    t = np.arange(20) * 0.1
    P = np.zeros((20, 7))
    P[:, 0] = np.sin(t)
    P[:, 1] = t
    P[:, 6] = 1.0
    Q = P.copy()
    Q[:, :3] = P[:, :3] @ np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]]).T + [1, 2, 3]
    Q[:, 5], Q[:, 6] = np.sin(np.pi / 4), np.cos(np.pi / 4)
    assert bivo.metrics.ate(t, P, t, Q)["rmse"] < 1e-12
    assert bivo.metrics.rpe(t, P, t, Q, delta=0.5)["trans_rmse"] < 1e-12


@pytest.mark.parametrize("change,match", [
    (lambda t, P: (t, P[:, :6]), r"poses: expected shape \(20, 7\)"),
    (lambda t, P: (t[::-1].copy(), P), "not strictly increasing"),
    (lambda t, P: (t, np.where(P == 1.0, np.nan, P)), "NaN/Inf"),
    (lambda t, P: (t, np.zeros_like(P)), "zero quaternion"),
])
def test_bad_arrays_are_value_errors(change, match):
    t = np.arange(20) * 0.1
    P = np.zeros((20, 7))
    P[:, 6] = 1.0
    bt, bP = change(t, P)
    with pytest.raises(ValueError, match=match):
        bivo.metrics.ate(t, P, bt, bP)


def test_a_bad_file_names_its_line(tmp_path):
    bad = tmp_path / "bad.txt"
    bad.write_text("1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n")
    with pytest.raises(bivo.Error, match="bad.txt.*2"):
        bivo.metrics.read_trajectory(str(bad))
