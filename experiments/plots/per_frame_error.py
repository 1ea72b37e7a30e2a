"""Per-frame translational error of every method, one panel per sequence (paper fig. 5).

usage: per_frame_error.py PAIRS.csv OUT.png
PAIRS.csv columns: sequence, method, pair, t, trans_err_m (pairs without ground truth are
left out by the writer).
"""
from collections import defaultdict

from common import colour, marker, need_args, plt, read_csv, save

src, out = need_args(2, "per_frame_error.py PAIRS.csv OUT.png")
rows = read_csv(src)
series = defaultdict(lambda: defaultdict(list))
for r in rows:
    series[r["sequence"]][r["method"]].append((float(r["t"]), float(r["trans_err_m"])))
sequences = sorted(series)
fig, axes = plt.subplots(len(sequences), 1, figsize=(8, 2.6 * len(sequences)), squeeze=False)
for ax, seq in zip(axes[:, 0], sequences):
    for method, pts in series[seq].items():
        pts.sort()
        t0 = pts[0][0]
        ax.plot([p[0] - t0 for p in pts], [1000 * p[1] for p in pts], label=method, color=colour(method), lw=1,
                marker=marker(method), ms=3, markevery=max(1, len(pts) // 12))
    ax.set_title(seq, fontsize=9)
    ax.set_ylabel("error per frame [mm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=3)
axes[-1, 0].set_xlabel("time since first frame [s]")
fig.subplots_adjust(hspace=0.4)
save(fig, out)
