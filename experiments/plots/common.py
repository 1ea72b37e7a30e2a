"""Shared helpers of the bivo plot scripts: CSV reading, atomic PNG saving, method styles."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only; no display on CI machines
import matplotlib.pyplot as plt  # noqa: E402

# One colour and one marker per method, distinct and the same in every plot of a report
# (matplotlib's default cycle gave two methods each colour).
METHOD_STYLES = {
    "single": ("#d62728", "o"),
    "depth": ("#8c564b", "v"),
    "fixed": ("#7f7f7f", "s"),
    "tykkala": ("#ff7f0e", "^"),
    "weighted": ("#1f77b4", "D"),
    "bounded": ("#2ca02c", "P"),
    "joint": ("#9467bd", "X"),
    "scaled": ("#e377c2", "h"),
    "noise-bounded": ("#17becf", "*"),
}
METHOD_COLOURS = {m: style[0] for m, style in METHOD_STYLES.items()}


def colour(method):
    return METHOD_STYLES.get(method, ("#000000", "."))[0]


def marker(method):
    return METHOD_STYLES.get(method, ("#000000", "."))[1]


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
