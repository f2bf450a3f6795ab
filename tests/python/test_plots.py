"""Tests of scripts/plots (plot.py and the two wrapper scripts): each subcommand draws a PNG of
the expected shape from small synthetic CSVs; bad inputs give one 'plot: error:' line, exit 2.

Run: /usr/bin/python3 -m pytest -q tests/python/test_plots.py
"""
import contextlib
import csv
import io
import json
import math
import os
import stat
import subprocess
import sys

import numpy as np
import pytest

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PLOT = os.path.join(ROOT, "scripts", "plots", "plot.py")
PYTHON = sys.executable
sys.path.insert(0, os.path.dirname(PLOT))
from minigolf_plots.cli import main as plot_main  # noqa: E402


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)
    return str(path)


def run_program(*args, script=PLOT):
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([PYTHON, script, *map(str, args)], capture_output=True, text=True,
                          env=env, timeout=120)


def run(*args, script=PLOT):
    """plot.py's main() in this process (a fresh Python and matplotlib per call cost the suite
    minutes); other scripts, and plot.py as a program (test_plot_runs_as_a_program), run apart."""
    if script != PLOT:
        return run_program(*args, script=script)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = plot_main([str(a) for a in args])
        except SystemExit as e:  # argparse's usage errors
            code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
    plt.close("all")
    return subprocess.CompletedProcess(args, code, out.getvalue(), err.getvalue())


def assert_png(result, path, ratio, tol=0.06):
    """Exit 0, nothing on stderr, a non-empty PNG whose width/height is about ratio."""
    assert result.returncode == 0, result.stderr
    assert result.stderr == ""
    assert os.path.getsize(path) > 1000
    h, w = mpimg.imread(str(path)).shape[:2]
    assert w / h == pytest.approx(ratio, rel=tol)
    leftovers = [n for n in os.listdir(os.path.dirname(str(path))) if n.startswith(".plot-")]
    assert leftovers == []  # the atomic write removed its temp file


def assert_error(result, *words):
    """Exit 2, exactly one stderr line 'plot: error: ...' naming the given words, no traceback."""
    assert result.returncode == 2, (result.stdout, result.stderr)
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("plot: error:")
    for word in words:
        assert word in lines[0]


# ---- synthetic inputs -------------------------------------------------------------------------

@pytest.fixture
def sweep_csv(tmp_path):
    """A 5 angle x 7 speed grid in shuffled order, sunk as 0/1 and true/false, extra columns."""
    rng = np.random.default_rng(1)
    rows = []
    for a in np.linspace(-0.04, 0.04, 5):
        for s in np.linspace(1.0, 2.2, 7):
            sunk = abs(a) < 0.025 and 1.3 < s < 1.9
            approach = 0.0 if sunk else 0.01 + 2 * abs(a) + 0.2 * abs(s - 1.6)
            rows.append([a, s, ("true" if sunk else "false") if len(rows) % 2 else int(sunk),
                         approach, 1.9, 0.0, "sunk" if sunk else "at_rest", a * 0.9, s * 1.6, 1])
    rows = [rows[i] for i in rng.permutation(len(rows))]
    return write_csv(tmp_path / "sweep.csv", ["angle", "speed", "sunk", "closest_approach",
                                              "rest_x", "rest_y", "end", "launch_angle",
                                              "launch_speed", "full_putts"], rows)


@pytest.fixture
def model_1d(tmp_path):
    xs = np.linspace(-1.0, 1.0, 41)
    p = write_csv(tmp_path / "pred1.csv", ["xi_y", "angle_mean", "angle_std", "echo"],
                  [[x, 0.3 * x, 0.02 + 0.03 * x * x, 7] for x in xs])
    t = write_csv(tmp_path / "train1.csv", ["xi_x", "xi_y", "angle", "speed"],
                  [[2.0, x, 0.3 * x + 0.01, 1.5] for x in np.linspace(-0.9, 0.9, 8)])
    v = write_csv(tmp_path / "valid1.csv", ["xi_y", "angle"],
                  [[x, 0.3 * x - 0.01] for x in (-0.5, 0.1, 0.7)])
    return p, t, v


