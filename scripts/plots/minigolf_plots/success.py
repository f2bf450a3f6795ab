"""Grouped bars: success ratio per field and method, 95 % whiskers, the oracle ceiling and,
when given, the thesis value as a hollow bar."""
import os

import matplotlib.lines as mlines
import matplotlib.patches as mpatches
import matplotlib.pyplot as plt
import numpy as np

from .common import read_csv, save


def plot_success(csv_path, png_path, title=None):
    t = read_csv(csv_path, ["field", "method", "success_ratio", "ci_lo", "ci_hi",
                            "oracle_ceiling"])
    field, method = t.text("field"), t.text("method")
    ratio, lo, hi = (t.numbers(c) * 100 for c in ("success_ratio", "ci_lo", "ci_hi"))
    ceiling = t.numbers("oracle_ceiling", blank_ok=True) * 100
    thesis = t.numbers("thesis_ratio", blank_ok=True) * 100 if t.has("thesis_ratio") else None
    counts = None
    if t.has("sunk") and t.has("situations"):
        counts = list(zip(t.numbers("sunk"), t.numbers("situations")))
    fields, methods = list(dict.fromkeys(field)), list(dict.fromkeys(method))
    width = 0.8 / len(methods)
    fig, ax = plt.subplots(figsize=(max(7, 1.6 * len(fields) * max(1, len(methods) / 2)), 5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    seen = set()  # legend labels already given

    def once(label):
        if label in seen:
            return None
        seen.add(label)
        return label

    for k in range(len(field)):
        f, m = fields.index(field[k]), methods.index(method[k])
        xc = f - 0.4 + width * (m + 0.5)
        c = colours[m % len(colours)]
        ax.bar(xc, ratio[k], width * 0.9, color=c, alpha=0.85,
               label=once(method[k]))
        err = [[max(ratio[k] - lo[k], 0)], [max(hi[k] - ratio[k], 0)]]
        ax.errorbar(xc, ratio[k], yerr=err, color="k", capsize=3, lw=1)
        if thesis is not None and np.isfinite(thesis[k]):
            ax.bar(xc, thesis[k], width * 0.9, fill=False, edgecolor="k", lw=1.5, ls="--",
                   zorder=3)
        if np.isfinite(ceiling[k]):
            ax.plot(xc, ceiling[k], "_", color="k", ms=max(8, 60 * width), mew=2.5,
                    zorder=4)
        if counts is not None:
            ax.text(xc, 1.5, f"{counts[k][0]:.0f}/{counts[k][1]:.0f}", ha="center",
                    va="bottom", fontsize=7, rotation=90, color="w")
    ax.set_xticks(range(len(fields)), fields)
    ax.set_ylim(0, 105)
    ax.set_ylabel("success ratio [%] (whiskers: 95 % interval)")
    ax.set_xlabel("field")
    ax.grid(axis="y", alpha=0.3)
    handles = ax.get_legend_handles_labels()[0]  # the methods, in file order
    if thesis is not None and np.isfinite(thesis).any():
        handles.append(mpatches.Patch(fill=False, edgecolor="k", ls="--", label="thesis (hollow)"))
    if np.isfinite(ceiling).any():
        handles.append(mlines.Line2D([], [], color="k", marker="_", ms=14, mew=2.5, ls="none",
                                     label="oracle ceiling"))
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    ax.set_title(title or f"Success per field and method ({os.path.basename(csv_path)})")
    fig.tight_layout()
    save(fig, png_path)
