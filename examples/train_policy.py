#!/usr/bin/python3
"""Trains a tiny linear policy on minigolf.env.PuttEnv with numpy and prints its success ratio.

The policy maps the situation xi = hole - tee [m] to (theta [rad], v [m/s]) through features
(1, xi_x, xi_y, |xi|); each iteration plays Gaussian-perturbed actions on random situations and
refits the policy by least squares to the best putts so far (the cross-entropy method): those
that sank, or, while too few have, the quarter that came closest to the hole (`info`).

    PYTHONPATH=build/python /usr/bin/python3 examples/train_policy.py [--mode arm]
"""
import argparse
import pathlib
import sys

import numpy as np

try:
    import minigolf  # noqa: F401
except ImportError:  # run from the repository without PYTHONPATH
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "build" / "python"))
from minigolf.env import PuttEnv


def features(xi):
    return np.array([1.0, xi[0], xi[1], np.hypot(xi[0], xi[1])])


def play(env, weights, episodes, seed, noise=None, rng=None):
    """Returns (features, actions, rewards, closest approaches) of `episodes` episodes from `seed`."""
    rows, actions, rewards, closest = [], [], [], []
    _, info = env.reset(seed=seed)
    for _ in range(episodes):
        phi = features(info["xi"])  # both coordinates (the observation leaves out a constant one)
        a = phi @ weights
        if noise is not None:
            a = a + rng.normal(0.0, noise)
        a = np.clip(a, env.action_space.low, env.action_space.high)
        _, reward, _, _, info = env.step(a)
        rows.append(phi), actions.append(a), rewards.append(reward), closest.append(info["closest_approach"])
        _, info = env.reset()
    return np.array(rows), np.array(actions), np.array(rewards), np.nan_to_num(np.array(closest), nan=1.0)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--field", default="flat")
    p.add_argument("--mode", default="ball", choices=["ball", "arm"])
    p.add_argument("--iterations", type=int, default=8)
    p.add_argument("--episodes", type=int, default=60, help="training putts per iteration")
    p.add_argument("--test", type=int, default=100, help="test putts")
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    env = PuttEnv(field=a.field, mode=a.mode)
    rng = np.random.default_rng(a.seed)
    # start: aim straight down the lane at a middling speed
    weights = np.zeros((4, 2))
    weights[0] = [0.0, 0.5 * (env.action_space.low[1] + env.action_space.high[1])]
    noise = np.array([0.1, 0.6])  # exploration std [rad], [m/s]
    X, Y, W = np.zeros((0, 4)), np.zeros((0, 2)), np.zeros(0)
    for it in range(a.iterations):
        phi, act, rew, closest = play(env, weights, a.episodes, seed=a.seed + 1000 * (it + 1), noise=noise, rng=rng)
        X, Y = np.vstack([X, phi]), np.vstack([Y, act])
        W = np.append(W, np.where(rew > 0, -1.0, closest))  # sunk first, then the closest
        best = np.argsort(W, kind="stable")[: max(int(np.sum(W < 0)), len(W) // 4)]
        weights = np.linalg.lstsq(X[best], Y[best], rcond=None)[0]
        noise = np.maximum(noise * 0.8, [0.004, 0.04])
        print(f"iteration {it + 1}: {int(rew.sum())}/{len(rew)} sunk while exploring")
    _, _, rew, _ = play(env, weights, a.test, seed=a.seed + 99)
    print(f"success ratio {rew.mean():.3f} on {a.test} test situations ({a.mode}, {a.field})")


if __name__ == "__main__":
    main()
