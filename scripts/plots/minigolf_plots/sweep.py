"""Sinking window: closest approach over (speed, angle), sunk cells hatched."""
import os

import matplotlib.colors as mcolors
import matplotlib.patches as mpatches
import matplotlib.pyplot as plt
import numpy as np

from .common import edges, on_grid, read_csv, regular_grid, save


def plot_sweep(csv_path, png_path, title=None):
    t = read_csv(csv_path, ["angle", "speed", "sunk", "closest_approach"])
    angle_deg = np.degrees(t.numbers("angle"))
    speed = t.numbers("speed")
    sunk = t.booleans("sunk")
    approach_mm = t.numbers("closest_approach") * 1000.0
    speeds, angles, iy, ix = regular_grid(t, "speed", "angle", speed, angle_deg)
    shape = (len(angles), len(speeds))
    grid = on_grid(approach_mm, iy, ix, shape)
    sunk_grid = on_grid(sunk.astype(float), iy, ix, shape) > 0.5

    # Log colour scale from 1 mm (a ball over the hole) to the largest miss; nan cells stay blank.
    finite = grid[np.isfinite(grid)]
    top = max(float(finite.max()) if finite.size else 10.0, 10.0)
    norm = mcolors.LogNorm(vmin=1.0, vmax=top, clip=True)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    xe, ye = edges(speeds), edges(angles)
    mesh = ax.pcolormesh(xe, ye, np.clip(grid, 1.0, None), cmap="viridis_r", norm=norm,
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="closest approach ball - hole centre [mm] (log, min 1 mm)",
                 extend="min")
    for r, c in zip(*np.nonzero(sunk_grid)):
        ax.add_patch(mpatches.Rectangle((xe[c], ye[r]), xe[c + 1] - xe[c], ye[r + 1] - ye[r],
                                        fill=False, hatch="xx", edgecolor="red", lw=1.2))
    ax.legend(handles=[mpatches.Patch(fill=False, hatch="xx", edgecolor="red", label="sunk")],
              loc="upper right", framealpha=0.9)
    ax.set_xlabel("speed [m/s]")
    ax.set_ylabel("angle [deg]")
    k, n = int(sunk.sum()), len(sunk)
    head = title or f"Sinking window ({os.path.basename(csv_path)})"
    ax.set_title(f"{head}\nsunk {k} / {n} ({len(angles)} angles x {len(speeds)} speeds)")
    fig.tight_layout()
    save(fig, png_path)
