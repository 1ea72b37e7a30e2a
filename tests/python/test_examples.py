"""The Python example runs and writes its plot."""
import os
import subprocess
import sys


def test_pareto_example_writes_its_plot(tmp_path):
    script = os.path.join(os.environ["BIVO_SOURCE_DIR"], "examples", "python", "pareto_synthetic_pair.py")
    out = tmp_path / "front.png"
    r = subprocess.run([sys.executable, script, "--output", str(out), "--points", "7"], capture_output=True,
                       text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    assert out.stat().st_size > 10000
    assert r.stdout.count("hypervolume") == 3