@pytest.fixture
def model_2d(tmp_path):
    rows = [[x, y, 0.4 * y / x, 0.02 + 0.01 * x, 1.0 + 0.3 * x, 0.05]
            for y in np.linspace(-1.0, 1.0, 5) for x in np.linspace(0.5, 3.0, 6)]
    p = write_csv(tmp_path / "pred2.csv",
                  ["xi_x", "xi_y", "angle_mean", "angle_std", "speed_mean", "speed_std"], rows)
    t = write_csv(tmp_path / "train2.csv", ["xi_x", "xi_y", "angle", "speed"],
                  [[x, y, 0.4 * y / x, 1.0 + 0.3 * x] for x, y in
                   [(0.7, 0.2), (1.5, -0.6), (2.2, 0.8), (2.8, -0.1), (1.1, 0.5)]])
    v = write_csv(tmp_path / "valid2.csv", ["xi_x", "xi_y", "angle", "speed"],
                  [[1.8, 0.3, 0.07, 1.55], [2.5, -0.7, -0.11, 1.75]])
    return p, t, v


@pytest.fixture
def heights_csv(tmp_path):
    """A 31 x 13 grid over [-0.3, 2.7] x [-0.6, 0.6] m (the project writes y-major rows)."""
    rows = [[x, y, 0.03 * math.atan(3 * (x - 1.2)) * math.atan(4 * y)]
            for y in np.linspace(-0.6, 0.6, 13) for x in np.linspace(-0.3, 2.7, 31)]
    return write_csv(tmp_path / "heights.csv", ["x", "y", "z"], rows)


def trajectory(path, angle=0.1):
    t = np.linspace(0, 2, 50)
    d = 1.8 * (1 - (1 - t / 2) ** 2)
    return write_csv(path, ["t", "x", "y", "z", "vx", "vy", "vz"],
                     [[ti, di * math.cos(angle), di * math.sin(angle), 0, 0, 0, 0]
                      for ti, di in zip(t, d)])


@pytest.fixture
def obstacles_csv(tmp_path):
    """A block (0.3 x 0.5 m at (1, 0)) and a wall, their footprints' corners counter-clockwise."""
    return write_csv(tmp_path / "obstacles.csv", ["obstacle", "block", "x", "y"],
                     [[0, 1, 1.15, 0.25], [0, 1, 0.85, 0.25], [0, 1, 0.85, -0.25],
                      [0, 1, 1.15, -0.25], [1, 0, 1.5, 0.44], [1, 0, 0.5, 0.44],
                      [1, 0, 0.5, 0.40], [1, 0, 1.5, 0.40]])


@pytest.fixture
def round_csvs(tmp_path):
    """Three rounds of one hole: short, then holed; the third round's first ball left the lane."""
    strokes, paths = [], []
    for r in range(3):
        rest = (1.5, 0.5 + 0.02 * r) if r < 2 else (2.75, 0.3)
        strokes.append([r, 1, 0, 0, 0.3, 2.0, *rest, 0, int(r == 2)])
        strokes.append([r, 2, *rest, -0.3, 1.5, 2.0, 0.0, 1, 0])
        for t in np.linspace(0, 1, 20):
            paths.append([r, 1, rest[0] * t, rest[1] * t])
            paths.append([r, 2, rest[0] + (2.0 - rest[0]) * t, rest[1] * (1 - t)])
    s = write_csv(tmp_path / "strokes.csv", ["round", "stroke", "ball_x", "ball_y", "angle",
                                             "speed", "rest_x", "rest_y", "sunk", "left_lane"],
                  strokes)
    p = write_csv(tmp_path / "paths.csv", ["round", "stroke", "x", "y"], paths)
    return s, p


@pytest.fixture
def curve_csv(tmp_path):
    rows = []
    for m, rate in (("gpr", 0.3), ("gmr", 0.15)):
        for x in (5, 10, 20, 40, 80):
            med = 1 - math.exp(-rate * x / 5)
            rows.append([m, x, med, max(med - 0.15, 0), min(med + 0.1, 1), "putts spent"])
    return write_csv(tmp_path / "curve.csv", ["method", "x", "median", "p10", "p90", "label_x"],
                     rows)


