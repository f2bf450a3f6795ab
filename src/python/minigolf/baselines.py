"""Baselines users know, in pure numpy: CMA-ES and Augmented Random Search over a linear policy,
learning through `minigolf.env.PuttEnv` with the same test situations and putt accounting as the
`minigolf curves` command (src/experiments/learning_curves.hpp).

    from minigolf import baselines
    rows = baselines.learning_curves("cma-es", field="flat", mode="arm", checkpoints=(10, 25, 50),
                                     seeds=3, situations=100, test_seed=7, seed=1)
    # [{"learner": "cma-es", "run": 0, "putts": 10, "sunk": 31, "situations": 100, "success": 0.31}, ...]

The policy (`LinearPolicy`): the observation scaled to z in [-1, 1] by the observation space's
bounds, a = clip(W z + b, -1, 1), the env's normalised action (theta, v) (normalize_actions=True
maps [-1, 1]^2 linearly onto the safe envelope: [rad], [m/s]). theta = (W | b) row by row:
2 (d + 1) numbers, d the observation's size (flat: d = 1, xi_y; arctan: d = 2, xi_x and xi_y).
Both learners start from theta = 0 (aim 0.15 rad, club speed 1.65 m/s: the envelope's middle).

The learners (`LEARNERS`), the optimisers written out below (generic objectives too: `cma_es_minimize`,
`ars_maximize`):
  "cma-es"  CMA-ES, (mu/mu_w, lambda) with cumulative step-size adaptation, rank-one and rank-mu
            covariance updates, Hansen's default parameters (N. Hansen, "The CMA Evolution Strategy:
            A Tutorial", arXiv:1604.00772, 2016, table 1 and fig. 6; Hansen & Ostermeier, Evolutionary
            Computation 9(2), 2001). It minimises -reward; its estimate is the distribution mean.
  "ars"     Augmented Random Search V1-t (H. Mania, A. Guy, B. Recht, "Simple random search of static
            linear policies is competitive for reinforcement learning", NeurIPS 2018, algorithm 1):
            N antithetic directions, the b best (by max(r+, r-)) step the policy, scaled by the
            standard deviation of their 2b rewards. V1, not V2: the observation is already scaled to
            [-1, 1] by its known bounds, which is what V2's running normalisation estimates.
Hyperparameters: `DEFAULTS` (how they were chosen is written there); `options` overrides them.
Every candidate of a generation (CMA-ES) or iteration (ARS) plays the same `episodes` holes: each
drawn by env.reset(seed=s), s from the run's generator (common random numbers: the ranking compares
policies, not holes). Its fitness is the mean shaped reward over them: 1 if sunk, else
-closest_approach / reward_scale [m] (the env's reward="shaped").

Putt accounting, as `curves`: every env.step a learner makes is a learning putt (full-system putts in
mode "arm", ball putts in mode "ball"). At checkpoint c the learner's estimate is recorded having
spent at most c putts: a generation (or iteration) that would take the count past c is played only
after the estimate for c is recorded (`Checkpoint.spent` <= c, the putts really spent; less than one
generation's putts short of c). So the estimate at c is the one a budget of c putts gives. The test
putts are not counted: at a checkpoint the estimate is played without exploration noise on the test
holes `field.situations.sample(situations, test_seed)` (`evaluation_holes`), the ones `curves` plays, through
env.reset(options={"hole": h}) and env.step.

Deterministic: run r of a given seed draws from numpy's default_rng([seed, r]), whatever the thread
count (`threads`: runs in parallel threads; putts release the GIL).
"""
from __future__ import annotations

import dataclasses
import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Callable, Optional, Sequence

import numpy as np

#: The learners and their curves-CSV names.
LEARNERS = ("cma-es", "ars")
#: The registered env id of each mode (normalised actions, shaped reward).
ENV_IDS = {"arm": "minigolf/Putt-v0", "ball": "minigolf/PuttBall-v0"}
#: The curves CSV's columns (src/experiments/learning_curves.hpp, curves_csv).
CSV_COLUMNS = ("learner", "run", "putts", "sunk", "situations", "success")


