"""The repetitions of a Google Benchmark binary's cases, read from its JSON output."""
import json
import subprocess
import tempfile


def gbench_runs(args):
    """Runs `args` (the binary and its flags) and returns {run name: [its iteration runs]}."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run(list(args) + ["--benchmark_out=" + out.name, "--benchmark_out_format=json"], check=True,
                       stdout=subprocess.DEVNULL)
        data = json.load(open(out.name))
    runs = {}
    for b in data["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration" or b.get("error_occurred"):
            continue
        runs.setdefault(b.get("run_name", b["name"]), []).append(b)
    return runs
