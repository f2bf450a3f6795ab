#!/usr/bin/python3
"""Does a policy trained fast play the arm? (docs/python.md, "Measured": transfer to Putt-v0)

    PYTHONPATH=build/python /usr/bin/python3 bench/python/transfer.py [--field flat] [--putts 3000] [--runs 3]

ARS (minigolf.baselines, its defaults) learns a linear policy for `--putts` putts in
PuttFast-v0 twice: with club actions (club_action=True: the action is the arm's (hitting angle,
club speed), launched through the robot's launch skill) and with plain launch actions (the
registered id). Each learned policy then plays the `--test` test holes of `minigolf curves`
(test seed 7) in PuttFast-v0 (its own env) and in Putt-v0 (the WAM hits the ball). Prints the
holes sunk per run as a Markdown table (and writes it with --out).
"""
import argparse
import os
import time

import numpy as np

import minigolf
from minigolf import baselines as B


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--field", default="flat")
    p.add_argument("--putts", type=int, default=3000)
    p.add_argument("--runs", type=int, default=3)
    p.add_argument("--test", type=int, default=50)
    p.add_argument("--out", default="")
    a = p.parse_args()
    common = dict(field=a.field, observation="varying")
    arm = minigolf.make("minigolf/Putt-v0", **common)
    holes = B.evaluation_holes(arm, a.test, 7)
    rows = []
    start = time.perf_counter()
    for label, kwargs in (("club actions (club_action=True)", dict(club_action=True)),
                          ("launch actions (the registered id)", dict())):
        fast = minigolf.make("minigolf/PuttFast-v0", **common, **kwargs)
        for run in range(a.runs):
            rng = B.run_seed(1, run)
            theta = B.learn("ars", fast, [a.putts], rng)[0].theta
            policy = B.LinearPolicy.for_env(fast)
            rows.append((label, run, B.evaluate(fast, policy, theta, holes), B.evaluate(arm, policy, theta, holes)))
    seconds = time.perf_counter() - start
    lines = [f"ARS, {a.putts} putts in PuttFast-v0 on {a.field}, then {a.test} test holes (test seed 7) in each env; "
             f"{a.runs} runs, {seconds:.0f} s (load average {os.getloadavg()[0]:.1f}):", "",
             "| trained with | run | sunk in PuttFast-v0 | sunk in Putt-v0 (the arm) |", "|---|---:|---:|---:|"]
    for label, run, f, r in rows:
        lines.append(f"| {label} | {run} | {f}/{a.test} | {r}/{a.test} |")
    text = "\n".join(lines)
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
