"""Time per frame pair of every method (paper table 3), median bar with mean marker.

usage: runtime_bars.py RUNTIME.csv OUT.png
RUNTIME.csv columns: method, backend, median_ms, mean_ms (one row per method, e.g. summed
over sequences by the writer).
"""
from common import colour, need_args, plt, read_csv, save

src, out = need_args(2, "runtime_bars.py RUNTIME.csv OUT.png")
rows = read_csv(src)
labels = [f'{r["method"]}\n({r["backend"]})' for r in rows]
med = [float(r["median_ms"]) for r in rows]
mean = [float(r["mean_ms"]) for r in rows]
fig, ax = plt.subplots(figsize=(1.3 * len(rows) + 2, 3.6))
x = range(len(rows))
ax.bar(x, med, color=[colour(r["method"]) or "C0" for r in rows], label="median")
ax.scatter(x, mean, color="k", marker="_", s=300, zorder=3, label="mean")
for i, v in enumerate(med):
    ax.text(i, v, f"{v:.1f}", ha="center", va="bottom", fontsize=8)
ax.set_xticks(list(x))
ax.set_xticklabels(labels, fontsize=8)
ax.set_ylabel("time per frame pair [ms]")
if max(med) > 50 * max(min(med), 1e-9):
    ax.set_yscale("log")
ax.grid(axis="y", alpha=0.3)
ax.legend(fontsize=8)
save(fig, out)
