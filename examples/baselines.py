#!/usr/bin/python3
"""Baselines beside self-teaching: CMA-ES and ARS over a linear policy (minigolf.baselines) and
`minigolf curves --learner self-teach`, on the same test situations, against the putts spent.

    PYTHONPATH=build/python /usr/bin/python3 examples/baselines.py --field flat --out out/baselines-flat
    PYTHONPATH=build/python /usr/bin/python3 examples/baselines.py --field arctan \\
        --checkpoints 10,25,50,100,150,300,600 --out out/baselines-arctan

Writes into --out: curves.csv (every learner, the curves format: learner,run,putts,sunk,situations,
success), summary.csv (method,x,median,p10,p90: the success ratio's median and 10 / 90 % quantiles
over the runs, linear interpolation, as experiments::summarize), summary.md (the table) and
learning_curves.png (scripts/plots/plot.py learning-curve). --mode arm (default) counts full-system
putts, as `curves` does; --mode ball lets the baselines learn with ball-only putts (fast; self-teach
still spends full-system putts: summary.md says so). The CLI binary: $MINIGOLF_BINARY, else
build/src/cli/minigolf. Progress on stderr when it is a terminal. Bad arguments: one line, exit 2.
"""
import argparse
import os
import pathlib
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
try:
    import minigolf  # noqa: F401
except ImportError:  # run from the repository without PYTHONPATH
    sys.path.insert(0, str(ROOT / "build" / "python"))
    import minigolf  # noqa: F401
from minigolf import baselines

PLOT_SCRIPT = ROOT / "scripts" / "plots" / "plot.py"
METHODS = ("self-teach",) + baselines.LEARNERS


class UsageError(Exception):
    pass


class Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse prints the usage too)
        raise UsageError(message)


def parse_checkpoints(text):
    try:
        cps = [int(c) for c in text.split(",")]
    except ValueError:
        raise UsageError(f"--checkpoints: expected increasing putt counts like 10,25,50, got '{text}'") from None
    try:
        return baselines._check_checkpoints(cps)
    except ValueError as e:
        raise UsageError(f"--checkpoints: {str(e).removeprefix('baselines: ')}") from None


def parse_args(argv):
    p = Parser(description=__doc__.splitlines()[0])
    p.add_argument("--field", default="flat", help="shipped field name or field file (default flat)")
    p.add_argument("--mode", default="arm", help="arm: full-system putts, as curves (default); ball: ball-only putts")
    p.add_argument("--checkpoints", default="10,25,50,100,150", help="putt counts, increasing (default: curves')")
    p.add_argument("--seeds", default="10", help="runs per learner (default 10)")
    p.add_argument("--situations", default="100", help="test situations per checkpoint (default 100)")
    p.add_argument("--test-seed", default="7", help="seed of the test situations (default 7)")
    p.add_argument("--seed", default="1", help="seed of the runs (default 1)")
    p.add_argument("--methods", default=",".join(METHODS), help=f"comma-separated, of {','.join(METHODS)}")
    p.add_argument("--threads", default="0", help="runs in parallel (0: every core; results do not depend on it)")
    p.add_argument("--out", help="output folder (default out/baselines-FIELD)")
    a = p.parse_args(argv)

    def integer(name, text, lo, hi):
        try:
            v = int(text)
        except ValueError:
            v = None
        if v is None or not lo <= v <= hi:
            raise UsageError(f"--{name}: expected an integer in [{lo}, {hi}], got '{text}'")
        return v

    a.seeds = integer("seeds", a.seeds, 1, 1000)
    a.situations = integer("situations", a.situations, 1, 100000)
    a.test_seed = integer("test-seed", a.test_seed, 0, 2**64 - 1)
    a.seed = integer("seed", a.seed, 0, 2**64 - 1)
    a.threads = integer("threads", a.threads, 0, 256)
    a.checkpoints = parse_checkpoints(a.checkpoints)
    if a.mode not in baselines.ENV_IDS:
        raise UsageError(f"--mode: expected arm or ball, got '{a.mode}'")
    a.methods = [m.strip() for m in a.methods.split(",") if m.strip()]
    bad = [m for m in a.methods if m not in METHODS]
    if bad or not a.methods or len(set(a.methods)) != len(a.methods):
        raise UsageError(f"--methods: expected distinct names among {', '.join(METHODS)}, got '{','.join(a.methods)}'")
    try:
        minigolf.System(field=a.field)
    except (ValueError, OSError) as e:
        raise UsageError(f"--field: {e}") from None
    a.binary = os.environ.get("MINIGOLF_BINARY") or str(ROOT / "build" / "src" / "cli" / "minigolf")
    if "self-teach" in a.methods and not os.access(a.binary, os.X_OK):
        raise UsageError(f"the minigolf binary '{a.binary}' is not there: build it or set MINIGOLF_BINARY")
    if not PLOT_SCRIPT.is_file():
        raise UsageError(f"the plot script {PLOT_SCRIPT} is not there")
    a.out = pathlib.Path(a.out or f"out/baselines-{pathlib.Path(a.field).stem}")
    if a.out.exists() and not a.out.is_dir():
        raise UsageError(f"--out: '{a.out}' is not a folder")
    return a


def write_atomic(path, text):
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def read_curves(path):
    lines = path.read_text().splitlines()
    header = lines[0].split(",")
    if tuple(header) != baselines.CSV_COLUMNS:
        raise RuntimeError(f"{path}: unexpected header {lines[0]}")
    rows = []
    for line in lines[1:]:
        v = dict(zip(header, line.split(",")))
        rows.append(dict(learner=v["learner"], run=int(v["run"]), putts=int(v["putts"]), sunk=int(v["sunk"]),
                         situations=int(v["situations"]), success=float(v["success"])))
    return rows


