"""The situations of a data set in the plane (thesis fig. 6.10): holes, the balls (hole - xi),
the hitting angle as an arrow and the speed as the marker size."""
import os

import matplotlib.pyplot as plt
import numpy as np

from .common import read_csv, save


def _load(path):
    t = read_csv(path, ["hole_x", "hole_y"])
    d = {c: t.numbers(c) for c in ("hole_x", "hole_y")}
    for c in ("xi_x", "xi_y", "angle", "speed"):
        if t.has(c):
            d[c] = t.numbers(c)
    return d


def plot_dataset(csv_path, png_path, validation_path=None, title=None):
    sets = [("training", "tab:green", _load(csv_path))]
    if validation_path:
        sets.append(("validation", "tab:red", _load(validation_path)))
    speeds = np.concatenate([d["speed"] for _, _, d in sets if "speed" in d] or [np.array([])])
    speeds = speeds[np.isfinite(speeds)]
    lo, hi = (float(speeds.min()), float(speeds.max())) if speeds.size else (0.0, 0.0)

    def size(v):  # marker area [pt^2] from the speed
        return 20 + 130 * (v - lo) / (hi - lo) if hi > lo else np.full_like(v, 60.0)

    fig, ax = plt.subplots(figsize=(8, 6))
    span = max(np.ptp(np.concatenate([d["hole_x"] for _, _, d in sets])),
               np.ptp(np.concatenate([d["hole_y"] for _, _, d in sets])), 0.1)
    for label, colour, d in sets:
        s = size(d["speed"]) if "speed" in d else 40
        ax.scatter(d["hole_x"], d["hole_y"], s=s, c=colour, alpha=0.75, edgecolors="k",
                   linewidths=0.5, label=f"{label} holes ({len(d['hole_x'])})", zorder=3)
        if "xi_x" in d and "xi_y" in d:
            ax.plot(d["hole_x"] - d["xi_x"], d["hole_y"] - d["xi_y"], "+", color=colour, ms=7,
                    alpha=0.6, label=f"{label} balls (hole - ξ)")
        if "angle" in d:
            a = d["angle"]
            ax.quiver(d["hole_x"], d["hole_y"], np.cos(a), np.sin(a), color=colour,
                      angles="xy", scale_units="xy", scale=1.0 / (0.08 * span), width=0.003,
                      zorder=4)
    if "angle" in sets[0][2]:
        ax.plot([], [], color="k", lw=1, label="arrow: hitting angle")
    if hi > lo:
        for v in (lo, hi):
            ax.scatter([], [], s=size(np.array([v])), c="w", edgecolors="k",
                       label=f"speed {v:.2f} m/s")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    ax.set_title(title or f"Situations of {os.path.basename(csv_path)}"
                 + (f" and {os.path.basename(validation_path)}" if validation_path else ""))
    fig.tight_layout()
    save(fig, png_path)
