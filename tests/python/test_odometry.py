"""The odometry bindings on a synthetic sequence, against bivo_oracle (the C++ tracker)."""
import shutil

import numpy as np
import pytest

import bivo
from conftest import IDENTITY, assert_same


def test_frame_pair_problem_and_estimate_match_cpp(oracle, synthetic_sequence):
    pair = bivo.odometry.load_frame_pair(synthetic_sequence, 0, 1)
    ref = oracle("pair", synthetic_sequence, 0, 1, 2, "weighted", "")
    problem = pair.problem(2)
    assert problem.manifold == "se3" and problem.num_terms > 200
    assert_same(problem.objectives_at(IDENTITY), ref["objectives_at_identity"])
    assert_same(pair.lam(), ref["lambda"])
    s = bivo.solve(problem, bivo.WeightedSum(pair.lam()), "gn", IDENTITY)
    assert_same(s.x, ref["solve"]["x"])
    assert_same(s.f1, ref["solve"]["f1"])
    result = pair.estimate()
    assert_same(result.T_21, ref["T_21"])
    # Synthetic frames have exact ground truth: the estimate is close to it.
    assert pair.groundtruth_T21 is not None
    assert result.translation_error < 0.01 and result.rotation_error_deg < 0.5


@pytest.mark.parametrize("method,backend", [("weighted", ""), ("bounded", "ipm-compressed"), ("fixed", "ceres")])
def test_track_matches_cpp(oracle, synthetic_sequence, method, backend):
    r = bivo.track(synthetic_sequence, method=method, backend=backend, max_frames=3)
    ref = oracle("track", synthetic_sequence, method, backend, 3)
    assert_same(r.poses, ref["poses"])
    assert list(r.iterations) == ref["iterations"]
    assert r.poses.shape == (3, 7) and r.timestamps.shape == (3,)
    assert len(r.pairs) == 2 and r.valid.all()
    assert np.all(np.isfinite(r.translation_errors)) and np.all(r.translation_errors < 0.02)


@pytest.mark.parametrize("method", ["joint", "robust", "noise-bounded"])
def test_pair_and_level_diagnostics_match_cpp(oracle, synthetic_sequence, method):
    r = bivo.track(synthetic_sequence, method=method, max_frames=3)
    ref = oracle("track", synthetic_sequence, method, "", 3)
    assert len(r.pairs) == len(ref["pairs"]) == 2
    for pair, ref_pair in zip(r.pairs, ref["pairs"]):
        for key in ("correlation", "trust", "epsilon_per_weight"):
            assert_same(getattr(pair, key), ref_pair[key])
        assert pair.relaxed_levels == ref_pair["relaxed_levels"]
        assert pair.cpu_seconds > 0 and pair.load_seconds >= 0
        assert len(pair.levels) == len(ref_pair["levels"])
        for level, ref_level in zip(pair.levels, ref_pair["levels"]):
            for key, value in ref_level.items():
                if isinstance(value, bool) or isinstance(value, int):
                    assert getattr(level, key) == value, key
                else:
                    assert_same(getattr(level, key), value)
    finest = [p.levels[-1] for p in r.pairs]
    if method == "joint":  # S is a covariance: its correlation lies in (-1, 1), and is not 0 on real residuals
        assert all(0 < abs(l.correlation) < 1 for l in finest)
    if method == "robust":  # the trust test is off by default: T is not evaluated
        assert all(np.isnan(l.trust) for l in finest) and not any(l.kept_prior for l in finest)
    if method == "noise-bounded":
        assert all(np.isfinite(l.guard_rise) for l in finest)


def test_every_backend_solves_a_pair_problem(synthetic_sequence):
    pair = bivo.odometry.load_frame_pair(synthetic_sequence, 0, 1, levels=4)
    problem = pair.problem(3)
    f2 = [bivo.solve(problem, bivo.WeightedSum(lam), "gn", IDENTITY).final_f2 for lam in (1e8, 0.0)]
    for b in bivo.backends():
        # epsilon near F_D at argmin F_I: reachable also by ipopt-nlp, whose re-weighting passes
        # change the scale of F_D (closer to min F_D it reports the bound infeasible).
        eps = f2[0] + 0.8 * (f2[1] - f2[0])
        scal = bivo.WeightedSum(pair.lam()) if b["weighted_sum"] else bivo.EpsilonConstraint(eps)
        s = bivo.solve(problem, scal, b["name"], IDENTITY)
        assert np.all(np.isfinite(s.x)) and s.iterations > 0, b["name"]
        assert s.termination not in ("numerical failure", "backend failure"), (b["name"], s.message)