# ----------------------------------------------------------------------------------------------
# The policy
class LinearPolicy:
    """a = clip(W z + b, -1, 1) with z = 2 (obs - low) / (high - low) - 1 (the observation scaled to
    [-1, 1] by its space's bounds). theta: W and b as rows (W[i], b[i]) of an (action_dim, d + 1)
    array, flattened (n_params = action_dim * (d + 1)). The action is the env's normalised one."""

    def __init__(self, low, high, action_dim: int = 2):
        self.low = np.asarray(low, dtype=np.float64).ravel()
        self.high = np.asarray(high, dtype=np.float64).ravel()
        if self.low.shape != self.high.shape or not np.all(self.high > self.low):
            raise ValueError("LinearPolicy: expected bounds low < high of the same shape")
        self.obs_dim = self.low.size
        self.action_dim = int(action_dim)
        self.n_params = self.action_dim * (self.obs_dim + 1)

    @classmethod
    def for_env(cls, env) -> "LinearPolicy":
        """The policy of an env with normalised actions (its observation space's bounds)."""
        space = env.observation_space
        a = env.action_space
        if not (np.all(a.low == -1.0) and np.all(a.high == 1.0)):
            raise ValueError("LinearPolicy.for_env: expected normalised actions (normalize_actions=True)")
        return cls(space.low, space.high, action_dim=a.shape[0])

    def features(self, obs) -> np.ndarray:
        """(z, 1): z the observation scaled to [-1, 1] (clipped there)."""
        o = np.asarray(obs, dtype=np.float64).ravel()
        z = np.clip(2.0 * (o - self.low) / (self.high - self.low) - 1.0, -1.0, 1.0)
        return np.append(z, 1.0)

    def act(self, theta, obs) -> np.ndarray:
        """The normalised action in [-1, 1]^action_dim (float32)."""
        w = np.asarray(theta, dtype=np.float64).reshape(self.action_dim, self.obs_dim + 1)
        return np.clip(w @ self.features(obs), -1.0, 1.0).astype(np.float32)


