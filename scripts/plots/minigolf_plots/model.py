"""A learner's prediction with a +-2 sigma envelope and its data points (thesis figs 6.3-6.9)."""
import matplotlib.pyplot as plt
import numpy as np

from .common import PlotError, on_grid, read_csv, regular_grid, save, unit

TRAIN = dict(color="tab:green", marker="o", label="training")
VALID = dict(color="tab:red", marker="^", label="validation")


def default_inputs(table):
    for k, name in enumerate(table.header):
        if name.endswith("_mean"):
            if k == 0:
                break
            return table.header[:k]
    raise PlotError(f"{table.path}: no input columns before a '*_mean' column; give --inputs")


def _points(path, inputs, output):
    if path is None:
        return None
    t = read_csv(path, list(inputs) + [output])
    return [t.numbers(c) for c in inputs], t.numbers(output)


def plot_model(pred_path, train_path, png_path, output, validation_path=None, inputs=None,
               title=None):
    p = read_csv(pred_path, [f"{output}_mean", f"{output}_std"])
    inputs = inputs or default_inputs(p)
    if len(inputs) not in (1, 2):
        raise PlotError(f"--inputs: {len(inputs)} columns ({','.join(inputs)}); 1 or 2 can be drawn")
    q = [p.numbers(c) for c in inputs]
    mean, std = p.numbers(f"{output}_mean"), p.numbers(f"{output}_std")
    train = _points(train_path, inputs, output)
    valid = _points(validation_path, inputs, output)
    ys, ylabel = unit(output)
    head = title or f"{output}: prediction mean ± 2σ"
    if len(inputs) == 1:
        fig = _one_input(q[0], mean * ys, std * ys, train, valid, inputs[0], ys, ylabel)
    else:
        fig = _two_inputs(p, q, mean * ys, std * ys, train, valid, inputs, ys, ylabel)
    fig.axes[0].set_title(head)
    fig.tight_layout()
    save(fig, png_path)


def _one_input(x, mean, std, train, valid, name, ys, ylabel):
    xs, xlabel = unit(name)
    order = np.argsort(x)
    x, mean, std = x[order] * xs, mean[order], std[order]
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.fill_between(x, mean - 2 * std, mean + 2 * std, color="tab:blue", alpha=0.2,
                    label="mean ± 2σ")
    ax.plot(x, mean, color="tab:blue", lw=2, label="prediction mean")
    for pts, style in ((train, TRAIN), (valid, VALID)):
        if pts is not None:
            ax.plot(pts[0][0] * xs, pts[1] * ys, ls="none", ms=6, mfc="none", mew=1.5, **style)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend()
    return fig


def _two_inputs(p, q, mean, std, train, valid, inputs, ys, ylabel):
    (sx, xlabel), (sy, ylab) = unit(inputs[0]), unit(inputs[1])
    gx, gy, iy, ix = regular_grid(p, inputs[0], inputs[1], q[0], q[1])
    X, Y = np.meshgrid(gx * sx, gy * sy)
    shape = X.shape
    M, S = on_grid(mean, iy, ix, shape), on_grid(std, iy, ix, shape)
    fig = plt.figure(figsize=(9, 7))
    # computed_zorder off: the data points stay visible in front of the surfaces
    ax = fig.add_subplot(projection="3d", computed_zorder=False)
    ax.plot_surface(X, Y, M, cmap="viridis", alpha=0.8, linewidth=0, antialiased=True, zorder=1)
    for sign in (-2, 2):
        ax.plot_surface(X, Y, M + sign * S, color="grey", alpha=0.2, linewidth=0, zorder=1)
    for pts, style in ((train, TRAIN), (valid, VALID)):
        if pts is not None:
            ax.scatter(pts[0][0] * sx, pts[0][1] * sy, pts[1] * ys, s=30, depthshade=False,
                       edgecolors="k", linewidths=0.5, zorder=5, **style)
    ax.plot([], [], color="grey", alpha=0.5, lw=6, label="mean ± 2σ")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylab)
    ax.set_zlabel(ylabel)
    ax.legend(loc="upper left")
    return fig
