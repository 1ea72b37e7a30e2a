"""Shared helpers of the bivo plot scripts: CSV reading, atomic PNG saving, method colours."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display on CI machines
import matplotlib.pyplot as plt  # noqa: E402

# One colour per method, stable across every plot of a report.
METHOD_COLOURS = {
    "single": "#d62728",
    "depth": "#8c564b",
    "fixed": "#7f7f7f",
    "tykkala": "#ff7f0e",
    "weighted": "#1f77b4",
    "bounded": "#2ca02c",
}


def colour(method):
    return METHOD_COLOURS.get(method, None)


def read_csv(path):
    """Rows as dicts; exits with a message naming the file when it is missing or empty."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot: cannot read '{path}': {e}")
    if not rows:
        sys.exit(f"plot: '{path}' has no data rows")
    return rows


def save(fig, path):
    """Writes the figure to a temporary file beside `path`, then renames it (atomic)."""
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110, bbox_inches="tight")
    plt.close(fig)
    os.replace(tmp, path)


def need_args(n, usage):
    if len(sys.argv) != n + 1:
        sys.exit("usage: " + usage)
    return sys.argv[1:]
