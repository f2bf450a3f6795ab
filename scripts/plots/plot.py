#!/usr/bin/python3
"""Figures for the minigolf experiments' report. Run with /usr/bin/python3 (numpy, matplotlib).

  plot.py sweep SWEEP.csv OUT.png [--title T]
  plot.py model OUT.png --predictions P.csv --train T.csv [--validation V.csv] --output NAME
          [--inputs a,b] [--title T]
  plot.py dataset DATA.csv OUT.png [--validation V.csv] [--title T]
  plot.py field HEIGHTS.csv OUT.png [--trajectory T.csv ...] [--hole X,Y ...] [--tee X,Y]
          [--hole-diameter D] [--obstacles O.csv] [--title T]
  plot.py round HEIGHTS.csv STROKES.csv OUT.png --hole=X,Y [--paths PATHS.csv]
          [--hole-diameter D] [--tee X,Y] [--obstacles O.csv] [--title T]
  plot.py learning-curve CURVE.csv OUT.png [--xlabel TEXT] [--percent] [--title T]
  plot.py success TABLE.csv OUT.png [--title T]
  plot.py launch-error IN.csv OUT.png
  plot.py ds DEMOS.csv GMM.csv FIELD.csv OUT.png [--plane xz|xy] [--target X,Y,Z] [--title T]
  plot.py strength STRENGTH.csv MODULATORS.csv OUT.png [--default-speed V] [--title T]
  plot.py demo DIR

Exit 0 and one PNG (written atomically); on a bad input one 'plot: error: ...' line, exit 2.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from minigolf_plots.cli import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