@pytest.fixture
def success_csv(tmp_path):
    rows = [["flat", "gpr", 50, 45, 0.9, 0.79, 0.96, 1.0, 0.93],
            ["flat", "gmr", 50, 40, 0.8, 0.67, 0.89, 1.0, ""],
            ["arctan", "gpr", 50, 30, 0.6, 0.46, 0.72, 0.9, 0.55],
            ["arctan", "gmr", 50, 25, 0.5, 0.36, 0.64, 0.9, ""]]
    return write_csv(tmp_path / "success.csv", ["field", "method", "situations", "sunk",
                                                "success_ratio", "ci_lo", "ci_hi",
                                                "oracle_ceiling", "thesis_ratio"], rows)


# ---- each subcommand draws ---------------------------------------------------------------------

def test_sweep(tmp_path, sweep_csv):
    out = tmp_path / "sweep.png"
    assert_png(run("sweep", sweep_csv, out, "--title", "flat field"), out, 8 / 5.5)


def test_model_one_input(tmp_path, model_1d):
    p, t, v = model_1d
    out = tmp_path / "m1.png"
    r = run("model", "--predictions", p, "--train", t, "--validation", v, "--output", "angle", out)
    assert_png(r, out, 8 / 5)


def test_model_two_inputs(tmp_path, model_2d):
    p, t, v = model_2d
    for name in ("angle", "speed"):
        out = tmp_path / f"m2_{name}.png"
        r = run("model", "--predictions", p, "--train", t, "--validation", v, "--output", name,
                "--inputs", "xi_x,xi_y", "--title", f"GPR {name}", out)
        assert_png(r, out, 9 / 7)


def test_model_default_inputs_without_validation(tmp_path, model_2d):
    p, t, _ = model_2d
    out = tmp_path / "m2.png"
    assert_png(run("model", "--predictions", p, "--train", t, "--output", "speed", out), out, 9 / 7)


def test_dataset(tmp_path):
    header = ["hole_x", "hole_y", "xi_x", "xi_y", "angle", "speed"]
    rows = [[hx, hy, hx, hy, math.atan2(hy, hx), 1 + 0.4 * hx]
            for hx in (1.0, 1.6, 2.2) for hy in (-0.4, 0.0, 0.4)]
    d = write_csv(tmp_path / "data.csv", header, rows)
    v = write_csv(tmp_path / "valid.csv", header, [[1.3, 0.2, 1.3, 0.2, 0.15, 1.5]])
    out = tmp_path / "data.png"
    assert_png(run("dataset", d, out, "--validation", v), out, 8 / 6)
    only_holes = write_csv(tmp_path / "holes.csv", ["hole_x", "hole_y"], [[1, 0], [2, 0.3]])
    out2 = tmp_path / "holes.png"
    assert_png(run("dataset", only_holes, out2), out2, 8 / 6)


def test_field(tmp_path, heights_csv):
    t1, t2 = trajectory(tmp_path / "t1.csv", 0.1), trajectory(tmp_path / "t2.csv", -0.15)
    out = tmp_path / "field.png"
    r = run("field", heights_csv, out, "--trajectory", t1, t2, "--hole", "1.8,0.2", "2.1,-0.3",
            "--tee", "0,0", "--title", "arctan")
    ratio = 10 / (0.85 * 10 * 1.2 / 3.0 + 1.3)  # field.figure_size of a 3.0 x 1.2 m lane
    assert_png(r, out, ratio)
    out2 = tmp_path / "field2.png"
    assert_png(run("field", heights_csv, out2, "--hole=-0.2,0.1"), out2, ratio)


def test_field_with_obstacles(tmp_path, heights_csv, obstacles_csv):
    out = tmp_path / "field.png"
    r = run("field", heights_csv, out, "--obstacles", obstacles_csv, "--hole=2.0,0",
            "--hole-diameter", "0.108", "--tee=0,0")
    assert_png(r, out, 10 / (0.85 * 10 * 1.2 / 3.0 + 1.3))


def test_round(tmp_path, heights_csv, obstacles_csv, round_csvs):
    strokes, paths = round_csvs
    out = tmp_path / "round.png"
    r = run("round", heights_csv, strokes, out, "--paths", paths, "--hole=2.0,0", "--tee=0,0",
            "--obstacles", obstacles_csv, "--title", "hole 1: flat, par 2")
    ratio = 10 / (0.85 * 10 * 1.2 / 3.0 + 1.3 - 0.1)  # field.figure_size, 0.1 in less: round.py
    assert_png(r, out, ratio)
    out2 = tmp_path / "round2.png"  # without paths (whiffs only) and obstacles
    assert_png(run("round", heights_csv, strokes, out2, "--hole=2.0,0"), out2, ratio)


