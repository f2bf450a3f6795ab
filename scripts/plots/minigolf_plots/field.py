"""A field's height colour map with ball trajectories, holes, the tee and the obstacles (thesis
fig. 5.4b)."""
import os

import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.axes_grid1 import make_axes_locatable

from .common import HOLE_DIAMETER, PlotError, edges, on_grid, read_csv, regular_grid, save


def read_heights(path):
    t = read_csv(path, ["x", "y", "z"])
    x, y, z = t.numbers("x"), t.numbers("y"), t.numbers("z")
    xs, ys, iy, ix = regular_grid(t, "x", "y", x, y)
    return xs, ys, on_grid(z, iy, ix, (len(ys), len(xs)))


def read_trajectory(path):
    t = read_csv(path, ["t", "x", "y"])
    return t.numbers("x"), t.numbers("y")


def read_obstacles(path):
    """[(is_block, corners (4 x 2))] from obstacle,block,x,y (the footprint's corners in order)."""
    t = read_csv(path, ["obstacle", "block", "x", "y"])
    ids, block, x, y = t.numbers("obstacle"), t.booleans("block"), t.numbers("x"), t.numbers("y")
    out = []
    for k in dict.fromkeys(ids.tolist()):  # in file order
        rows = np.flatnonzero(ids == k)
        if len(rows) < 3:
            raise PlotError(f"{path}: obstacle {k:g} has {len(rows)} corners, expected at least 3")
        out.append((bool(block[rows[0]]), np.column_stack([x[rows], y[rows]])))
    return out


WALL_COLOUR, BLOCK_COLOUR = "#5a4632", "#8c6d4f"


def draw_obstacles(ax, obstacles):
    """Walls and blocks as filled polygons of their footprints, with one legend entry each kind."""
    kinds = set()
    for is_block, corners in obstacles:
        colour = BLOCK_COLOUR if is_block else WALL_COLOUR
        ax.add_patch(plt.Polygon(corners, closed=True, facecolor=colour, edgecolor="k", lw=0.6,
                                 zorder=3))
        kinds.add(is_block)
    for is_block in sorted(kinds):  # legend proxies
        ax.fill([], [], facecolor=BLOCK_COLOUR if is_block else WALL_COLOUR, edgecolor="k",
                lw=0.6, label="block" if is_block else "wall")


def draw_field(fig, ax, heights, trajectories=(), holes=(), tee=None,
               hole_diameter=HOLE_DIAMETER, obstacles=(), legend=True):
    """heights: (xs, ys, z grid); trajectories: [(x, y, label)]; holes: [(x, y)];
    obstacles: [(is_block, corners)] (read_obstacles)."""
    xs, ys, z = heights
    zmm = z * 1000.0
    lo, hi = np.nanmin(zmm), np.nanmax(zmm)
    if not hi - lo > 1.0:  # a (nearly) level field: a +-1 mm range instead of a noise colour scale
        lo, hi = (lo + hi) / 2 - 1.0, (lo + hi) / 2 + 1.0
    mesh = ax.pcolormesh(edges(xs), edges(ys), zmm, cmap="terrain", shading="flat", vmin=lo,
                         vmax=hi)
    cax = make_axes_locatable(ax).append_axes("right", size="2%", pad=0.1)  # as tall as the lane
    fig.colorbar(mesh, cax=cax, label="height [mm]")
    draw_obstacles(ax, obstacles)
    for x, y, label in trajectories:
        ax.plot(x, y, "-", lw=1.6, label=label)
        ax.plot(x[-1:], y[-1:], "o", color=ax.lines[-1].get_color(), ms=4)
    for h in holes:
        ax.add_patch(plt.Circle(h, hole_diameter / 2, facecolor="k", edgecolor="w", lw=0.8,
                                zorder=4))
    if holes:  # legend proxy: a round marker, not the patch's rectangle
        ax.plot([], [], "o", color="k", mec="w", ms=8,
                label=f"hole (⌀ {hole_diameter * 1000:.0f} mm)")
    if tee is not None:
        ax.plot(*tee, "^", color="w", mec="k", ms=9, zorder=5, label="tee")
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(ys[0], ys[-1])
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if legend and ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7, loc="lower right", framealpha=0.85)


def figure_size(xs, ys, width=10.0):
    """[in] for one field: the lane at equal aspect, room for labels, title and colour bar."""
    aspect = (ys[-1] - ys[0]) / max(xs[-1] - xs[0], 1e-9)
    return width, max(2.5, min(0.85 * width * aspect + 1.3, 12.0))


def plot_field(heights_path, png_path, trajectories=(), holes=(), tee=None, title=None,
               obstacles_path=None, hole_diameter=HOLE_DIAMETER):
    heights = read_heights(heights_path)
    trajs = [(*read_trajectory(p), os.path.basename(p)) for p in trajectories]
    obstacles = read_obstacles(obstacles_path) if obstacles_path else ()
    fig, ax = plt.subplots(figsize=figure_size(*heights[:2]))
    draw_field(fig, ax, heights, trajs, holes, tee, hole_diameter, obstacles)
    ax.set_title(title or f"Field {os.path.basename(heights_path)}")
    fig.tight_layout()
    save(fig, png_path)
