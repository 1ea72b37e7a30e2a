"""Contact sheet of the 8 synthetic Structure-vs-Texture categories: for the middle frame
(the nominal view) of each sequence rendered by `bivo synth`, the colour image, the
intensity the tracker sees (gray, contrast stretched to its own 1st-99th percentile, so
the faint shading of white foil shows) and the depth.

usage: /usr/bin/python3 contact_sheet.py SEQUENCES_DIR OUT.png
SEQUENCES_DIR holds rgbd_dataset_freiburg3_synth_<category> folders for all 8 categories
(e.g. the benchmark set of `bivo synth --benchmark-set`).

Sensor defects (`--defects`, contact_sheet_defects.py): each defect of `bivo synth` on one
frame beside the same frame rendered without it, and real frames beside them.
"""
import os
import sys

import numpy as np
from PIL import Image

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import need_args, plt, save  # noqa: E402

CATEGORIES = [f"{s}_{t}_{d}" for d in ("near", "far") for s in ("structure", "nostructure")
              for t in ("texture", "notexture")]


def middle_frame(seq):
    """(rgb array, depth in metres) of the middle line of associations.txt."""
    path = os.path.join(seq, "associations.txt")
    try:
        with open(path) as f:
            rows = [line.split() for line in f if line.strip() and not line.startswith("#")]
    except OSError as e:
        sys.exit(f"contact_sheet: cannot read '{path}': {e}")
    if not rows or len(rows[0]) != 4:
        sys.exit(f"contact_sheet: '{path}' has no 'ts rgb ts depth' lines")
    row = rows[len(rows) // 2]
    rgb = np.array(Image.open(os.path.join(seq, row[1])))
    depth = np.array(Image.open(os.path.join(seq, row[3]))).astype(np.float64) / 5000.0
    return rgb, depth


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--defects":
        from contact_sheet_defects import main as defects_main
        defects_main(sys.argv[2:])
        return
    seq_dir, out = need_args(2, "contact_sheet.py SEQUENCES_DIR OUT.png")
    fig, axes = plt.subplots(6, 4, figsize=(13, 14.2))
    for k, cat in enumerate(CATEGORIES):
        seq = os.path.join(seq_dir, "rgbd_dataset_freiburg3_synth_" + cat)
        if not os.path.isdir(seq):
            sys.exit(f"contact_sheet: missing sequence folder '{seq}' (render it with bivo synth)")
        rgb, depth = middle_frame(seq)
        row, col = 3 * (k // 4), k % 4
        axes[row, col].imshow(rgb)
        axes[row, col].set_title(cat, fontsize=11)
        # The tracker's intensity (docs/architecture.md: 0.299 R + 0.587 G + 0.114 B).
        gray = rgb[..., :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114])
        lo, hi = np.percentile(gray, [1, 99])
        axes[row + 1, col].imshow(gray, cmap="gray", vmin=lo, vmax=hi)
        axes[row + 1, col].set_title(f"intensity stretched: {lo:.0f}-{hi:.0f} gray levels", fontsize=9)
        masked = np.ma.masked_equal(depth, 0.0)
        cmap = plt.get_cmap("viridis").copy()
        cmap.set_bad("black")  # no depth measurement
        # Per-image range (2nd-98th percentile) so the zig-zag's few-decimetre relief shows.
        lo, hi = np.percentile(depth[depth > 0], [2, 98]) if np.any(depth > 0) else (0.0, 1.0)
        im = axes[row + 2, col].imshow(masked, cmap=cmap, vmin=lo, vmax=hi)
        fig.colorbar(im, ax=axes[row + 2, col], fraction=0.035, pad=0.02, label="m")
        valid = 100.0 * np.count_nonzero(depth) / depth.size
        axes[row + 2, col].set_title(f"depth (black: missing, {valid:.1f}% valid)", fontsize=9)
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("bivo synth: Structure vs. Texture, near (rows 1-3) and far (rows 4-6): colour, intensity, depth",
                 fontsize=14, y=0.995)
    fig.tight_layout(rect=(0, 0, 1, 0.985))
    save(fig, out)


if __name__ == "__main__":
    main()