def test_learning_curve(tmp_path, curve_csv):
    out = tmp_path / "curve.png"
    assert_png(run("learning-curve", curve_csv, out, "--title", "T"), out, 8 / 5)
    out2 = tmp_path / "curve2.png"
    assert_png(run("learning-curve", curve_csv, out2, "--xlabel", "examples"), out2, 8 / 5)


def test_success(tmp_path, success_csv):
    out = tmp_path / "success.png"
    assert_png(run("success", success_csv, out), out, 7 / 5)


def test_launch_error_wrapper(tmp_path):
    header = ["angle_deg", "hit", "seed", "struck", "ball_x", "ball_y", "club_angle",
              "club_speed", "launch_angle", "launch_speed", "launch_error_deg",
              "club_speed_error", "launch_club_ratio", "faulted"]
    rows = []
    for a in (-10, 0, 10):
        for h in range(4):
            struck = not (a == 0 and h == 3)
            v = (lambda x: x if struck else "nan")
            rows.append([a, h, h + 1, int(struck), 0, 0, v(math.radians(a) + 0.001 * h), v(1.6),
                         v(math.radians(a)), v(2.6), v(0.1 * h - 0.15), v(0.01), v(1.6), 0])
    d = write_csv(tmp_path / "launch_error.csv", header, rows)
    out = tmp_path / "launch_error.png"
    script = os.path.join(ROOT, "scripts", "plot_launch_error.py")
    assert_png(run(d, out, script=script), out, 11 / 4.2)
    assert_png(run("launch-error", d, out), out, 11 / 4.2)


def test_demo_wrapper(tmp_path, heights_csv):
    fields = ["flat", "multiple-hills", "regular-hill", "arctan"]
    for k, name in enumerate(fields):
        os.link(heights_csv, tmp_path / f"heights_{name}.csv")
        (tmp_path / f"field_{name}.json").write_text(json.dumps(
            {"tee": [0, 0], "hole": [2.0, 0.0], "hole_diameter": 0.108, "description": name}))
        trajectory(tmp_path / f"putt_{k}_{name}.csv", 0.05 * k)
        (tmp_path / f"putt_{k}_{name}.json").write_text(json.dumps(
            {"angle": 0.05 * k, "speed": 1.6, "sunk": k % 2 == 0, "hole": [2.0, 0.0]}))
    script = os.path.join(ROOT, "scripts", "plot_demo.py")
    assert_png(run(tmp_path, script=script), tmp_path / "fields.png", 9 / (3.2 * 4))
    os.remove(tmp_path / "field_arctan.json")
    assert_error(run(tmp_path, script=script), "field_arctan.json")
    # A key given twice (json keeps the last) is refused.
    (tmp_path / "field_arctan.json").write_text(
        '{"tee": [0, 0], "hole": [2.0, 0.0], "hole": [9.0, 0.0], "hole_diameter": 0.108}')
    assert_error(run(tmp_path, script=script), "field_arctan.json", "duplicate key 'hole'")


# ---- bad inputs: one line, exit 2, no PNG -------------------------------------------------------

def corrupt(path, column, value, row=1):
    """Rewrites one cell (data row `row`) of a CSV written by write_csv."""
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    lines[row][lines[0].index(column)] = value
    bad = str(path).replace(".csv", f"_bad_{column}.csv")
    with open(bad, "w", newline="") as f:
        csv.writer(f).writerows(lines)
    return bad


def drop_column(path, column):
    with open(path, newline="") as f:
        lines = list(csv.reader(f))
    k = lines[0].index(column)
    out = str(path).replace(".csv", f"_no_{column}.csv")
    with open(out, "w", newline="") as f:
        csv.writer(f).writerows([row[:k] + row[k + 1:] for row in lines])
    return out


