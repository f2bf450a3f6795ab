"""Draws the demo putts over the four shipped fields (height colour map, tee, hole).

Usage: /usr/bin/python3 scripts/plot_demo.py OUT_DIR   (writes OUT_DIR/fields.png)

A thin wrapper: the figure is minigolf_plots.demo (scripts/plots/), also reachable as
'scripts/plots/plot.py demo OUT_DIR'.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "plots"))
from minigolf_plots.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main(["demo", *sys.argv[1:]]))