# ----------------------------------------------------------------------------------------------
# CMA-ES
class CMAES:
    """CMA-ES minimising f over R^n (Hansen 2016, arXiv:1604.00772: the (mu/mu_w, lambda)-CMA-ES of
    fig. 6 with the default parameters of table 1, positive recombination weights only).

    ask() -> (lambda, n) candidates; tell(candidates, values) updates the mean, the evolution paths
    p_sigma and p_c, the covariance C (rank-one update with p_c, rank-mu update with the mu best
    steps) and the step size sigma (cumulative step-size adaptation). `mean` is the estimate.
    x0: the initial mean; sigma0 > 0 the initial step size (units of x); popsize: lambda (default
    4 + floor(3 ln n)); rng: a numpy Generator (or seed: default_rng(seed)).
    """

    def __init__(self, x0, sigma0: float, popsize: Optional[int] = None,
                 rng: Optional[np.random.Generator] = None, seed=None):
        x0 = np.asarray(x0, dtype=np.float64).ravel()
        n = x0.size
        if n < 1:
            raise ValueError("CMAES: x0 is empty")
        if not (np.isfinite(sigma0) and sigma0 > 0):
            raise ValueError(f"CMAES: sigma0: expected a finite value > 0, got {sigma0!r}")
        lam = int(popsize) if popsize is not None else 4 + int(math.floor(3.0 * math.log(n)))
        if lam < 2:
            raise ValueError(f"CMAES: popsize: expected >= 2, got {lam}")
        self.rng = rng if rng is not None else np.random.default_rng(seed)
        self.n, self.lam = n, lam
        self.mu = lam // 2
        w = math.log((lam + 1) / 2.0) - np.log(np.arange(1, self.mu + 1))
        self.weights = w / w.sum()
        self.mueff = 1.0 / float(np.sum(self.weights ** 2))
        mueff = self.mueff
        # Table 1 (alpha_mu = 2, c_m = 1)
        self.cs = (mueff + 2.0) / (n + mueff + 5.0)
        self.ds = 1.0 + 2.0 * max(0.0, math.sqrt((mueff - 1.0) / (n + 1.0)) - 1.0) + self.cs
        self.cc = (4.0 + mueff / n) / (n + 4.0 + 2.0 * mueff / n)
        self.c1 = 2.0 / ((n + 1.3) ** 2 + mueff)
        self.cmu = min(1.0 - self.c1, 2.0 * (mueff - 2.0 + 1.0 / mueff) / ((n + 2.0) ** 2 + mueff))
        self.chi_n = math.sqrt(n) * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n))  # E||N(0, I)||
        self.mean = x0.copy()
        self.sigma = float(sigma0)
        self.ps = np.zeros(n)
        self.pc = np.zeros(n)
        self.C = np.eye(n)
        self.B = np.eye(n)
        self.D = np.ones(n)       # sqrt of C's eigenvalues
        self.generation = 0
        self.evaluations = 0

    def ask(self) -> np.ndarray:
        """lambda candidates x_k = mean + sigma B D z_k, z_k ~ N(0, I)."""
        z = self.rng.standard_normal((self.lam, self.n))
        return self.mean + self.sigma * (z * self.D) @ self.B.T

    def tell(self, candidates, values) -> None:
        """Updates from the candidates' objective values (lower is better; ties keep their order)."""
        x = np.asarray(candidates, dtype=np.float64).reshape(self.lam, self.n)
        f = np.asarray(values, dtype=np.float64).ravel()
        if f.size != self.lam:
            raise ValueError(f"CMAES.tell: expected {self.lam} values, got {f.size}")
        if not np.all(np.isfinite(f)):
            raise ValueError("CMAES.tell: the objective values must be finite")
        n, cs, cc, c1, cmu = self.n, self.cs, self.cc, self.c1, self.cmu
        order = np.argsort(f, kind="stable")[: self.mu]
        y = (x[order] - self.mean) / self.sigma            # the mu best steps, (mu, n)
        yw = self.weights @ y
        self.mean = self.mean + self.sigma * yw             # c_m = 1
        inv_sqrt_c_yw = self.B @ ((self.B.T @ yw) / self.D)  # C^{-1/2} y_w
        self.ps = (1.0 - cs) * self.ps + math.sqrt(cs * (2.0 - cs) * self.mueff) * inv_sqrt_c_yw
        self.generation += 1
        self.evaluations += self.lam
        ps_norm = float(np.linalg.norm(self.ps))
        h_sigma = ps_norm / math.sqrt(1.0 - (1.0 - cs) ** (2 * self.generation)) < (1.4 + 2.0 / (n + 1.0)) * self.chi_n
        self.pc = (1.0 - cc) * self.pc + (math.sqrt(cc * (2.0 - cc) * self.mueff) * yw if h_sigma else 0.0)
        delta_h = 0.0 if h_sigma else cc * (2.0 - cc)
        rank_mu = (y * self.weights[:, None]).T @ y
        self.C = ((1.0 + c1 * delta_h - c1 - cmu) * self.C   # sum(weights) = 1
                  + c1 * np.outer(self.pc, self.pc) + cmu * rank_mu)
        self.C = 0.5 * (self.C + self.C.T)
        self.sigma *= math.exp((cs / self.ds) * (ps_norm / self.chi_n - 1.0))
        eig, self.B = np.linalg.eigh(self.C)
        self.D = np.sqrt(np.maximum(eig, 1e-300))

    @property
    def condition(self) -> float:
        """C's condition number."""
        return float((self.D.max() / self.D.min()) ** 2)


@dataclasses.dataclass
class OptimumResult:
    x: np.ndarray          #: the best point evaluated
    f: float               #: its objective value
    mean: np.ndarray       #: the final estimate (CMA-ES: the mean; ARS: the policy)
    evaluations: int       #: objective evaluations spent
    iterations: int        #: generations (CMA-ES) or iterations (ARS)
    stop: str              #: why it stopped