def progress_printer(method, tty):
    start = time.monotonic()

    def show(done, total):
        if tty:
            end = "\n" if done == total else ""
            print(f"\r{method}: {done}/{total} runs ({time.monotonic() - start:.0f} s)", end=end, file=sys.stderr,
                  flush=True)
    return show


def run_self_teach(a, tty):
    """`minigolf curves --learner self-teach` with the same field, checkpoints, runs and test situations."""
    with tempfile.TemporaryDirectory(dir=a.out) as tmp:
        csv = pathlib.Path(tmp) / "self-teach.csv"
        cmd = [a.binary, "curves", "--field", a.field, "--learner", "self-teach",
               "--checkpoints", ",".join(map(str, a.checkpoints)), "--seeds", str(a.seeds),
               "--situations", str(a.situations), "--test-seed", str(a.test_seed), "--seed", str(a.seed),
               "--threads", str(a.threads), "-o", str(csv)]
        r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=None if tty else subprocess.PIPE, text=True)
        if r.returncode != 0:
            lines = ((r.stderr or "") + r.stdout).strip().splitlines()
            raise RuntimeError(f"{shlex.join(cmd)} failed (exit {r.returncode}): {lines[-1] if lines else ''}")
        return read_curves(csv), shlex.join(cmd[:-1] + ["CURVES.csv"])


def summary_markdown(a, summary, walls, argv):
    methods = list(dict.fromkeys(s["method"] for s in summary))
    cell = {(s["method"], s["x"]): s for s in summary}
    unit = "full-system putts" if a.mode == "arm" else "the baselines' ball-only putts, self-teach's full-system putts"
    lines = [f"# Baselines beside self-teaching: {minigolf.System(field=a.field).field.name}", "",
             f"Success [%] on {a.situations} test situations (test seed {a.test_seed}) after the learning putts spent "
             f"({unit}): median over {a.seeds} runs (10-90 %). Seed {a.seed}.", "",
             "| putts | " + " | ".join(methods) + " |", "|---:|" + "---|" * len(methods)]
    for x in a.checkpoints:
        row = []
        for m in methods:
            s = cell.get((m, x))
            row.append("" if s is None else f"{100 * s['median']:.1f} ({100 * s['p10']:.1f}-{100 * s['p90']:.1f})")
        lines.append(f"| {x} | " + " | ".join(row) + " |")
    lines += ["", "Wall time: " + ", ".join(f"{m} {walls[m]:.0f} s" for m in methods if m in walls)
              + f" (threads {a.threads or os.cpu_count()}).", "",
              "Command: `" + shlex.join(["examples/baselines.py"] + list(argv)) + "`", ""]
    if "self-teach" in walls:
        lines += ["Self-teach: `" + walls["self-teach-cmd"] + "`", ""]
    lines += ["Baselines: a linear policy clip(W z + b) of the observation z scaled to [-1, 1] (minigolf.baselines); "
              "CMA-ES (Hansen's defaults, sigma0 {sigma0}) and ARS V1-t ({directions} directions, top {top}, "
              "step {step}, noise {noise}) from theta = 0, each candidate on {episodes} shared hole(s) per "
              "generation, the shaped reward.".format(**{**baselines.DEFAULTS["cma-es"], **baselines.DEFAULTS["ars"]}),
              ""]
    return "\n".join(lines)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    try:
        a = parse_args(argv)
    except UsageError as e:
        print(f"baselines: error: {e}", file=sys.stderr)
        return 2
    tty = sys.stderr.isatty()
    a.out.mkdir(parents=True, exist_ok=True)
    rows, walls = [], {}
    try:
        for m in a.methods:
            t = time.monotonic()
            if m == "self-teach":
                got, cmd = run_self_teach(a, tty)
                walls["self-teach-cmd"] = cmd
            else:
                got = baselines.learning_curves(m, a.field, a.mode, a.checkpoints, a.seeds, a.situations, a.test_seed,
                                                a.seed, threads=a.threads, progress=progress_printer(m, tty))
            walls[m] = time.monotonic() - t
            rows += got
        summary = baselines.summarize(rows)
        write_atomic(a.out / "curves.csv", baselines.curves_csv(rows))
        write_atomic(a.out / "summary.csv", "method,x,median,p10,p90\n" + "".join(
            f"{s['method']},{s['x']},{baselines.format_number(s['median'])},{baselines.format_number(s['p10'])},"
            f"{baselines.format_number(s['p90'])}\n" for s in summary))
        md = summary_markdown(a, summary, walls, argv)
        write_atomic(a.out / "summary.md", md)
        xlabel = "full-system putts spent" if a.mode == "arm" else "putts spent (baselines: ball only)"
        title = f"{minigolf.System(field=a.field).field.name}: baselines beside self-teaching"
        png = a.out / "learning_curves.png"
        r = subprocess.run(["/usr/bin/python3", str(PLOT_SCRIPT), "learning-curve", str(a.out / "summary.csv"),
                            str(png), "--xlabel", xlabel, "--title", title],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                           env={**os.environ, "MPLBACKEND": "Agg"})
        if r.returncode != 0:
            lines = r.stdout.strip().splitlines()
            raise RuntimeError(f"plot.py learning-curve failed (exit {r.returncode}): {lines[-1] if lines else ''}")
    except (RuntimeError, OSError) as e:
        print(f"baselines: error: {e}", file=sys.stderr)
        return 1
    print(md.split("\n\nWall time")[0].split("\n", 2)[2])
    print(f"\nwrote {a.out}/curves.csv, summary.csv, summary.md, learning_curves.png")
    return 0


if __name__ == "__main__":
    sys.exit(main())
