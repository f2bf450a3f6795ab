"""The hitting DS's speed: the strength factor v along the demonstrations (thesis fig. 2.3) and
the constant and sine speed modulators s(r) (eqs. 2.6a-d, fig. 2.4)."""
import matplotlib.pyplot as plt
import numpy as np

from .common import PlotError, read_csv, save


def plot_strength(strength_path, modulators_path, png_path, default_speed=None, title=None):
    s = read_csv(strength_path, ["demo", "distance", "speed", "strength"])
    m = read_csv(modulators_path, ["r"])
    const = [c for c in m.header if c.startswith("s_constant_")]
    if not const:
        raise PlotError(f"{modulators_path}: no s_constant_V columns")
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    ids, r = s.numbers("demo"), s.numbers("distance")
    speed, strength = s.numbers("speed"), s.numbers("strength")
    for k, demo in enumerate(np.unique(ids)):
        sel = ids == demo
        ax1.plot(r[sel], speed[sel], color="0.6", lw=0.8, label="demonstrated |ẋ|" if k == 0 else None)
    order = np.argsort(r)
    ax1.plot(r[order], strength[order], ".", color="tab:blue", ms=2, label="strength factor v(x - x*)")
    if default_speed is not None:
        ax1.axhline(default_speed, color="tab:red", ls="--", lw=1, label=f"v(x*) = {default_speed:.2f} m/s")
    ax1.set_xlabel("distance to the ball |x - x*| [m]")
    ax1.set_ylabel("speed [m/s]")
    ax1.invert_xaxis()
    ax1.set_title("strength factor along the demonstrations")
    ax1.legend(fontsize=8)

    rr = m.numbers("r")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, c in enumerate(const):
        v = c[len("s_constant_"):]
        sine = f"s_sine_{v}"
        ax2.plot(rr, m.numbers(c), "--", color=colors[k % len(colors)], label=f"constant, v^d = {v} m/s")
        if m.has(sine):
            ax2.plot(rr, m.numbers(sine), "-", color=colors[k % len(colors)], label=f"sine, v^d = {v} m/s")
    ax2.set_xlabel("distance to the ball r [m]")
    ax2.set_ylabel("speed modulator s(r) [-]")
    ax2.invert_xaxis()
    ax2.set_title("speed modulators (the club moves right to left, to the ball)")
    ax2.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    save(fig, png_path)
