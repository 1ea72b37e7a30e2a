"""Contact sheet of the renderer's sensor defects: one frame of a deep scene moved along real
fr1/rpy motion, rendered once without defects and once per defect (same seed, so the noise
is the same and the difference is the defect alone), beside real fr1/rpy and fr3 frames.

usage: /usr/bin/python3 contact_sheet.py --defects BIVO FR1_DIR FR3_DIR WORK_DIR OUT.png
BIVO is the bivo binary; FR1_DIR / FR3_DIR are the real TUM sequences (rgbd_dataset_
freiburg1_rpy, rgbd_dataset_freiburg3_long_office_household); WORK_DIR receives the short
renderings. The PNG is written with a 256-colour palette to stay small.
"""
import io
import os
import shutil
import subprocess
import sys

import numpy as np
from PIL import Image

from common import plt

SCENE = ["--category", "structure_texture_far", "--wall-behind", "3.5", "--view-pitch", "12", "--max-range", "8",
         "--frames", "3", "--start", "9.0"]
# (name, bivo synth flags, what it changes): the values of the stress set's profiles.
DEFECTS = [
    ("depth bias 2 % radial + 0.8 % smooth (at 1 m)",
     ["--depth-bias-radial", "0.02", "--depth-bias-lowfreq", "0.008", "--depth-bias-wavelength", "300"], "depth"),
    ("depth noise 5.6e-4 z^3 (clean: 1.4e-3 z^2)", ["--depth-noise", "5.6e-4", "--depth-noise-exponent", "3"], "depth"),
    ("disparity offset per frame (0.05 px)", ["--disparity-offset", "0.05"], "depth"),
    ("speckle 0.8 % + flying pixels 50 % of edge band",
     ["--speckle-outliers", "0.008", "--flying-pixels", "0.5"], "depth"),
    ("misregistration 4/2 mm + 2 mrad",
     ["--depth-offset", "0.004", "0.002", "0", "--depth-rotation", "0", "0.002", "0"], "depth"),
    ("depth 10-14 ms after colour", ["--depth-delay", "0.010", "0.014"], "depth"),
    ("rolling shutter 25 ms + blur 10 ms",
     ["--readout", "0.025", "--exposure", "0.010", "--blur-samples", "4"], "colour"),
    ("auto-exposure gain + vignetting 0.3", ["--gain-step", "0.1", "--vignetting", "0.3"], "colour"),
]


def frame(seq, index):
    """(rgb, depth [m]) of line `index` of associations.txt."""
    with open(os.path.join(seq, "associations.txt")) as f:
        rows = [line.split() for line in f if line.strip() and not line.startswith("#")]
    if not rows:
        sys.exit(f"contact_sheet: '{seq}' has no associations")
    row = rows[min(index, len(rows) - 1)]
    rgb = np.array(Image.open(os.path.join(seq, row[1])).convert("RGB"))
    depth = np.array(Image.open(os.path.join(seq, row[3]))).astype(np.float64) / 5000.0
    return rgb, depth


def real_frame(seq, index):
    """Real TUM sequences have no associations.txt: pair rgb.txt and depth.txt line by line."""
    lists = []
    for name in ("rgb.txt", "depth.txt"):
        with open(os.path.join(seq, name)) as f:
            lists.append([line.split() for line in f if line.strip() and not line.startswith("#")])
    k = min(index, len(lists[0]) - 1, len(lists[1]) - 1)
    rgb = np.array(Image.open(os.path.join(seq, lists[0][k][1])).convert("RGB"))
    depth = np.array(Image.open(os.path.join(seq, lists[1][k][1]))).astype(np.float64) / 5000.0
    return rgb, depth


def render(bivo, traj, work, name, flags):
    out = os.path.join(work, "rgbd_dataset_freiburg3_" + name)
    shutil.rmtree(out, ignore_errors=True)
    cmd = [bivo, "synth", *SCENE, "--trajectory", traj, "--name", os.path.basename(out), "--output", work, *flags]
    if subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode != 0:
        sys.exit("contact_sheet: failed: " + " ".join(cmd))
    return out


