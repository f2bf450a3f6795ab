"""Draws the launch-error study like thesis figure 6.1 (minigolf study launch-error --plot).

Usage: /usr/bin/python3 scripts/plot_launch_error.py launch_error.csv launch_error.png

Left: the launch angle error of every attempt, one series per commanded angle, the mean (bias)
dashed and +-1 std shaded. Right: launch error against approach error (club direction at impact
minus the command), the correlation the thesis points out in 6.1.1.
"""
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

csv_path, png_path = sys.argv[1], sys.argv[2]
d = np.genfromtxt(csv_path, delimiter=",", names=True)
d = np.atleast_1d(d)
struck = d[d["struck"] == 1]
angles = list(dict.fromkeys(d["angle_deg"].tolist()))  # file order

fig, (ax, ax2) = plt.subplots(1, 2, figsize=(11, 4.2), gridspec_kw={"width_ratios": [3, 2]})
colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
for k, a in enumerate(angles):
    rows = struck[struck["angle_deg"] == a]
    if len(rows) == 0:
        continue
    c = colors[k % len(colors)]
    err = rows["launch_error_deg"]
    mean, std = float(np.mean(err)), float(np.std(err, ddof=1)) if len(err) > 1 else 0.0
    attempt = rows["hit"] + 1
    ax.plot(attempt, err, "o-", color=c, lw=1, ms=5,
            label=f"{a:g} deg: bias {mean:+.3f}, std {std:.3f} deg")
    ax.axhline(mean, color=c, ls="--", lw=1)
    ax.axhspan(mean - std, mean + std, color=c, alpha=0.12)
    approach = (rows["club_angle"] - math.radians(a)) * 180.0 / math.pi
    ax2.plot(approach, err, "o", color=c, ms=5, label=f"{a:g} deg")
ax.axhline(0.0, color="k", lw=0.6)
ax.set_xlabel("attempt")
ax.set_ylabel("launch angle error [deg]")
ax.set_title("Launch angle error per attempt (flat field, simulated WAM)")
ax.legend(fontsize=8)
ax.grid(alpha=0.3)
ax2.set_xlabel("approach error: club direction - command [deg]")
ax2.set_ylabel("launch angle error [deg]")
ax2.set_title("Launch vs approach error")
ax2.grid(alpha=0.3)
ax2.legend(fontsize=8)
fig.tight_layout()
fig.savefig(png_path, dpi=110)