def _batch(objective, vectorized):
    if vectorized:
        return lambda xs: np.asarray(objective(xs), dtype=np.float64).ravel()
    return lambda xs: np.array([float(objective(x)) for x in xs])


def cma_es_minimize(objective: Callable, x0, sigma0: float, *, max_evaluations: int = 100000,
                    ftarget: float = -np.inf, tolx: float = 1e-12, popsize: Optional[int] = None,
                    seed=None, vectorized: bool = False) -> OptimumResult:
    """Minimises objective(x) (x: a 1-D array; vectorized=True: objective(X) of a (lambda, n) array
    returns lambda values) with `CMAES` from x0 and step size sigma0. Stops at max_evaluations, when
    a value <= ftarget is found, when sigma * sqrt(max C_ii) < tolx, or at C's condition 1e14."""
    es = CMAES(x0, sigma0, popsize=popsize, seed=seed)
    f_batch = _batch(objective, vectorized)
    best_x, best_f = es.mean.copy(), np.inf
    stop = "max_evaluations"
    while es.evaluations + es.lam <= max_evaluations:
        xs = es.ask()
        fs = f_batch(xs)
        k = int(np.argmin(fs))
        if fs[k] < best_f:
            best_x, best_f = xs[k].copy(), float(fs[k])
        es.tell(xs, fs)
        if best_f <= ftarget:
            stop = "ftarget"
            break
        if es.sigma * math.sqrt(float(np.max(np.diag(es.C)))) < tolx:
            stop = "tolx"
            break
        if es.condition > 1e14:
            stop = "condition"
            break
    return OptimumResult(best_x, best_f, es.mean.copy(), es.evaluations, es.generation, stop)


# ----------------------------------------------------------------------------------------------
# Augmented Random Search
class ARS:
    """Augmented Random Search V1-t maximising a reward over R^n (Mania, Guy & Recht 2018, algorithm 1).

    ask() -> the 2N candidates (theta + nu delta_k for k < N, then theta - nu delta_k), delta_k with
    i.i.d. N(0, 1) entries; tell(rewards) steps theta += step / (b sigma_R) sum_top-b (r+ - r-) delta,
    the b directions with the largest max(r+, r-), sigma_R the standard deviation of their 2b
    rewards (no step when it is 0: all equal). `theta` is the estimate.
    directions: N; top: b (1..N, default N); step: alpha; noise: nu (units of theta).
    """

    def __init__(self, x0, directions: int = 4, top: Optional[int] = None, step: float = 0.02,
                 noise: float = 0.03, rng: Optional[np.random.Generator] = None, seed=None):
        self.theta = np.asarray(x0, dtype=np.float64).ravel().copy()
        self.n = self.theta.size
        self.N = int(directions)
        self.b = self.N if top is None else int(top)
        if self.n < 1:
            raise ValueError("ARS: x0 is empty")
        if self.N < 1 or not 1 <= self.b <= self.N:
            raise ValueError(f"ARS: expected directions >= 1 and 1 <= top <= directions, got {self.N}, {self.b}")
        if not (np.isfinite(step) and step > 0 and np.isfinite(noise) and noise > 0):
            raise ValueError(f"ARS: step and noise: expected finite values > 0, got {step!r}, {noise!r}")
        self.step, self.noise = float(step), float(noise)
        self.rng = rng if rng is not None else np.random.default_rng(seed)
        self.iteration = 0
        self.evaluations = 0
        self._delta = None

    @property
    def lam(self) -> int:
        """Candidates per iteration (2N)."""
        return 2 * self.N

    def ask(self) -> np.ndarray:
        self._delta = self.rng.standard_normal((self.N, self.n))
        return np.vstack([self.theta + self.noise * self._delta, self.theta - self.noise * self._delta])

    def tell(self, rewards) -> None:
        """Updates from the 2N candidates' rewards (higher is better), in ask()'s order."""
        if self._delta is None:
            raise RuntimeError("ARS.tell: call ask() first")
        r = np.asarray(rewards, dtype=np.float64).ravel()
        if r.size != 2 * self.N or not np.all(np.isfinite(r)):
            raise ValueError(f"ARS.tell: expected {2 * self.N} finite rewards, got {r.size}")
        plus, minus = r[: self.N], r[self.N:]
        top = np.argsort(-np.maximum(plus, minus), kind="stable")[: self.b]
        sigma_r = float(np.std(np.concatenate([plus[top], minus[top]])))
        if sigma_r > 0.0:
            self.theta = self.theta + self.step / (self.b * sigma_r) * ((plus[top] - minus[top]) @ self._delta[top])
        self._delta = None
        self.iteration += 1
        self.evaluations += 2 * self.N