def assert_bad(tmp_path, make_args, good_csv, column, text="abc"):
    """Missing file, missing column, a non-numeric cell and an empty file all fail cleanly."""
    out = tmp_path / "bad.png"
    missing = str(tmp_path / "nope.csv")
    assert_error(run(*make_args(missing, out)), missing, "no such file")
    no_col = drop_column(good_csv, column)
    assert_error(run(*make_args(no_col, out)), no_col, f"'{column}'")
    bad_cell = corrupt(good_csv, column, text)
    assert_error(run(*make_args(bad_cell, out)), bad_cell, f"'{column}'", text)
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    assert_error(run(*make_args(empty, out)), str(empty), "empty")
    assert not out.exists()


def test_sweep_errors(tmp_path, sweep_csv):
    args = lambda f, out: ("sweep", f, out)  # noqa: E731
    assert_bad(tmp_path, args, sweep_csv, "closest_approach")
    assert_bad(tmp_path, args, sweep_csv, "speed")
    assert_error(run("sweep", corrupt(sweep_csv, "sunk", "maybe"), tmp_path / "x.png"),
                 "'sunk'", "maybe")
    with open(sweep_csv) as f:
        lines = f.readlines()
    hole = tmp_path / "holey.csv"
    hole.write_text("".join(lines[:-1]))
    assert_error(run("sweep", hole, tmp_path / "x.png"), "full grid")


def test_model_errors(tmp_path, model_1d):
    p, t, v = model_1d
    assert_bad(tmp_path, lambda f, out: ("model", "--predictions", f, "--train", t, "--output",
                                         "angle", out), p, "angle_mean")
    assert_bad(tmp_path, lambda f, out: ("model", "--predictions", p, "--train", t,
                                         "--validation", f, "--output", "angle", out), v, "angle")
    assert_error(run("model", "--predictions", p, "--train", t, "--output", "speed",
                     tmp_path / "x.png"), "'speed_mean'")
    no_output = drop_column(t, "angle")
    assert_error(run("model", "--predictions", p, "--train", no_output, "--output", "angle",
                     tmp_path / "x.png"), no_output, "'angle'")
    assert_error(run("model", "--predictions", p, "--train", t, "--output", "angle",
                     "--inputs", "xi_x", tmp_path / "x.png"), p, "'xi_x'")

def test_dataset_errors(tmp_path):
    d = write_csv(tmp_path / "data.csv", ["hole_x", "hole_y", "angle"], [[1, 0, 0.1], [2, 1, 0.2]])
    assert_bad(tmp_path, lambda f, out: ("dataset", f, out), d, "hole_y")


def test_field_errors(tmp_path, heights_csv):
    t1 = trajectory(tmp_path / "t1.csv")
    assert_bad(tmp_path, lambda f, out: ("field", f, out), heights_csv, "z")
    assert_bad(tmp_path, lambda f, out: ("field", heights_csv, out, "--trajectory", f), t1, "x")
    assert_error(run("field", heights_csv, tmp_path / "x.png", "--hole", "1.0"), "--hole", "X,Y")


def test_round_errors(tmp_path, heights_csv, obstacles_csv, round_csvs):
    strokes, paths = round_csvs
    hole = "--hole=2.0,0"
    assert_bad(tmp_path, lambda f, out: ("round", heights_csv, f, out, hole), strokes, "rest_x")
    assert_bad(tmp_path, lambda f, out: ("round", heights_csv, strokes, out, hole, "--paths", f),
               paths, "x")
    assert_bad(tmp_path, lambda f, out: ("round", heights_csv, strokes, out, hole,
                                         "--obstacles", f), obstacles_csv, "y")
    out = tmp_path / "x.png"
    assert_error(run("round", heights_csv, strokes, out), "--hole")
    assert_error(run("round", heights_csv, corrupt(strokes, "left_lane", "maybe"), out, hole),
                 "'left_lane'", "maybe")
    assert_error(run("round", heights_csv, corrupt(strokes, "stroke", "0"), out, hole),
                 "'stroke'")
    assert_error(run("round", heights_csv, strokes, out, hole, "--hole-diameter", "0"),
                 "--hole-diameter")
    two = write_csv(tmp_path / "two.csv", ["obstacle", "block", "x", "y"], [[0, 1, 0, 0],
                                                                           [0, 1, 1, 1]])
    assert_error(run("field", heights_csv, out, "--obstacles", two), "corners")
    assert not out.exists()


