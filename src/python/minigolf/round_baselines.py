"""Baselines for `minigolf/Round-v0` (minigolf.round_env.RoundEnv), beside the environment:

- `PlannerPolicy`: the robot's own planner (`minigolf.plan_stroke`, game::plan_stroke: the search
  `minigolf play` plays every stroke with) as a policy of the environment. It plans in the robot's
  model of the lane (the field file, not the plant) under a launch error; for player "arm" it
  first calibrates its launch skill with arm putts from the tee (as `minigolf play` does) and
  turns the planned launch into a club speed and direction.
- `learn_linear`: a numpy learner, CMA-ES (minigolf.baselines.CMAES) over a linear policy of the
  observation scaled to [-1, 1] by its bounds, fitness the mean return over a generation's
  episodes (common random numbers). `learning_curve` records its mean strokes per hole on held-out
  episodes at checkpoints of strokes played.

    env = minigolf.make("minigolf/Round-v0", player="fast")
    policy = PlannerPolicy(env)
    returns = [play_episode(env, policy, seed=s)["return"] for s in range(5)]
"""
from __future__ import annotations

import math
from typing import Callable, Optional, Sequence

import numpy as np

from . import _minigolf
from .baselines import CMAES
from .round_env import LAUNCH_SPEEDS, RoundEnv


class PlannerPolicy:
    """The round's planner as a policy: policy(obs, env) -> action (uses the env's ball and hole).

    angle_error, speed_error: the launch error it plans under (std [rad], relative [-]; default:
    the oracle's, the arm's measured precision; for player "arm" at least its skill's).
    """

    def __init__(self, env, angle_error: float = 0.0005, speed_error: float = 0.007, threads: int = 0):
        self.env = env.unwrapped
        if not isinstance(self.env, RoundEnv):
            raise ValueError("PlannerPolicy: expected a RoundEnv (minigolf/Round-v0)")
        self.angle_error, self.speed_error, self.threads = angle_error, speed_error, threads
        self.cache = _minigolf.ImaginedCache()
        self._belief = {}   # field -> System without the plant (the robot's model)
        self._skills = {}   # field -> LaunchSkill (player "arm")
        self.imagined_putts = 0

    def _model(self):
        e = self.env
        key = e.holes[e._hole_index]["field"]
        if key not in self._belief:
            k = e._init_kwargs
            self._belief[key] = (e.system if not k["plant"] else
                                 _minigolf.System(field=key, config=k["config"], hitting_model=k["hitting_model"]))
        return key, self._belief[key]

    def plan(self) -> dict:
        """The planner's stroke from where the ball lies: a dict of plan_stroke, plus `direction`
        [rad, world] and `speed` [m/s] as the env's to_physical takes them."""
        e = self.env
        key, system = self._model()
        ball, hole = tuple(e.ball), tuple(e.hole)
        if e.player != "arm":
            p = _minigolf.plan_stroke(system, ball, hole, self.angle_error, self.speed_error,
                                      speed_min=LAUNCH_SPEEDS[0], speed_max=LAUNCH_SPEEDS[1],
                                      threads=self.threads, cache=self.cache)
            p["direction"], p["speed_command"] = p["angle"], p["speed"]
        else:
            if key not in self._skills:
                self._skills[key] = _minigolf.calibrate_launch_skill(e.system)
            skill = self._skills[key]
            lo, hi = e.speed_range
            p = _minigolf.plan_stroke(system, ball, hole, max(self.angle_error, skill.angle_std),
                                      max(self.speed_error, skill.speed_std),
                                      speed_min=skill.launch_speed(lo * 1.02), speed_max=skill.launch_speed(hi * 0.98),
                                      threads=self.threads, cache=self.cache, skill=skill)
            club = skill.club_for(p["speed"], lo, hi)
            p["direction"] = math.remainder(p["angle"] - skill.angle_offset(club), 2.0 * math.pi)
            p["speed_command"] = club
        self.imagined_putts += p["imagined_putts"]
        return p

    def __call__(self, obs=None, env=None) -> np.ndarray:
        p = self.plan()
        return self.env.from_physical((p["direction"], p["speed_command"]))