def ars_maximize(objective: Callable, x0, *, iterations: int = 1000, directions: int = 4,
                 top: Optional[int] = None, step: float = 0.02, noise: float = 0.03, seed=None,
                 vectorized: bool = False) -> OptimumResult:
    """Maximises objective(x) (vectorized=True: objective(X) of a (2N, n) array returns 2N values:
    one call per iteration, e.g. the same random episodes for every candidate) with `ARS`."""
    ars = ARS(x0, directions=directions, top=top, step=step, noise=noise, seed=seed)
    f_batch = _batch(objective, vectorized)
    best_x, best_f = ars.theta.copy(), -np.inf
    for _ in range(iterations):
        xs = ars.ask()
        fs = f_batch(xs)
        k = int(np.argmax(fs))
        if fs[k] > best_f:
            best_x, best_f = xs[k].copy(), float(fs[k])
        ars.tell(fs)
    return OptimumResult(best_x, best_f, ars.theta.copy(), ars.evaluations, ars.iteration, "iterations")


# ----------------------------------------------------------------------------------------------
# Learning through the env
#: Default hyperparameters (theta is in normalised action units: 1 unit = 0.45 rad of hitting angle,
#: 1.35 m/s of club speed). CMA-ES: sigma0 = 0.1, about a fifth of theta's distance to a good policy
#: (Hansen's advice), popsize Hansen's 4 + floor(3 ln n) (8 on flat, 9 on arctan). ARS: N = 4
#: directions, all kept (b = N), step 0.02, noise 0.03. Chosen on validation runs (4 runs, seed
#: 100, test seed 1001, 50 holes, full system) among sigma0 0.05 / 0.1 / 0.3, two episodes per
#: candidate, and ARS (N, b, step, noise) in (4, 2, 0.03, 0.05), (4, 4, 0.02, 0.03), (4, 2, 0.05,
#: 0.05), (8, 4, 0.02, 0.03), (4, 4, 0.01, 0.02): sigma0 = 0.3 let CMA-ES drift to the club's
#: fastest putts (a fast ball over the hole's centre has a closest approach of millimetres: the
#: shaped reward barely tells it from a sunk one) and never recovered; larger ARS steps stalled.
DEFAULTS = {
    "cma-es": dict(sigma0=0.1, popsize=None, episodes=1),
    "ars": dict(directions=4, top=4, step=0.02, noise=0.03, episodes=1),
}


@dataclasses.dataclass
class Checkpoint:
    putts: int             #: the checkpoint c
    spent: int             #: learning putts spent when the estimate was taken (<= c)
    theta: np.ndarray      #: the policy's parameters then


def _check_checkpoints(checkpoints) -> list:
    cps = [int(c) for c in checkpoints]
    if not cps:
        raise ValueError("baselines: no checkpoints")
    for c in cps:
        if not 0 <= c <= 100000:
            raise ValueError(f"baselines: checkpoint {c}: expected 0..100000")
    if cps[-1] < 1:
        raise ValueError("baselines: the last checkpoint must be >= 1 putt")
    if any(b <= a for a, b in zip(cps, cps[1:])):
        raise ValueError("baselines: checkpoints must be strictly increasing (each a different putt count)")
    return cps


