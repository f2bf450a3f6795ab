"""Draws the demo putts over the four shipped fields (height colour map, tee, hole)."""
import glob
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

out = sys.argv[1]
fields = ["flat", "multiple-hills", "regular-hill", "arctan"]
fig, axes = plt.subplots(len(fields), 1, figsize=(9, 3.2 * len(fields)))
for ax, name in zip(axes, fields):
    h = np.genfromtxt(os.path.join(out, f"heights_{name}.csv"), delimiter=",", names=True)
    xs, ys = np.unique(h["x"]), np.unique(h["y"])
    z = h["z"].reshape(len(ys), len(xs))
    im = ax.imshow(z, origin="lower", extent=[xs[0], xs[-1], ys[0], ys[-1]], cmap="terrain",
                   aspect="equal")
    fig.colorbar(im, ax=ax, label="height [m]", fraction=0.025)
    info = json.load(open(os.path.join(out, f"field_{name}.json")))
    ax.plot(*info["tee"], "k^", label="tee")
    for traj in sorted(glob.glob(os.path.join(out, f"putt_*_{name}.csv"))):
        t = np.genfromtxt(traj, delimiter=",", names=True)
        res = json.load(open(traj.replace(".csv", ".json")))
        ax.plot(t["x"], t["y"], "-", lw=1.5,
                label=f"angle {res['angle']:.2f} rad, {res['speed']:.1f} m/s: "
                      + ("sunk" if res["sunk"] else "missed"))
        hole = res["hole"]
    ax.add_patch(plt.Circle(hole, info["hole_diameter"] / 2, color="k", fill=False, lw=1.5))
    ax.set_title(f"{name}: {info['description']}", fontsize=9)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.legend(fontsize=7, loc="lower right")
fig.tight_layout()
fig.savefig(os.path.join(out, "fields.png"), dpi=110)
