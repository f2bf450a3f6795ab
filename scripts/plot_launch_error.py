"""Draws the launch-error study like thesis figure 6.1 (minigolf study launch-error --plot).

Usage: /usr/bin/python3 scripts/plot_launch_error.py launch_error.csv launch_error.png

A thin wrapper: the figure is minigolf_plots.launch_error (scripts/plots/), also reachable as
'scripts/plots/plot.py launch-error IN.csv OUT.png'.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "plots"))
from minigolf_plots.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(["launch-error", *sys.argv[1:]]))
