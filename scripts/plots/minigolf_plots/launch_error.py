"""The launch-error study like thesis figure 6.1 (minigolf study launch-error --plot).

Left: the launch angle error of every attempt, one series per commanded angle, the mean (bias)
dashed and +-1 std shaded. Right: launch error against approach error (club direction at impact
minus the command), the correlation the thesis points out in 6.1.1."""
import math

import matplotlib.pyplot as plt
import numpy as np

from .common import read_csv, save


def plot_launch_error(csv_path, png_path):
    t = read_csv(csv_path, ["angle_deg", "hit", "struck", "club_angle", "launch_error_deg"])
    angle_deg, hit, struck = t.numbers("angle_deg"), t.numbers("hit"), t.numbers("struck") == 1
    club_angle, error = t.numbers("club_angle"), t.numbers("launch_error_deg")
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [3, 2]})
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, a in enumerate(dict.fromkeys(angle_deg.tolist())):  # file order
        rows = struck & (angle_deg == a)
        if not rows.any():
            continue
        c = colours[k % len(colours)]
        err = error[rows]
        mean = float(np.mean(err))
        std = float(np.std(err, ddof=1)) if len(err) > 1 else 0.0
        ax.plot(hit[rows] + 1, err, "o-", color=c, lw=1, ms=5,
                label=f"{a:g} deg: bias {mean:+.3f}, std {std:.3f} deg")
        ax.axhline(mean, color=c, ls="--", lw=1)
        ax.axhspan(mean - std, mean + std, color=c, alpha=0.12)
        approach = np.degrees(club_angle[rows] - math.radians(a))
        ax2.plot(approach, err, "o", color=c, ms=5, label=f"{a:g} deg")
    ax.axhline(0.0, color="k", lw=0.6)
    ax.set_xlabel("attempt")
    ax.set_ylabel("launch angle error [deg]")
    ax.set_title("Launch angle error per attempt (flat field, simulated WAM)")
    ax.grid(alpha=0.3)
    ax2.set_xlabel("approach error: club direction - command [deg]")
    ax2.set_ylabel("launch angle error [deg]")
    ax2.set_title("Launch vs approach error")
    ax2.grid(alpha=0.3)
    for a in (ax, ax2):
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=8)
    fig.tight_layout()
    save(fig, png_path, dpi=110)
