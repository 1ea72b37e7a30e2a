"""Error vs the scalarization parameter (lambda log grid, or epsilon), paper fig. 3: the
RMSE and max-error ratios to the single-objective run, one line per sequence.

usage: parameter_sweep.py SWEEP.csv OUT.png
SWEEP.csv columns: sequence, parameter (lambda|epsilon), value, rpe_trans, max_err,
rmse_ratio, max_ratio.
"""
from collections import defaultdict

from common import need_args, plt, read_csv, save

src, out = need_args(2, "parameter_sweep.py SWEEP.csv OUT.png")
rows = read_csv(src)
by = defaultdict(lambda: defaultdict(list))
for r in rows:
    by[r["parameter"]][r["sequence"]].append(
        (float(r["value"]), float(r["rmse_ratio"]), float(r["max_ratio"])))
params = [p for p in ("lambda", "epsilon") if p in by]  # lambda left, epsilon right
fig, axes = plt.subplots(1, len(params), figsize=(6.5 * len(params), 4), squeeze=False)
for ax, p in zip(axes[0], params):
    for i, (seq, pts) in enumerate(sorted(by[p].items())):
        pts.sort()
        c = f"C{i}"
        ax.plot([q[0] for q in pts], [q[1] for q in pts], "o-", color=c, ms=3, label=f"{seq} RMSE")
        ax.plot([q[0] for q in pts], [q[2] for q in pts], "s--", color=c, ms=3, alpha=0.7, label=f"{seq} max")
    ax.set_xscale("log")
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xlabel("lambda of F_I + lambda F_D [gray^2/m^2]" if p == "lambda"
                  else "epsilon: bound on F_D per unit weight [m^2]")
    ax.set_ylabel("error / single-objective error")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
save(fig, out)