def _hyper(method: str, options: Optional[dict]) -> dict:
    if method not in LEARNERS:
        raise ValueError(f"baselines: method: expected one of {', '.join(LEARNERS)}, got '{method}'")
    h = dict(DEFAULTS[method])
    unknown = set(options or {}) - set(h)
    if unknown:
        raise ValueError(f"baselines: {method}: unknown option(s) {sorted(unknown)} (expected {sorted(h)})")
    h.update(options or {})
    if int(h["episodes"]) < 1:
        raise ValueError(f"baselines: episodes: expected >= 1, got {h['episodes']}")
    return h


def learn(method: str, env, checkpoints: Sequence[int], rng: np.random.Generator,
          options: Optional[dict] = None) -> list:
    """Runs a learner through `env` (normalised actions; the shaped reward is what it maximises) and
    returns a `Checkpoint` per checkpoint: the estimate having spent at most c learning putts (every
    env.step here is one). Stops once the last checkpoint is recorded. options: `DEFAULTS[method]`'s
    keys (episodes: holes per generation / iteration, shared by its candidates)."""
    cps = _check_checkpoints(checkpoints)
    h = _hyper(method, options)
    episodes = int(h["episodes"])
    policy = LinearPolicy.for_env(env)
    x0 = np.zeros(policy.n_params)
    if method == "cma-es":
        opt = CMAES(x0, h["sigma0"], popsize=h["popsize"], rng=rng)
        estimate = lambda: opt.mean.copy()  # noqa: E731
    else:
        opt = ARS(x0, directions=h["directions"], top=h["top"], step=h["step"], noise=h["noise"], rng=rng)
        estimate = lambda: opt.theta.copy()  # noqa: E731
    records, pending, spent = [], list(cps), 0
    while True:
        cost = opt.lam * episodes
        while pending and spent + cost > pending[0]:  # the next generation would overshoot
            records.append(Checkpoint(pending.pop(0), spent, estimate()))
        if not pending:
            return records
        xs = opt.ask()
        seeds = rng.integers(0, 2**63 - 1, size=episodes)
        fitness = np.zeros(len(xs))
        for k, theta in enumerate(xs):
            for s in seeds:
                obs, _ = env.reset(seed=int(s))
                _, reward, _, _, _ = env.step(policy.act(theta, obs))
                spent += 1
                fitness[k] += reward / episodes
        if method == "cma-es":
            opt.tell(xs, -fitness)
        else:
            opt.tell(fitness)


def evaluation_holes(field, situations: int, test_seed: int) -> np.ndarray:
    """The test holes (situations, 2) [m] of `curves`: the field's region sampled with test_seed
    (field: a minigolf.Field, or an env: its first field)."""
    f = field.unwrapped.systems[0].field if hasattr(field, "unwrapped") else field
    return np.asarray(f.situations.sample(int(situations), int(test_seed)), dtype=np.float64)


def evaluate(env, policy: LinearPolicy, theta, holes) -> int:
    """Holes sunk by the policy theta (no exploration noise), one putt each through the env."""
    sunk = 0
    for h in holes:
        obs, _ = env.reset(options={"hole": (float(h[0]), float(h[1]))})
        _, _, _, _, info = env.step(policy.act(theta, obs))
        sunk += bool(info["sunk"])
    return sunk


def make_env(field: str = "flat", mode: str = "arm", **kwargs):
    """The env the baselines learn in: `ENV_IDS[mode]` (normalised actions, shaped reward) on field."""
    if mode not in ENV_IDS:
        raise ValueError(f"baselines: mode: expected 'arm' or 'ball', got '{mode}'")
    from .env import make
    # The layout the measured curves (docs/python.md) were learned with: xi's varying coordinates.
    return make(ENV_IDS[mode], field=field, **{"observation": "varying", **kwargs})


def run_seed(seed: int, run: int) -> np.random.Generator:
    """The generator of run `run` (0-based) of a learning_curves seed."""
    return np.random.default_rng([int(seed), int(run)])


