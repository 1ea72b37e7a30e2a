#!/usr/bin/env python3
"""Pareto front of one synthetic RGB-D frame pair (F_I photometric vs F_D depth) swept by
three solver backends, plotted with matplotlib (Agg).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/pareto_synthetic_pair.py --output front.png
"""
import argparse
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bivo  # noqa: E402

IDENTITY = np.array([0, 0, 0, 0, 0, 0, 1.0])  # x = T_21 as [t; q]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", default="pareto_synthetic_pair.png")
    parser.add_argument("--level", type=int, default=2, help="pyramid level (0 = 640x480)")
    parser.add_argument("--points", type=int, default=15)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        sequence = bivo.odometry.render_synthetic(tmp, "structure_texture_near", frames=2, seed=3)
        pair = bivo.odometry.load_frame_pair(sequence, 0, 1)
        problem = pair.problem(args.level)
        # The same front three ways: weighted sums (Gauss-Newton), epsilon-constraint steps
        # solved exactly, and by the own conic IPM.
        sweeps = [("gn", "lambda"), ("exact", "epsilon"), ("ipm-compressed", "epsilon")]
        fronts = [bivo.pareto_sweep(problem, IDENTITY, scalarization, points=args.points, backend=backend,
                                    lambda_min=1e2, lambda_max=1e8) for backend, scalarization in sweeps]
        # One reference point for all three hypervolumes (the common nadir), so they compare.
        reference = [max(f.f1.max() for f in fronts), max(f.f2.max() for f in fronts)]
        fig, ax = plt.subplots(figsize=(6, 4.5))
        for (backend, scalarization), front, marker in zip(sweeps, fronts, "o^s"):
            hv = bivo.hypervolume(front.f1, front.f2, reference)
            label = f"{backend} ({scalarization}): {len(front)} points, hypervolume {hv:.4g}"
            ax.plot(front.f1, front.f2, marker=marker, ms=4, lw=1, label=label, alpha=0.8)
            if front.knee is not None:
                ax.plot(front.f1[front.knee], front.f2[front.knee], "k*", ms=12)
            print(label, "knee", front.knee)
        ax.set_xlabel("F_I (photometric)")
        ax.set_ylabel("F_D (depth)")
        ax.set_title(f"Pareto front of one synthetic pair, level {args.level} (* = knee)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.output, dpi=120)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