def test_learning_curve_errors(tmp_path, curve_csv):
    assert_bad(tmp_path, lambda f, out: ("learning-curve", f, out), curve_csv, "median")
    assert_error(run("learning-curve", corrupt(curve_csv, "p90", "70"), tmp_path / "x.png"),
                 "'p90'", "--percent")


def test_success_errors(tmp_path, success_csv):
    assert_bad(tmp_path, lambda f, out: ("success", f, out), success_csv, "ci_hi")


def test_launch_error_errors(tmp_path):
    d = write_csv(tmp_path / "le.csv", ["angle_deg", "hit", "struck", "club_angle",
                                        "launch_error_deg"], [[0, 0, 1, 0.0, 0.1]])
    assert_bad(tmp_path, lambda f, out: ("launch-error", f, out), d, "launch_error_deg")


def test_usage_errors_are_one_line(tmp_path, sweep_csv):
    assert_error(run("nonsense"), "nonsense")
    assert_error(run("sweep", sweep_csv), "sweep", "OUT.png")
    assert_error(run("model", tmp_path / "x.png"), "--predictions")
    short = tmp_path / "short.csv"
    short.write_text("angle,speed,sunk,closest_approach\n0,1,1\n")
    assert_error(run("sweep", short, tmp_path / "x.png"), "line 2", "3 cells")
    header_only = tmp_path / "header.csv"
    header_only.write_text("angle,speed,sunk,closest_approach\n")
    assert_error(run("sweep", header_only, tmp_path / "x.png"), "no data rows")
    assert_error(run("sweep", sweep_csv, tmp_path / "no" / "dir" / "x.png"), "does not exist")


# ---- ds and strength (minigolf plot ds | strength export these files) ----

def ds_inputs(tmp_path):
    rows = []
    for demo in range(3):
        for i in range(20):
            s = i / 19
            rows.append([demo, 0.01 * i, -0.3 * (1 - s), 0.02 * demo * (1 - s), 0.02 + 0.1 * (1 - s) ** 2,
                         1.5 * s, 0.3 * (1 - s)])
    demos = write_csv(tmp_path / "demos.csv", ["demo", "t", "x", "y", "z", "speed", "distance"], rows)
    gmm = write_csv(tmp_path / "gmm.csv", ["k", "prior", "mx", "my", "mz", "cxx", "cxy", "cxz", "cyy", "cyz", "czz"],
                    [[0, 0.5, -0.2, 0.0, 0.08, 0.004, 0.0, 0.001, 0.002, 0.0, 0.002],
                     [1, 0.5, -0.05, 0.0, 0.03, 0.001, 0.0, 0.0, 0.001, 0.0, 0.0005]])
    grid = []
    for a in np.linspace(-0.35, 0.05, 8):
        for b in np.linspace(0.0, 0.15, 6):
            grid.append([a, b, -a + 0.3, -(b - 0.02), math.hypot(-a + 0.3, b - 0.02)])
    field = write_csv(tmp_path / "field.csv", ["a", "b", "u", "v", "speed"], grid)
    return demos, gmm, field


def assert_wide_png(result, path):
    assert result.returncode == 0, result.stderr
    assert os.path.getsize(path) > 1000
    h, w = mpimg.imread(str(path)).shape[:2]
    assert w > h


def test_ds_draws_demonstrations_ellipses_and_streamlines(tmp_path):
    demos, gmm, field = ds_inputs(tmp_path)
    out = tmp_path / "ds.png"
    assert_wide_png(run("ds", demos, gmm, field, out, "--target=0,0,0.02135"), out)
    out2 = tmp_path / "ds_xy.png"
    assert_wide_png(run("ds", demos, gmm, field, out2, "--plane", "xy"), out2)


def test_ds_rejects_bad_inputs(tmp_path):
    demos, gmm, field = ds_inputs(tmp_path)
    out = tmp_path / "ds.png"
    assert_error(run("ds", demos, gmm, tmp_path / "missing.csv", out), "missing.csv")
    bad = write_csv(tmp_path / "bad_gmm.csv", ["k", "prior", "mx"], [[0, 1, 0]])
    assert_error(run("ds", demos, bad, field, out), "bad_gmm.csv", "my")
    neg = write_csv(tmp_path / "neg.csv", ["k", "prior", "mx", "my", "mz", "cxx", "cxy", "cxz", "cyy", "cyz", "czz"],
                    [[0, 1, 0, 0, 0, -1, 0, 0, -1, 0, -1]])
    assert_error(run("ds", demos, neg, field, out), "positive")
    assert_error(run("ds", demos, gmm, field, out, "--plane", "yz"), "--plane")
    assert_error(run("ds", demos, gmm, field, out, "--target", "1,2"), "--target")
    assert not out.exists()