def test_bad_options_and_paths_raise_bivo_errors(synthetic_sequence, tmp_path):
    with pytest.raises(bivo.Error, match="method"):
        bivo.track(synthetic_sequence, method="nonsense")
    with pytest.raises(bivo.Error, match="no_such_option"):
        bivo.track(synthetic_sequence, no_such_option=3)
    with pytest.raises(bivo.Error, match=str(tmp_path)):
        bivo.track(str(tmp_path / "missing"))
    with pytest.raises(bivo.Error, match="level 9 outside"):
        bivo.odometry.load_frame_pair(synthetic_sequence, 0, 1).problem(9)
    with pytest.raises(ValueError, match="expected 7 entries"):
        bivo.odometry.load_frame_pair(synthetic_sequence, 0, 1).estimate(np.zeros(6))


def test_open_sequence_lists_frames_and_ground_truth(synthetic_sequence):
    seq = bivo.odometry.open_sequence(synthetic_sequence)
    assert len(seq["timestamps"]) == 4 and len(seq["rgb"]) == 4
    t, poses = seq["groundtruth"]
    assert poses.shape == (len(t), 7)
    assert seq["intrinsics"]["fx"] > 0
    assert seq["distortion"] == {"k1": 0.0, "k2": 0.0, "p1": 0.0, "p2": 0.0, "k3": 0.0}  # a rendering
    assert seq["readout_time"] is None  # rendered without sensor defects: no readout stated
    assert seq["vignetting"] is None  # nor a fall-off
    track = bivo.track(synthetic_sequence, max_frames=2)
    assert_same(track.timestamps, seq["timestamps"][:2], 0.0)
    assert_same(track.poses[0], poses[0], 1e-9)  # the first pose starts at the ground truth


def test_open_sequence_reads_a_stated_fall_off(synthetic_sequence, tmp_path):
    copy = tmp_path / "stated"
    shutil.copytree(synthetic_sequence, copy)
    (copy / "scene.json").write_text('{"sensor_defects": {"vignetting": 0.2, "readout_s": 0.01}}')
    seq = bivo.odometry.open_sequence(str(copy))
    assert seq["vignetting"] == 0.2 and seq["readout_time"] == 0.01
    (copy / "scene.json").write_text('{"sensor_defects": {"vignetting": 1.5}}')
    with pytest.raises(bivo.Error, match="vignetting: 1.5"):
        bivo.odometry.open_sequence(str(copy))


def test_tracker_options_are_the_config_file_keys():
    o = bivo.odometry.tracker_options(method="bounded", policy={"eps": 2e-4})
    assert o["method"] == "bounded" and o["policy"]["eps"] == 2e-4
    lens = {"k1": 0.25, "k2": -0.5, "p1": 0.001, "p2": -0.002, "k3": 1.0}
    assert bivo.odometry.tracker_options(distortion=lens)["distortion"] == lens
    assert "weighted" in bivo.odometry.methods()


def test_tracker_keywords_are_checked_as_the_config_file_and_the_flags():
    # The same table and check as `bivo run --nu -2` and a file holding {"problem": {"weights": {"nu": -2}}}.
    message = "tracker options: problem.weights.nu: -2 is outside (0, inf]"
    with pytest.raises(bivo.Error, match=message.replace("(", r"\(").replace("[", r"\[").replace("]", r"\]")):
        bivo.odometry.tracker_options(problem={"weights": {"nu": -2}})
    with pytest.raises(bivo.Error, match=r"problem\.weights\.nu: -2 is outside \(0, inf\]"):
        bivo.odometry.tracker_options(nu=-2)
    with pytest.raises(bivo.Error, match=r"step_tolerance: -1 is outside \[0, inf\]"):
        bivo.odometry.tracker_options(step_tolerance=-1)
    # A flat keyword lands on the nested key.
    assert bivo.odometry.tracker_options(nu=3.5, phi=40)["problem"]["weights"]["nu"] == 3.5
    assert bivo.odometry.tracker_options(phi=40)["policy"]["phi"] == 40
    rows = bivo.odometry.tracker_option_table()
    nu = next(r for r in rows if r["key"] == "problem.weights.nu")
    assert nu["flag"] == "--nu" and nu["python_name"] == "nu" and nu["range"] == "(0, inf]" and nu["default"] == 5