def learning_curves(method: str, field: str = "flat", mode: str = "arm",
                    checkpoints: Sequence[int] = (10, 25, 50, 100, 150), seeds: int = 10,
                    situations: int = 100, test_seed: int = 7, seed: int = 1,
                    options: Optional[dict] = None, threads: int = 1,
                    env_factory: Optional[Callable] = None,
                    progress: Optional[Callable[[int, int], None]] = None) -> list:
    """Learning curves of a baseline as `minigolf curves` writes them: a run per seed (run r learns
    from `run_seed(seed, r)`), each checkpoint's estimate played on `evaluation_holes(field, situations,
    test_seed)`. Returns rows {learner, run, putts, sunk, situations, success} (`CSV_COLUMNS`),
    run by run, checkpoint by checkpoint. putts: the checkpoint (learning putts spent <= it); success:
    sunk / situations. threads: runs in parallel (0: every core); the rows do not depend on it.
    env_factory(): the env (default make_env(field, mode)); progress(done, total) after each run."""
    cps = _check_checkpoints(checkpoints)
    _hyper(method, options)
    if not 1 <= int(seeds) <= 1000:
        raise ValueError(f"baselines: seeds: expected 1..1000, got {seeds}")
    if not 1 <= int(situations) <= 100000:
        raise ValueError(f"baselines: situations: expected 1..100000, got {situations}")
    factory = env_factory or (lambda: make_env(field, mode))

    def one(r):
        env = factory()
        try:
            records = learn(method, env, cps, run_seed(seed, r), options)
            policy = LinearPolicy.for_env(env)
            holes = evaluation_holes(env, situations, test_seed)
            rows, played = [], {}
            for c in records:
                key = c.theta.tobytes()
                if key not in played:  # an estimate unchanged since the last checkpoint
                    played[key] = evaluate(env, policy, c.theta, holes)
                sunk = played[key]
                rows.append(dict(learner=method, run=r, putts=c.putts, sunk=sunk, situations=int(situations),
                                 success=sunk / int(situations)))
            return rows
        finally:
            env.close()

    workers = int(threads) if threads else (os.cpu_count() or 1)
    workers = max(1, min(workers, int(seeds)))
    out = [None] * int(seeds)
    done = 0
    if workers == 1:
        for r in range(int(seeds)):
            out[r] = one(r)
            done += 1
            if progress:
                progress(done, int(seeds))
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = {pool.submit(one, r): r for r in range(int(seeds))}
            from concurrent.futures import as_completed
            for fut in as_completed(futures):
                out[futures[fut]] = fut.result()
                done += 1
                if progress:
                    progress(done, int(seeds))
    return [row for rows in out for row in rows]


# ----------------------------------------------------------------------------------------------
# CSV and summaries (the formats of experiments::curves_csv and experiments::summarize)
def format_number(x: float) -> str:
    """A double as fmt's "{}" writes it (the shortest round trip; integral values without ".0")."""
    s = repr(float(x))
    return s[:-2] if s.endswith(".0") else s


def curves_csv(rows) -> str:
    """The curves CSV (learner,run,putts,sunk,situations,success) of rows."""
    lines = [",".join(CSV_COLUMNS)]
    for r in rows:
        lines.append(f"{r['learner']},{int(r['run'])},{int(r['putts'])},{int(r['sunk'])},{int(r['situations'])},"
                     f"{format_number(int(r['sunk']) / int(r['situations']))}")
    return "\n".join(lines) + "\n"


def quantile(values, q: float) -> float:
    """Linear interpolation between order statistics (experiments::summarize; numpy's 'linear')."""
    v = np.sort(np.asarray(values, dtype=np.float64))
    pos = q * (v.size - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, v.size - 1)
    return float(v[lo] + (pos - lo) * (v[hi] - v[lo]))


def summarize(rows) -> list:
    """Per learner and checkpoint: {method, x, median, p10, p90} of the success ratio over runs, in
    the rows' order of learners and checkpoints."""
    groups = {}
    for r in rows:
        groups.setdefault(r["learner"], {}).setdefault(int(r["putts"]), []).append(int(r["sunk"]) / int(r["situations"]))
    out = []
    for method, by_putts in groups.items():
        for x, v in by_putts.items():
            out.append(dict(method=method, x=x, median=quantile(v, 0.5), p10=quantile(v, 0.1), p90=quantile(v, 0.9)))
    return out
