"""Shared fixtures of the Python tests: the C++ oracle (bivo_oracle, the same computations
through the C++ API, printed as round-trip JSON) and one small synthetic sequence."""
import json
import os
import subprocess

import numpy as np
import pytest

import bivo

ORACLE = os.environ.get("BIVO_ORACLE")
IDENTITY = np.array([0, 0, 0, 0, 0, 0, 1.0])


@pytest.fixture(scope="session")
def oracle():
    if not ORACLE:
        pytest.fail("BIVO_ORACLE is not set (run the tests through ctest)")

    def run(*args, may_fail=False):
        """The oracle's JSON; with may_fail, {"error": message} when the C++ call threw."""
        out = subprocess.run([ORACLE, *map(str, args)], capture_output=True, text=True)
        if may_fail and out.returncode == 1 and out.stderr.startswith("bivo_oracle: "):
            return {"error": out.stderr[len("bivo_oracle: "):].strip()}
        assert out.returncode == 0, out.stderr
        return json.loads(out.stdout)

    return run


@pytest.fixture(scope="session")
def synthetic_sequence(tmp_path_factory):
    """Four frames of a textured, structured synthetic scene with exact ground truth."""
    folder = tmp_path_factory.mktemp("synth")
    return bivo.odometry.render_synthetic(str(folder), "structure_texture_near", frames=4, seed=5, threads=1)


def assert_same(actual, expected, tol=1e-12):
    """Equal to `tol` relative to the larger magnitude (1 for numbers near 0); infinities and
    NaN (the oracle writes them as the strings "inf", "nan") must sit at the same places."""
    a = np.asarray(actual, dtype=float)
    e = np.asarray(expected, dtype=float)
    assert a.shape == e.shape, (a.shape, e.shape)
    finite = np.isfinite(a) & np.isfinite(e)
    assert np.array_equal(a[~finite], e[~finite], equal_nan=True), (a, e)
    a, e = a[finite], e[finite]
    scale = np.maximum(1.0, np.maximum(np.abs(a), np.abs(e)))
    assert np.all(np.abs(a - e) <= tol * scale), np.max(np.abs(a - e) / scale)
