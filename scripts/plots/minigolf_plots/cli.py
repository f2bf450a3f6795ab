"""Command line: plot.py SUBCOMMAND ...; input problems give one 'plot: error:' line, exit 2."""
import argparse
import sys

from .common import HOLE_DIAMETER, PlotError, parse_point


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line instead of argparse's usage block
        name = self.prog.split()[-1]
        raise PlotError(message if name == "plot" else f"{name}: {message}")


def build_parser():
    p = Parser(prog="plot", description="Figures for the minigolf experiments (PNG, Agg).")
    sub = p.add_subparsers(dest="command", required=True, metavar="SUBCOMMAND")

    s = sub.add_parser("sweep", help="sinking window heat map over (speed, angle)")
    s.add_argument("sweep_csv", metavar="SWEEP.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--title")

    s = sub.add_parser("model", help="a learner's prediction, +-2 std and its data points")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--predictions", required=True, metavar="P.csv")
    s.add_argument("--train", required=True, metavar="T.csv")
    s.add_argument("--validation", metavar="V.csv")
    s.add_argument("--output", required=True, metavar="NAME")
    s.add_argument("--inputs", metavar="a,b", help="default: the columns before the first *_mean")
    s.add_argument("--title")

    s = sub.add_parser("dataset", help="the situations of a data set in the plane")
    s.add_argument("data_csv", metavar="DATA.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--validation", metavar="V.csv")
    s.add_argument("--title")

    s = sub.add_parser("field", help="field heights with trajectories, holes and the tee")
    s.add_argument("heights_csv", metavar="HEIGHTS.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--trajectory", action="extend", nargs="+", default=[], metavar="T.csv")
    s.add_argument("--hole", action="extend", nargs="+", default=[], metavar="X,Y",
                   help="metres; write --hole=-0.3,0.2 when X is negative")
    s.add_argument("--tee", metavar="X,Y")
    s.add_argument("--hole-diameter", type=float, default=HOLE_DIAMETER, metavar="D",
                   help="[m] the cup drawn to scale")
    s.add_argument("--obstacles", metavar="O.csv", help="obstacle,block,x,y footprint corners")
    s.add_argument("--title")

    s = sub.add_parser("round", help="a round's hole: every stroke's ball path over the field")
    s.add_argument("heights_csv", metavar="HEIGHTS.csv")
    s.add_argument("strokes_csv", metavar="STROKES.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--paths", metavar="PATHS.csv", help="round,stroke,x,y: the ball paths")
    s.add_argument("--hole", required=True, metavar="X,Y", help="metres; write --hole=-0.3,0.2")
    s.add_argument("--hole-diameter", type=float, default=HOLE_DIAMETER, metavar="D")
    s.add_argument("--tee", metavar="X,Y")
    s.add_argument("--obstacles", metavar="O.csv", help="obstacle,block,x,y footprint corners")
    s.add_argument("--title")

    s = sub.add_parser("learning-curve", help="success against training examples or putts")
    s.add_argument("curve_csv", metavar="CURVE.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--xlabel", help="x axis label (default: column label_x, else 'training examples')")
    s.add_argument("--percent", action="store_true", help="median/p10/p90 are in %% (default: ratios)")
    s.add_argument("--title")

    s = sub.add_parser("success", help="success ratio per field and method with 95 %% intervals")
    s.add_argument("table_csv", metavar="TABLE.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--title")

    s = sub.add_parser("launch-error", help="the launch-error study (thesis fig. 6.1)")
    s.add_argument("csv", metavar="IN.csv")
    s.add_argument("out", metavar="OUT.png")

    s = sub.add_parser("ds", help="the hitting DS: demonstrations, GMM ellipses, streamlines")
    s.add_argument("demos_csv", metavar="DEMOS.csv")
    s.add_argument("gmm_csv", metavar="GMM.csv")
    s.add_argument("field_csv", metavar="FIELD.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--plane", default="xz", help="xz | xy")
    s.add_argument("--target", metavar="X,Y,Z", help="x*, the ball [m]")
    s.add_argument("--title")

    s = sub.add_parser("strength", help="the strength factor and the speed modulators")
    s.add_argument("strength_csv", metavar="STRENGTH.csv")
    s.add_argument("modulators_csv", metavar="MODULATORS.csv")
    s.add_argument("out", metavar="OUT.png")
    s.add_argument("--default-speed", type=float, metavar="V", help="v(x*) [m/s]")
    s.add_argument("--title")

    s = sub.add_parser("demo", help="the main job's demo putts over the four fields -> DIR/fields.png")
    s.add_argument("dir", metavar="DIR")
    return p


def positive_diameter(d):
    if not (0.0 < d < 10.0):
        raise PlotError(f"--hole-diameter: {d} m: expected (0, 10)")
    return d


def run(a):
    from . import (plot_dataset, plot_demo, plot_ds, plot_field, plot_launch_error,
                   plot_learning_curve, plot_model, plot_round, plot_strength, plot_success,
                   plot_sweep)
    if a.command == "sweep":
        plot_sweep(a.sweep_csv, a.out, a.title)
    elif a.command == "model":
        inputs = [c.strip() for c in a.inputs.split(",") if c.strip()] if a.inputs else None
        plot_model(a.predictions, a.train, a.out, a.output, a.validation, inputs, a.title)
    elif a.command == "dataset":
        plot_dataset(a.data_csv, a.out, a.validation, a.title)
    elif a.command == "field":
        holes = [parse_point(h, "--hole") for h in a.hole]
        tee = parse_point(a.tee, "--tee") if a.tee else None
        plot_field(a.heights_csv, a.out, a.trajectory, holes, tee, a.title, a.obstacles,
                   positive_diameter(a.hole_diameter))
    elif a.command == "round":
        tee = parse_point(a.tee, "--tee") if a.tee else None
        plot_round(a.heights_csv, a.strokes_csv, a.paths, a.out,
                   parse_point(a.hole, "--hole"), positive_diameter(a.hole_diameter), tee,
                   a.obstacles, a.title)
    elif a.command == "learning-curve":
        plot_learning_curve(a.curve_csv, a.out, a.title, a.xlabel, a.percent)
    elif a.command == "success":
        plot_success(a.table_csv, a.out, a.title)
    elif a.command == "launch-error":
        plot_launch_error(a.csv, a.out)
    elif a.command == "ds":
        target = None
        if a.target:
            try:
                target = tuple(float(v) for v in a.target.split(","))
            except ValueError:
                target = ()
            if len(target) != 3:
                raise PlotError(f"--target: '{a.target}' is not X,Y,Z in metres")
        plot_ds(a.demos_csv, a.gmm_csv, a.field_csv, a.out, a.plane, target, a.title)
    elif a.command == "strength":
        plot_strength(a.strength_csv, a.modulators_csv, a.out, a.default_speed, a.title)
    elif a.command == "demo":
        plot_demo(a.dir)


def main(argv=None):
    try:
        run(build_parser().parse_args(argv))
    except PlotError as e:
        print(f"plot: error: {e}", file=sys.stderr)
        return 2
    except Exception as e:  # a bug, not an input problem: still one line, no traceback
        text = " ".join(str(e).split())
        print(f"plot: internal error: {type(e).__name__}: {text}", file=sys.stderr)
        return 1
    return 0
