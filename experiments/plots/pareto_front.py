"""Pareto front (F_I, F_D) of one frame pair traced by a lambda sweep and by an epsilon
sweep, the points each method picks, and the knee; colour = pose error vs ground truth.

usage: pareto_front.py PARETO.json OUT.png
PARETO.json: {"title": str, "lambda_sweep": [{"f_i","f_d","lambda","trans_err_m"?}],
"epsilon_sweep": [{"f_i","f_d","epsilon","trans_err_m"?}], "methods": [{"method","f_i","f_d"}],
"knee": {"f_i","f_d"} | null}
"""
import json
import sys

from common import colour, marker, need_args, plt, save

src, out = need_args(2, "pareto_front.py PARETO.json OUT.png")
try:
    with open(src) as f:
        d = json.load(f)
except (OSError, ValueError) as e:
    sys.exit(f"plot: cannot read '{src}': {e}")
fig, ax = plt.subplots(figsize=(6.5, 5))
has_err = any("trans_err_m" in p for p in d["lambda_sweep"] + d["epsilon_sweep"])
for key, shape, label in (("lambda_sweep", "o", "lambda sweep"), ("epsilon_sweep", "^", "epsilon sweep")):
    pts = d[key]
    if not pts:
        continue
    xs, ys = [p["f_i"] for p in pts], [p["f_d"] for p in pts]
    ax.plot(xs, ys, "-", lw=0.6, color="0.6")
    if has_err:
        sc = ax.scatter(xs, ys, c=[1000 * p.get("trans_err_m", float("nan")) for p in pts], marker=shape,
                        cmap="viridis", s=22, label=label, edgecolors="none")
    else:
        sc = ax.scatter(xs, ys, marker=shape, s=22, label=label)
if has_err:
    fig.colorbar(sc, ax=ax, label="translation error vs ground truth [mm]")
# Picks often coincide (single and bounded where the bound is slack): each is drawn smaller
# than the one before, so every marker stays visible on top of the others.
for i, m in enumerate(d.get("methods", [])):
    ax.scatter([m["f_i"]], [m["f_d"]], marker=marker(m["method"]), s=max(40, 230 - 30 * i),
               color=colour(m["method"]), edgecolors="k", linewidths=0.6, zorder=5 + 0.1 * i, label=m["method"])
if d.get("knee"):
    ax.scatter([d["knee"]["f_i"]], [d["knee"]["f_d"]], marker="D", s=70, facecolors="none", edgecolors="r",
               linewidths=1.5, zorder=6, label="knee")
# Log axes only where an objective spans more than a decade over the plotted points.
all_pts = d["lambda_sweep"] + d["epsilon_sweep"] + d.get("methods", [])
for key, setter in (("f_i", ax.set_xscale), ("f_d", ax.set_yscale)):
    vals = [p[key] for p in all_pts if p[key] > 0]
    if vals and max(vals) > 10 * min(vals):
        setter("log")
ax.set_xlabel("F_I (intensity objective)")
ax.set_ylabel("F_D (depth objective)")
ax.set_title(d.get("title", ""), fontsize=9)
ax.grid(alpha=0.3, which="both")
ax.legend(fontsize=7)
save(fig, out)