def test_strength_draws_both_panels_and_rejects_bad_inputs(tmp_path):
    rows = [[d, 0.3 * (1 - s), 1.5 * s, max(0.15, 1.5 * s)] for d in range(2) for s in np.linspace(0, 1, 15)]
    strength = write_csv(tmp_path / "strength.csv", ["demo", "distance", "speed", "strength"], rows)
    r = np.linspace(0, 0.36, 20)
    mods = write_csv(tmp_path / "mods.csv", ["r", "s_constant_1", "s_sine_1"],
                     [[x, 0.66, 0.66 + 0.34 * math.sin(math.pi * min(x, 0.3) / 0.6) ** 2] for x in r])
    out = tmp_path / "strength.png"
    assert_wide_png(run("strength", strength, mods, out, "--default-speed", "1.52"), out)
    nomod = write_csv(tmp_path / "nomod.csv", ["r", "other"], [[0, 1]])
    assert_error(run("strength", strength, nomod, tmp_path / "x.png"), "s_constant_")
    text = write_csv(tmp_path / "text.csv", ["demo", "distance", "speed", "strength"], [[0, "abc", 1, 1]])
    assert_error(run("strength", text, mods, tmp_path / "x.png"), "text.csv", "distance")


def test_figures_never_replace_fifos_links_or_devices(tmp_path, sweep_csv):
    """The Python figure path keeps the atomic-file policy of the C++ writers."""
    fifo = tmp_path / "f.png"
    os.mkfifo(fifo)
    kept = tmp_path / "kept.txt"
    kept.write_text("kept\n")
    link = tmp_path / "l.png"
    link.symlink_to(kept)
    for target in (fifo, link, tmp_path):
        assert_error(run("sweep", sweep_csv, target), "not a regular file" if target != tmp_path else "")
    assert_error(run("sweep", sweep_csv, tmp_path / "missing" / "x.png"), "does not exist")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode) and os.path.islink(link)
    assert kept.read_text() == "kept\n"
    assert not [p for p in os.listdir(tmp_path) if p.startswith(".plot-")]


def test_fuzzed_sweep_csvs_are_drawn_or_refused_in_one_line(tmp_path, sweep_csv):
    """A fuzz of the figure path's CSV reader: mutated files give a PNG (exit 0) or one
    'plot: error:' line (exit 2), never a traceback. Fixed seed: the same cases every run."""
    rng = np.random.default_rng(22)
    text = open(sweep_csv).read()
    tokens = ["", "nan", "inf", "-1e308", "1e309", "x", ",", "\n", "\"", "0x10", "\x00", "true"]
    for k in range(16):
        chars = list(text)
        for _ in range(int(rng.integers(1, 6))):
            i = int(rng.integers(0, len(chars)))
            if rng.random() < 0.5:
                chars[i] = tokens[int(rng.integers(0, len(tokens)))]
            else:
                del chars[i:i + int(rng.integers(1, 40))]
        case = tmp_path / f"case{k}.csv"
        case.write_text("".join(chars))
        out = tmp_path / f"case{k}.png"
        r = run("sweep", case, out)
        assert r.returncode in (0, 2), (k, r.stderr)
        assert "Traceback" not in r.stderr, (k, r.stderr)
        if r.returncode == 2:
            assert len(r.stderr.splitlines()) == 1 and r.stderr.startswith("plot: error:"), (k, r.stderr)
            assert not out.exists()
        else:
            assert out.stat().st_size > 0


def test_plot_runs_as_a_program(tmp_path, sweep_csv):
    """plot.py itself: a figure, and a bad input's one line and exit 2, from a separate Python."""
    out = tmp_path / "sweep.png"
    assert_png(run_program("sweep", sweep_csv, out), out, 8 / 5.5)
    assert_error(run_program("sweep", tmp_path / "missing.csv", out), "missing.csv")
