"""The hitting DS in a plane through the ball: demonstrations, the SEDS GMM's position ellipses
(2 sigma) and streamlines of the learned velocity field (thesis fig. 2.2)."""
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import Ellipse

from .common import PlotError, read_csv, regular_grid, on_grid, save

PLANES = {"xz": (0, 2, "x [m]", "z [m]"), "xy": (0, 1, "x [m]", "y [m]")}


def _ellipse(mean2, cov2, **style):
    values, vectors = np.linalg.eigh(cov2)
    if not np.all(np.isfinite(values)) or values.min() < 0:
        raise PlotError("GMM: a covariance is not positive semi-definite")
    angle = np.degrees(np.arctan2(vectors[1, 1], vectors[0, 1]))
    w, h = 2 * 2 * np.sqrt(values[1]), 2 * 2 * np.sqrt(values[0])  # full axes of the 2 sigma ellipse
    return Ellipse(mean2, w, h, angle=angle, **style)


def plot_ds(demos_path, gmm_path, field_path, png_path, plane="xz", target=None, title=None):
    if plane not in PLANES:
        raise PlotError(f"--plane '{plane}': expected xz or xy")
    ia, ib, alabel, blabel = PLANES[plane]
    axes = "xyz"
    demos = read_csv(demos_path, ["demo", "x", "y", "z"])
    gmm = read_csv(gmm_path, ["prior", "mx", "my", "mz", "cxx", "cxy", "cxz", "cyy", "cyz", "czz"])
    field = read_csv(field_path, ["a", "b", "u", "v", "speed"])

    fig, ax = plt.subplots(figsize=(9, 5))
    a, b = field.numbers("a"), field.numbers("b")
    xs, ys, iy, ix = regular_grid(field, "a", "b", a, b)
    shape = (len(ys), len(xs))
    u, v = on_grid(field.numbers("u"), iy, ix, shape), on_grid(field.numbers("v"), iy, ix, shape)
    speed = on_grid(field.numbers("speed"), iy, ix, shape)
    if not (np.all(np.isfinite(u)) and np.all(np.isfinite(v))):
        raise PlotError(f"{field_path}: non-finite velocities")
    strm = ax.streamplot(xs, ys, u, v, color=speed, cmap="viridis", density=1.3, linewidth=0.8,
                         arrowsize=0.8)
    fig.colorbar(strm.lines, ax=ax, label="DS speed in the plane [m/s]", shrink=0.8)

    ids = demos.numbers("demo")
    pos = [demos.numbers(c) for c in "xyz"]
    for k, demo in enumerate(np.unique(ids)):
        sel = ids == demo
        ax.plot(pos[ia][sel], pos[ib][sel], color="0.25", lw=1.0, alpha=0.8,
                label="demonstrations" if k == 0 else None)
        ax.plot(pos[ia][sel][0], pos[ib][sel][0], "o", color="0.25", ms=3)

    means = np.column_stack([gmm.numbers(c) for c in ("mx", "my", "mz")])
    full = {}
    for name in ("cxx", "cxy", "cxz", "cyy", "cyz", "czz"):
        full[name] = gmm.numbers(name)
    key = {(0, 0): "cxx", (0, 1): "cxy", (0, 2): "cxz", (1, 1): "cyy", (1, 2): "cyz", (2, 2): "czz"}
    pick = lambda i, j: full[key[(min(i, j), max(i, j))]]  # noqa: E731
    for k in range(len(gmm)):
        cov2 = np.array([[pick(ia, ia)[k], pick(ia, ib)[k]], [pick(ib, ia)[k], pick(ib, ib)[k]]])
        ax.add_patch(_ellipse((means[k, ia], means[k, ib]), cov2, fill=False, lw=1.8,
                              edgecolor="tab:red", label="GMM, 2σ" if k == 0 else None))
        ax.plot(means[k, ia], means[k, ib], "+", color="tab:red", ms=8)
    if target is not None:
        ax.plot(target[ia], target[ib], "*", color="gold", mec="k", ms=16, label="x* (ball)", zorder=5)
    ax.set_xlabel(alabel)
    ax.set_ylabel(blabel)
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(ys[0], ys[-1])
    ax.set_aspect("equal")
    ax.legend(loc="upper left", fontsize=8)
    other = ({0, 1, 2} - {ia, ib}).pop()
    ax.set_title(title or f"hitting DS: demonstrations, GMM and streamlines "
                          f"({plane} plane, {axes[other]} = x*_{axes[other]})", fontsize=10)
    fig.tight_layout()
    save(fig, png_path)
