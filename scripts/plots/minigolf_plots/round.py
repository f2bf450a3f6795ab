"""One hole of a round of minigolf: the field's height colour map with its obstacles, tee and hole,
and the ball path of every stroke of every round played (one colour per stroke number, rests as
dots, a ball that left the lane as a cross)."""
import matplotlib.pyplot as plt
import numpy as np

from .common import HOLE_DIAMETER, PlotError, read_csv, save
from .field import draw_field, figure_size, read_heights, read_obstacles

# Stroke 1, 2, ...: colours that stand out on the terrain colour map (no greens).
STROKE_COLOURS = ["#d62728", "#1f3fb4", "#ff7f0e", "#9467bd", "#e377c2", "#17becf", "#8c564b",
                  "#bcbd22", "#7f7f7f", "#000000"]


def stroke_colour(k):
    return STROKE_COLOURS[(int(k) - 1) % len(STROKE_COLOURS)]


def read_strokes(path):
    t = read_csv(path, ["round", "stroke", "rest_x", "rest_y", "sunk", "left_lane"])
    out = {name: t.numbers(name) for name in ("round", "stroke", "rest_x", "rest_y")}
    out["sunk"], out["left_lane"] = t.booleans("sunk"), t.booleans("left_lane")
    if np.any(out["stroke"] < 1):
        raise PlotError(f"{path}: column 'stroke' counts from 1")
    return out


def read_paths(path):
    """{(round, stroke): (x, y)} in file order."""
    t = read_csv(path, ["round", "stroke", "x", "y"])
    r, s, x, y = t.numbers("round"), t.numbers("stroke"), t.numbers("x"), t.numbers("y")
    paths = {}
    for key in dict.fromkeys(zip(r.tolist(), s.tolist())):
        rows = np.flatnonzero((r == key[0]) & (s == key[1]))
        paths[key] = (x[rows], y[rows])
    return paths


def plot_round(heights_path, strokes_path, paths_path, png_path, hole, hole_diameter=HOLE_DIAMETER,
               tee=None, obstacles_path=None, title=None):
    heights = read_heights(heights_path)
    strokes = read_strokes(strokes_path)
    paths = read_paths(paths_path) if paths_path else {}
    obstacles = read_obstacles(obstacles_path) if obstacles_path else ()
    width, height = figure_size(*heights[:2])
    fig, ax = plt.subplots(figsize=(width, height - 0.1))  # the legend below; less slack
    draw_field(fig, ax, heights, (), [hole], tee, hole_diameter, obstacles, legend=False)
    numbers = sorted(set(strokes["stroke"].astype(int).tolist()))
    rounds = len(set(strokes["round"].tolist()))
    for k in numbers:
        colour = stroke_colour(k)
        rows = np.flatnonzero(strokes["stroke"] == k)
        sunk = int(np.count_nonzero(strokes["sunk"][rows]))
        for i in rows:
            key = (strokes["round"][i], float(k))
            if key in paths:
                ax.plot(*paths[key], "-", color=colour, lw=1.3, alpha=0.75, zorder=5)
        ok = rows[~strokes["left_lane"][rows]]
        out = rows[strokes["left_lane"][rows]]
        ax.plot(strokes["rest_x"][ok], strokes["rest_y"][ok], "o", color=colour, mec="w",
                mew=0.6, ms=5, zorder=6)
        xs, ys = heights[0], heights[1]  # a ball off the lane: its cross on the lane's edge
        crosses, = ax.plot(np.clip(strokes["rest_x"][out], xs[0], xs[-1]),
                           np.clip(strokes["rest_y"][out], ys[0], ys[-1]), "x", color=colour,
                           ms=7, mew=2, zorder=6, clip_on=False)
        crosses.set_in_layout(False)
        ax.plot([], [], "-o", color=colour, mec="w", ms=5,
                label=f"stroke {k}: {len(rows)} played, {sunk} sunk")
    ax.plot([], [], "o", color="0.4", mec="w", ms=5, label="rest")
    if np.any(strokes["left_lane"]):
        ax.plot([], [], "x", color="0.4", ms=7, mew=2, label="left the lane (+1)")
    handles, labels = ax.get_legend_handles_labels()
    rows = -(-len(labels) // 4)
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=min(4, len(labels)),
               framealpha=0.9)
    ax.set_title(title or f"{rounds} round(s)")
    fig.tight_layout(rect=(0, (0.12 + 0.17 * rows) / (height - 0.1), 1, 1))
    save(fig, png_path)
