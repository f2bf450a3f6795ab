#!/usr/bin/python3
"""Baselines of minigolf/Round-v0 (docs/python.md, "Baselines of the round"): the robot's planner
as a policy, and a numpy learner (CMA-ES over a linear policy) with its learning curve.

    PYTHONPATH=build/python /usr/bin/python3 bench/python/round_baselines.py --out out/round-baselines

Configurations (CONFIGS): flat with holes and balls drawn from boxes, bank-shot with balls drawn
from a box before the block, l-shape from its tee, the obstacles course.
1. The planner (minigolf.round_baselines.PlannerPolicy, the search `minigolf play` plays with):
   `--episodes` episodes per configuration (player "fast", "ball" for the MuJoCo ball, "arm" on
   flat) with the oracle's launch error; mean strokes per hole, holes sunk, seconds per stroke.
2. CMA-ES over LinearRoundPolicy (features to_hole_x, to_hole_y, distance, line_blocked) on
   Round-v0 with player "fast" in `--learn` configurations, `--runs` runs: mean strokes per hole of
   the distribution mean on 20 held-out episodes at checkpoints of strokes played.
Writes summary.md, curves.csv and round_learning_curves.png to --out.
"""
import argparse
import os
import pathlib
import time

import numpy as np

import minigolf
from minigolf.round_baselines import PlannerPolicy, learning_curve, play_episode


CONFIGS = {
    "flat (boxes)": dict(field="flat", situations="box:1.0,2.5:-0.4,0.4:4,4", balls="box:0.0,0.5:-0.3,0.3:3,3"),
    "bank-shot (balls in a box)": dict(field="bank-shot", balls="box:0.0,0.6:-0.4,0.4:3,3"),
    "l-shape (tee)": dict(field="l-shape"),
    "obstacles (course)": dict(course="obstacles"),
}


def planner_rows(configs, players, episodes):
    rows = []
    for name in configs:
        for player in players:
            if player == "arm" and not name.startswith("flat"):
                continue
            env = minigolf.make("minigolf/Round-v0", player=player, **CONFIGS[name])
            policy = PlannerPolicy(env)
            start = time.perf_counter()
            results = [play_episode(env, policy, seed=s) for s in range(episodes)]
            seconds = time.perf_counter() - start
            steps = sum(r["steps"] for r in results)
            holes = len(env.holes)
            rows.append(dict(field=name, player=player, episodes=episodes, holes=holes * episodes,
                             mean_strokes=float(np.mean([r["strokes"] for r in results])) / holes,
                             sunk=sum(r["sunk"] for r in results), seconds_per_stroke=seconds / steps))
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--configs", default=",".join(CONFIGS))
    p.add_argument("--players", default="fast,ball,arm")
    p.add_argument("--episodes", type=int, default=5)
    p.add_argument("--learn", default="flat (boxes),bank-shot (balls in a box)")
    p.add_argument("--checkpoints", default="100,300,1000,3000,10000")
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--out", default="out/round-baselines")
    args = p.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    planner = planner_rows([c for c in args.configs.split(",") if c], args.players.split(","), args.episodes)
    checkpoints = [int(c) for c in args.checkpoints.split(",")]
    curves = []
    start = time.perf_counter()
    learn = [c for c in args.learn.split(",") if c]
    for field in learn:
        env = minigolf.make("minigolf/Round-v0", player="fast", **CONFIGS[field])
        for run in range(args.runs):
            for row in learning_curve(env, checkpoints, seed=run, test_seeds=range(2000, 2020)):
                curves.append(dict(field=field, run=run, **row))
    learn_seconds = time.perf_counter() - start
    with open(out / "curves.csv", "w") as f:
        f.write("config,run,strokes_played,spent,mean_strokes,sunk_ratio\n")
        for r in curves:
            f.write(f"\"{r['field']}\",{r['run']},{r['strokes_played']},{r['spent']},{r['mean_strokes']:.3f},"
                    f"{r['sunk_ratio']:.3f}\n")
    lines = [f"Planner policy (oracle launch error), {args.episodes} episodes per row, max_strokes 6 "
             f"(load average {os.getloadavg()[0]:.1f}, {os.cpu_count()} cores):", "",
             "| configuration | player | strokes per hole | holes sunk | s / stroke |", "|---|---|---:|---:|---:|"]
    for r in planner:
        lines.append(f"| {r['field']} | {r['player']} | {r['mean_strokes']:.2f} | {r['sunk']}/{r['holes']} | "
                     f"{r['seconds_per_stroke']:.2f} |")
    lines += ["", f"CMA-ES over a linear policy (player fast), strokes per hole on 20 held-out episodes, median "
                  f"(min-max) over {args.runs} runs ({learn_seconds:.0f} s in all):", "",
              "| configuration | " + " | ".join(f"{c} strokes" for c in checkpoints) + " | planner |",
              "|---|" + "---:|" * (len(checkpoints) + 1)]
    for field in learn:
        cells = []
        for c in checkpoints:
            v = [r["mean_strokes"] for r in curves if r["field"] == field and r["strokes_played"] == c]
            cells.append(f"{np.median(v):.2f} ({min(v):.1f}-{max(v):.1f})")
        planner_ref = [r["mean_strokes"] for r in planner if r["field"] == field and r["player"] == "fast"]
        lines.append(f"| {field} | " + " | ".join(cells) + " | "
                     + (f"{planner_ref[0]:.2f} |" if planner_ref else "— |"))
    text = "\n".join(lines)
    print(text)
    (out / "summary.md").write_text(text + "\n")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(6, 3.6))
    if not learn:
        return
    for k, field in enumerate(learn):
        med = [np.median([r["mean_strokes"] for r in curves if r["field"] == field and r["strokes_played"] == c])
               for c in checkpoints]
        lo = [min(r["mean_strokes"] for r in curves if r["field"] == field and r["strokes_played"] == c)
              for c in checkpoints]
        hi = [max(r["mean_strokes"] for r in curves if r["field"] == field and r["strokes_played"] == c)
              for c in checkpoints]
        line, = ax.plot(checkpoints, med, "o-", label=f"CMA-ES, {field}")
        ax.fill_between(checkpoints, lo, hi, color=line.get_color(), alpha=0.2)
        ref = [r["mean_strokes"] for r in planner if r["field"] == field and r["player"] == "fast"]
        if ref:
            ax.axhline(ref[0], color=line.get_color(), ls="--", label=f"planner, {field}")
    ax.set_xscale("log")
    ax.set_xlabel("strokes played by the learner")
    ax.set_ylabel("strokes per hole (held-out)")
    ax.set_title("Round-v0 (player fast): CMA-ES vs the robot's planner")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "round_learning_curves.png", dpi=110)


if __name__ == "__main__":
    main()