def show_depth(ax, depth, title):
    cmap = plt.get_cmap("viridis").copy()
    cmap.set_bad("black")
    ax.imshow(np.ma.masked_equal(depth[::2, ::2], 0.0), cmap=cmap, vmin=0.5, vmax=7.0)
    ax.set_title(title, fontsize=8)


def show_change(ax, new, old, kind):
    if kind == "depth":
        both = (new > 0) & (old > 0)
        rel = np.where(both, (new - old) / np.where(both, old, 1.0), np.nan)
        scale = max(1e-4, np.nanpercentile(np.abs(rel), 99)) if np.any(both) else 1.0
        cmap = plt.get_cmap("RdBu").copy()
        cmap.set_bad("black")
        ax.imshow(np.ma.masked_invalid(rel[::2, ::2]), cmap=cmap, vmin=-scale, vmax=scale)
        gone = 100.0 * np.count_nonzero((old > 0) & (new == 0)) / old.size
        came = 100.0 * np.count_nonzero((old == 0) & (new > 0)) / old.size
        ax.set_title(f"(z - z_clean)/z: +-{100 * scale:.2f} %; +{came:.1f} % / -{gone:.1f} % px", fontsize=8)
    else:
        g = [x[..., :3].astype(np.float64) @ np.array([0.299, 0.587, 0.114]) for x in (new, old)]
        d = g[0] - g[1]
        scale = max(1.0, np.percentile(np.abs(d), 99))
        ax.imshow(d[::2, ::2], cmap="RdBu", vmin=-scale, vmax=scale)
        ax.set_title(f"intensity - clean: +-{scale:.0f} gray levels", fontsize=8)


def main(argv):
    if len(argv) != 5:
        sys.exit("usage: contact_sheet.py --defects BIVO FR1_DIR FR3_DIR WORK_DIR OUT.png")
    bivo, fr1, fr3, work, out = argv
    os.makedirs(work, exist_ok=True)
    traj = os.path.join(fr1, "groundtruth.txt")
    clean_rgb, clean_depth = frame(render(bivo, traj, work, "defect_clean", []), 1)
    rows = len(DEFECTS) + 1
    fig, axes = plt.subplots(rows, 3, figsize=(9.6, 2.55 * rows))
    for k, (title, flags, kind) in enumerate(DEFECTS):
        rgb, depth = frame(render(bivo, traj, work, f"defect_{k}", flags), 1)
        clean = clean_depth if kind == "depth" else clean_rgb
        if kind == "depth":
            show_depth(axes[k, 0], clean_depth, "clean depth (black: missing)")
            show_depth(axes[k, 1], depth, title)
        else:
            axes[k, 0].imshow(clean_rgb[::2, ::2])
            axes[k, 0].set_title("clean colour", fontsize=8)
            axes[k, 1].imshow(rgb[::2, ::2])
            axes[k, 1].set_title(title, fontsize=8)
        show_change(axes[k, 2], depth if kind == "depth" else rgb, clean, kind)
    # Real frames: fr1/rpy during fast rotation (blur, rolling shutter, edge outliers), fr3 deep depth.
    r1_rgb, r1_depth = real_frame(fr1, 300)
    _, r3_depth = real_frame(fr3, 8)
    axes[-1, 0].imshow(r1_rgb[::2, ::2])
    axes[-1, 0].set_title("real fr1/rpy colour (frame 300)", fontsize=8)
    show_depth(axes[-1, 1], r1_depth, "real fr1/rpy depth (frame 300)")
    show_depth(axes[-1, 2], r3_depth, "real fr3/long_office depth (frame 8)")
    for ax in axes.flat:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle("bivo synth sensor defects: clean | with the defect | change (depth colour scale 0.5-7 m)",
                 fontsize=11, y=0.998)
    fig.tight_layout(rect=(0, 0, 1, 0.99))
    buf = io.BytesIO()
    fig.savefig(buf, dpi=60, format="png")
    plt.close(fig)
    buf.seek(0)
    tmp = out + ".tmp.png"
    Image.open(buf).convert("RGB").quantize(256).save(tmp, optimize=True)
    os.replace(tmp, out)
