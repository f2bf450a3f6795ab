#!/usr/bin/python3
"""Steps per second of the environments, in the same run, and PuttFast-v0's outcome agreement
with the MuJoCo ball world (PuttBall-v0) over random actions (docs/python.md, "Measured").

    PYTHONPATH=build/python /usr/bin/python3 bench/python/env_speed.py [--agreement 500] [--seconds 5]

Speed: each id steps random actions (reset + step per putt episode; step only for Round-v0) in
rounds of about `--seconds` s, interleaved, `--repeats` times; the median rate per id, on one core
(one process, one thread). Agreement: the same `--agreement` random normalised actions and seeds
(holes) in both ids on every field: same sunk/missed, and the rest positions' distance. Prints
Markdown tables and writes them with --out (a .md file).
"""
import argparse
import os
import statistics
import time

import numpy as np

import minigolf


def rate(make, seconds, seed):
    env = make()
    rng = np.random.default_rng(seed)
    n, start = 0, time.perf_counter()
    obs, _ = env.reset(seed=seed)
    while time.perf_counter() - start < seconds:
        _, _, term, trunc, _ = env.step(rng.uniform(-1, 1, 2).astype(np.float32))
        n += 1
        if term or trunc:
            env.reset()
    return n / (time.perf_counter() - start)


def agreement(field, n, seed):
    fast = minigolf.make("minigolf/PuttFast-v0", field=field)
    ball = minigolf.make("minigolf/PuttBall-v0", field=field)
    rng = np.random.default_rng(seed)
    same, gaps = 0, []
    for k in range(n):
        a = rng.uniform(-1, 1, 2).astype(np.float32)
        fast.reset(seed=seed + k), ball.reset(seed=seed + k)
        f, b = fast.step(a)[4], ball.step(a)[4]
        same += f["sunk"] == b["sunk"]
        gaps.append(float(np.hypot(*np.subtract(f["rest_position"], b["rest_position"]))))
    gaps = np.array(gaps)
    return same, float(np.median(gaps)), float(np.quantile(gaps, 0.99)), int(np.sum(gaps > 0.01))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seconds", type=float, default=5.0)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--agreement", type=int, default=500)
    p.add_argument("--fields", default="flat,arctan,bank-shot,l-shape")
    p.add_argument("--arm", action="store_true", help="also time Putt-v0 and Round-v0 with the arm")
    p.add_argument("--out", default="")
    args = p.parse_args()
    ids = {
        "minigolf/PuttBall-v0": lambda: minigolf.make("minigolf/PuttBall-v0"),
        "minigolf/PuttFast-v0": lambda: minigolf.make("minigolf/PuttFast-v0"),
        "minigolf/Round-v0 (player ball)": lambda: minigolf.make("minigolf/Round-v0", player="ball"),
        "minigolf/Round-v0 (player fast)": lambda: minigolf.make("minigolf/Round-v0", player="fast"),
    }
    if args.arm:
        ids["minigolf/Putt-v0"] = lambda: minigolf.make("minigolf/Putt-v0")
        ids["minigolf/Round-v0 (player arm)"] = lambda: minigolf.make("minigolf/Round-v0", player="arm")
    rates = {k: [] for k in ids}
    for r in range(args.repeats):
        for k, make in ids.items():
            rates[k].append(rate(make, args.seconds, seed=r))
    load = os.getloadavg()[0]
    lines = [f"Steps per second, one process, median of {args.repeats} x {args.seconds:g} s, interleaved "
             f"(load average {load:.1f} on {os.cpu_count()} cores):", "",
             "| id | steps/s | runs |", "|---|---:|---|"]
    base = statistics.median(rates["minigolf/PuttBall-v0"])
    for k, v in rates.items():
        m = statistics.median(v)
        lines.append(f"| {k} | {m:.0f} ({m / base:.1f} x PuttBall-v0) | {', '.join(f'{x:.0f}' for x in v)} |")
    lines += ["", f"PuttFast-v0 against PuttBall-v0 (MuJoCo), {args.agreement} random actions and holes per field:", "",
              "| field | same sunk/missed | rest gap median [m] | rest gap 99 % [m] | rest gap > 1 cm |",
              "|---|---:|---:|---:|---:|"]
    for field in args.fields.split(","):
        same, med, q99, far = agreement(field, args.agreement, seed=1)
        lines.append(f"| {field} | {same}/{args.agreement} ({100 * same / args.agreement:.1f} %) | {med:.1e} | "
                     f"{q99:.1e} | {far} |")
    text = "\n".join(lines)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()
