"""Success against training examples (or putts spent): median per method with a 10-90 % band."""
import os

import matplotlib.pyplot as plt
import numpy as np

from .common import PlotError, read_csv, save


def plot_learning_curve(csv_path, png_path, title=None, xlabel=None, percent=False):
    t = read_csv(csv_path, ["method", "x", "median", "p10", "p90"])
    methods = t.text("method")
    x = t.numbers("x")
    scale = 1.0 if percent else 100.0
    cols = {c: t.numbers(c) for c in ("median", "p10", "p90")}
    for c, v in cols.items():
        bad = np.isfinite(v) & ((v < 0) | (v * scale > 100.0 + 1e-9))
        if bad.any():
            unit = "percent in [0, 100]" if percent else "ratios in [0, 1] (or pass --percent)"
            raise PlotError(f"{csv_path}: column '{c}': {v[bad][0]:g} is out of range; "
                            f"values are success {unit}")
    if xlabel is None:
        labels = [s for s in t.text("label_x") if s] if t.has("label_x") else []
        xlabel = labels[0] if labels else "training examples"
    fig, ax = plt.subplots(figsize=(8, 5))
    for m in dict.fromkeys(methods):
        rows = np.array([k for k, name in enumerate(methods) if name == m])
        rows = rows[np.argsort(x[rows])]
        line, = ax.plot(x[rows], cols["median"][rows] * scale, "o-", lw=2, ms=4,
                        label=f"{m} (median)")
        ax.fill_between(x[rows], cols["p10"][rows] * scale, cols["p90"][rows] * scale,
                        color=line.get_color(), alpha=0.18)
    ax.fill_between([], [], [], color="grey", alpha=0.3, label="10-90 % band")
    ax.set_ylim(0, 100)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("success [%]")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title or f"Learning curve ({os.path.basename(csv_path)})")
    fig.tight_layout()
    save(fig, png_path)