FEATURES = ("to_hole_x", "to_hole_y", "distance", "line_blocked")


class LinearRoundPolicy:
    """a = clip(S (W z + b), -1, 1), z the observation's `features` (names of observation_names)
    scaled to [-1, 1] by the observation space's bounds, S = diag(direction_scale, 1): the
    direction's output scaled (0.1: a unit of theta turns the stroke by 18 degrees, so isotropic
    search steps aim finely and still reach a bank). theta = (W | b) row by row."""

    def __init__(self, env, features: Sequence[str] = FEATURES, direction_scale: float = 0.1):
        space = env.observation_space
        names = list(env.unwrapped.observation_names)
        self.index = np.array([names.index(f) for f in features])
        self.low = np.asarray(space.low, dtype=np.float64)[self.index]
        self.high = np.asarray(space.high, dtype=np.float64)[self.index]
        self.dim = 2 * (self.index.size + 1)
        self.scale = np.array([direction_scale, 1.0])

    def act(self, theta, obs) -> np.ndarray:
        x = np.asarray(obs, dtype=np.float64)[self.index]
        z = 2.0 * (x - self.low) / (self.high - self.low) - 1.0
        w = np.asarray(theta, dtype=np.float64).reshape(2, -1)
        return np.clip(self.scale * (w[:, :-1] @ z + w[:, -1]), -1.0, 1.0).astype(np.float32)


def play_episode(env, policy: Callable, seed: Optional[int] = None, options: Optional[dict] = None) -> dict:
    """One episode with policy(obs, env) -> action: its return, strokes (the env's total),
    holes sunk and strokes played (env.step calls)."""
    obs, info = env.reset(seed=seed, options=options)
    total, steps, sunk = 0.0, 0, 0
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs, env))
        total += reward
        steps += 1
        sunk += int(info["sunk"])
        if terminated or truncated:
            return {"return": total, "strokes": info["total_strokes"], "sunk": sunk, "steps": steps}


def learning_curve(env, checkpoints: Sequence[int], seed: int = 0, test_seeds: Sequence[int] = range(1000, 1010),
                   episodes: int = 4, sigma0: float = 0.2, theta0=None) -> list:
    """CMA-ES over LinearRoundPolicy on `env` (minimising the mean strokes of a generation's
    `episodes` episodes, each candidate on the same seeds; the policy's direction scale 0.1, sigma0
    0.2 and 4 episodes were chosen over scale 1 with sigma0 0.3 / 0.05 / 0.02 and 2 episodes on
    two-run trials with test seeds 1000-1019 on flat and bank-shot; the measured curves use
    2000-2019). At every checkpoint (strokes played by
    the learner, every env.step; test episodes not counted) the distribution mean plays the test
    episodes: rows {"strokes_played", "mean_strokes", "sunk_ratio"}."""
    rng = np.random.default_rng(seed)
    policy = LinearRoundPolicy(env)
    x0 = np.zeros(policy.dim) if theta0 is None else np.asarray(theta0, dtype=np.float64)
    es = CMAES(x0, sigma0, rng=rng)
    played, rows = 0, []
    pending = sorted(checkpoints)

    def test(theta):
        results = [play_episode(env, lambda o, e: policy.act(theta, o), seed=int(s)) for s in test_seeds]
        return (float(np.mean([r["strokes"] for r in results])),
                float(np.mean([r["sunk"] / len(env.unwrapped.holes) for r in results])))

    while pending:
        candidates = es.ask()
        seeds = rng.integers(0, 2**31 - 1, size=episodes)
        values, cost = [], 0
        for c in candidates:
            results = [play_episode(env, lambda o, e, c=c: policy.act(c, o), seed=int(s)) for s in seeds]
            values.append(float(np.mean([r["strokes"] for r in results])))
            cost += sum(r["steps"] for r in results)
        while pending and played + cost > pending[0]:  # the estimate a budget of pending[0] strokes gives
            m, s = test(es.mean)
            rows.append({"strokes_played": pending.pop(0), "spent": played, "mean_strokes": m, "sunk_ratio": s})
        if not pending:
            break
        es.tell(candidates, values)
        played += cost
    return rows
