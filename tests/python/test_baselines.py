"""minigolf.baselines (CMA-ES and ARS over a linear policy through PuttEnv) and examples/baselines.py:
the optimisers' maths away from the env, the putt accounting, the test situations, determinism,
and a smoke run of the runner (ball mode: fast)."""
import os
import subprocess
import sys

import numpy as np
import pytest

import minigolf
from minigolf import baselines as B
from conftest import BINARY, ROOT


# ---- the optimisers on known functions
def rosenbrock(x):
    return float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1.0 - x[:-1]) ** 2))


def ellipsoid(x):  # condition 1e6: CMA-ES must learn the covariance to get there in few evaluations
    n = len(x)
    return float(np.sum(1e6 ** (np.arange(n) / (n - 1)) * x ** 2))


@pytest.mark.parametrize("n", [4, 8])
def test_cma_es_minimises_the_rosenbrock_function(n):
    r = B.cma_es_minimize(rosenbrock, np.full(n, -1.0), 0.5, ftarget=1e-14, max_evaluations=40000, seed=3)
    assert r.stop == "ftarget" and r.f <= 1e-14
    np.testing.assert_allclose(r.x, np.ones(n), atol=1e-6)
    np.testing.assert_allclose(r.mean, np.ones(n), atol=1e-4)


def test_cma_es_learns_an_ill_conditioned_quadratic():
    r = B.cma_es_minimize(ellipsoid, np.ones(6), 0.5, ftarget=1e-14, max_evaluations=20000, seed=1)
    assert r.f <= 1e-14 and np.max(np.abs(r.x)) < 1e-6
    # without the covariance (sigma and mean alone), an isotropic ES needs about 1e3 times more
    assert r.evaluations < 6000


def test_cma_es_parameters_are_hansens_defaults():
    es = B.CMAES(np.zeros(10), 1.0, seed=0)
    assert (es.lam, es.mu) == (10, 5)  # 4 + floor(3 ln 10), lambda / 2
    assert es.weights.sum() == pytest.approx(1.0) and np.all(np.diff(es.weights) < 0)
    assert es.mueff == pytest.approx(1.0 / np.sum(es.weights ** 2))
    assert es.cs == pytest.approx((es.mueff + 2) / (10 + es.mueff + 5))
    assert es.c1 == pytest.approx(2 / (11.3 ** 2 + es.mueff))
    assert es.c1 + es.cmu <= 1.0
    # step-size adaptation: on a sphere far from the optimum sigma grows, near it sigma shrinks
    grow = B.CMAES(np.full(10, 1e3), 1e-3, seed=0)
    shrink = B.CMAES(np.zeros(10), 1.0, seed=0)
    for es in (grow, shrink):
        for _ in range(60):
            xs = es.ask()
            es.tell(xs, np.sum(xs ** 2, axis=1))
    assert grow.sigma > 10.0 and shrink.sigma < 0.02  # both from their sigma0 (1e-3 and 1)


def test_cma_es_is_deterministic_for_a_seed():
    a = B.cma_es_minimize(rosenbrock, np.zeros(4), 0.3, max_evaluations=400, seed=5)
    b = B.cma_es_minimize(rosenbrock, np.zeros(4), 0.3, max_evaluations=400, seed=5)
    c = B.cma_es_minimize(rosenbrock, np.zeros(4), 0.3, max_evaluations=400, seed=6)
    assert np.array_equal(a.mean, b.mean) and not np.array_equal(a.mean, c.mean)


def test_ars_solves_a_linear_regression_policy_problem():
    """The reward of a linear policy theta: minus the mean squared distance of its (clipped) action
    to a target linear policy's, over 8 random states per iteration shared by the candidates."""
    target = np.array([[0.5, -0.3, 0.1], [0.2, 0.4, -0.2]])  # (W | b), actions inside [-1, 1]
    rng = np.random.default_rng(0)
    policy = B.LinearPolicy([-1.0, -1.0], [1.0, 1.0])

    def rewards(thetas):
        states = rng.uniform(-1.0, 1.0, size=(8, 2))
        want = np.array([policy.act(target.ravel(), s) for s in states])
        return [-np.mean(np.sum((np.array([policy.act(t, s) for s in states]) - want) ** 2, axis=1))
                for t in thetas]

    r = B.ars_maximize(rewards, np.zeros(6), iterations=300, directions=4, step=0.02, noise=0.03, seed=1,
                       vectorized=True)
    assert r.evaluations == 300 * 8
    assert np.max(np.abs(r.mean - target.ravel())) < 0.05


def test_ars_update_is_algorithm_1_of_mania_et_al():
    ars = B.ARS(np.zeros(3), directions=3, top=2, step=0.1, noise=0.5, seed=0)
    xs = ars.ask()
    delta = (xs[:3] - xs[3:]) / (2 * 0.5)
    rewards = np.array([3.0, 1.0, 0.0, 0.0, 2.0, 0.5])  # max(r+, r-): 3, 2, 0.5 -> directions 0 and 1
    ars.tell(rewards)
    used = np.array([3.0, 1.0, 0.0, 2.0])
    want = 0.1 / (2 * np.std(used)) * ((3.0 - 0.0) * delta[0] + (1.0 - 2.0) * delta[1])
    np.testing.assert_allclose(ars.theta, want, rtol=1e-12)


def test_linear_policy_scales_the_observation_by_its_bounds():
    p = B.LinearPolicy([-0.2], [0.4])
    np.testing.assert_allclose(p.features([-0.2]), [-1.0, 1.0])
    np.testing.assert_allclose(p.features([0.4]), [1.0, 1.0])
    np.testing.assert_allclose(p.features([0.1]), [0.0, 1.0], atol=1e-12)
    theta = np.array([0.5, 0.25, 2.0, -3.0])  # theta row = (W_i, b_i)
    np.testing.assert_allclose(p.act(theta, [0.4]), [0.75, -1.0])  # clipped to [-1, 1]
    assert p.act(theta, [0.0]).dtype == np.float32 and p.n_params == 4


# ---- through the env
class Counting:
    """An env wrapper counting steps and recording resets."""

    def __init__(self, env):
        self.env = env
        self.steps = 0
        self.learning_steps = 0  # steps after a reset(seed=...)
        self.holes = []          # reset(options={"hole": ...}) in order
        self._seeded = False

    def __getattr__(self, name):
        return getattr(self.env, name)

    def reset(self, *, seed=None, options=None):
        self._seeded = seed is not None
        if options and "hole" in options:
            self.holes.append(tuple(options["hole"]))
        return self.env.reset(seed=seed, options=options)

    def step(self, action):
        self.steps += 1
        self.learning_steps += self._seeded
        return self.env.step(action)


CHECKPOINTS = [0, 5, 10, 30, 47]


@pytest.mark.parametrize("method", B.LEARNERS)
def test_every_step_is_counted_and_no_checkpoint_overshoots(method):
    env = Counting(B.make_env("flat", "ball"))
    records = B.learn(method, env, CHECKPOINTS, np.random.default_rng(11))
    assert [c.putts for c in records] == CHECKPOINTS
    cost = (B.CMAES(np.zeros(4), 0.3).lam if method == "cma-es" else 2 * B.DEFAULTS["ars"]["directions"])
    for c in records:
        assert c.spent <= c.putts and c.putts - c.spent < cost  # at most c putts, less than a generation short
    assert env.steps == env.learning_steps == records[-1].spent  # it stops once the last is recorded
    # the estimate at c is the one a budget of c putts gives, and it spent exactly `spent` putts
    for c in records[1:4]:
        alone = Counting(B.make_env("flat", "ball"))
        (only,) = B.learn(method, alone, [c.putts], np.random.default_rng(11))
        assert alone.steps == only.spent == c.spent and np.array_equal(only.theta, c.theta)


def test_test_putts_are_the_curves_situations_and_not_counted():
    situations, test_seed = 6, 7
    envs = []

    def factory():
        envs.append(Counting(B.make_env("arctan", "ball")))
        return envs[-1]

    rows = B.learning_curves("ars", "arctan", "ball", [8, 16], seeds=2, situations=situations, test_seed=test_seed,
                             env_factory=factory)
    want = minigolf.System(field="arctan").field.situations.sample(situations, test_seed)
    np.testing.assert_array_equal(B.evaluation_holes(minigolf.System(field="arctan").field, situations, test_seed), want)
    for env in envs:
        assert env.learning_steps <= 16
        played = np.array(env.holes).reshape(-1, situations, 2)  # one block per evaluated estimate
        assert 1 <= len(played) <= 2
        for block in played:
            np.testing.assert_array_equal(block, want)
        assert env.steps == env.learning_steps + played.size // 2
    assert [(r["learner"], r["run"], r["putts"], r["situations"]) for r in rows] == [
        ("ars", 0, 8, 6), ("ars", 0, 16, 6), ("ars", 1, 8, 6), ("ars", 1, 16, 6)]
    assert all(r["success"] == r["sunk"] / situations for r in rows)


def test_learning_curves_are_deterministic_for_a_seed():
    kw = dict(field="flat", mode="ball", checkpoints=[24, 64], seeds=2, situations=10, test_seed=7)
    a = B.learning_curves("cma-es", seed=1, **kw)
    assert B.learning_curves("cma-es", seed=1, threads=2, **kw) == a  # any thread count
    b = B.learning_curves("cma-es", seed=2, **kw)
    assert a != b
    x = B.learn("ars", B.make_env("flat", "ball"), [32], B.run_seed(1, 0))
    y = B.learn("ars", B.make_env("flat", "ball"), [32], B.run_seed(1, 0))
    z = B.learn("ars", B.make_env("flat", "ball"), [32], B.run_seed(2, 0))
    assert np.array_equal(x[0].theta, y[0].theta) and not np.array_equal(x[0].theta, z[0].theta)


def test_bad_arguments_raise_value_errors():
    with pytest.raises(ValueError, match="strictly increasing"):
        B.learning_curves("ars", checkpoints=[10, 10])
    with pytest.raises(ValueError, match="method"):
        B.learning_curves("ppo")
    with pytest.raises(ValueError, match="unknown option"):
        B.learning_curves("ars", options={"sigma0": 1.0})
    with pytest.raises(ValueError, match="mode"):
        B.make_env("flat", "wheel")


def test_csv_and_summary_follow_the_curves_formats():
    rows = [dict(learner="ars", run=r, putts=10, sunk=s, situations=4, success=s / 4) for r, s in enumerate([0, 1, 2, 4])]
    assert B.curves_csv(rows).splitlines() == ["learner,run,putts,sunk,situations,success", "ars,0,10,0,4,0",
                                               "ars,1,10,1,4,0.25", "ars,2,10,2,4,0.5", "ars,3,10,4,4,1"]
    (s,) = B.summarize(rows)
    v = [0, 0.25, 0.5, 1.0]
    assert s == dict(method="ars", x=10, median=np.quantile(v, 0.5), p10=np.quantile(v, 0.1), p90=np.quantile(v, 0.9))


# ---- the runner
RUNNER = ROOT / "examples" / "baselines.py"


def run_runner(*args):
    env = {**os.environ, "MINIGOLF_BINARY": BINARY, "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, str(RUNNER), *args], capture_output=True, text=True, env=env, timeout=300)


def test_runner_writes_the_curves_summaries_and_the_figure(tmp_path):
    out = tmp_path / "out"
    r = run_runner("--mode", "ball", "--checkpoints", "8,16", "--seeds", "2", "--situations", "4", "--threads", "2",
                   "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""  # no progress off a terminal
    curves = (out / "curves.csv").read_text().splitlines()
    assert curves[0] == "learner,run,putts,sunk,situations,success"
    assert {line.split(",")[0] for line in curves[1:]} == {"self-teach", "cma-es", "ars"} and len(curves) == 1 + 3 * 2 * 2
    summary = (out / "summary.csv").read_text().splitlines()
    assert summary[0] == "method,x,median,p10,p90" and len(summary) == 1 + 3 * 2
    md = (out / "summary.md").read_text()
    assert "| putts | self-teach | cma-es | ars |" in md and "| 16 |" in md
    assert (out / "learning_curves.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in out.iterdir()) == ["curves.csv", "learning_curves.png", "summary.csv", "summary.md"]


@pytest.mark.parametrize("args", [["--checkpoints", "10,5"], ["--seeds", "0"], ["--mode", "wheel"],
                                  ["--field", "no-such-field"], ["--methods", "ppo"], ["--situations", "x"],
                                  ["--bogus"]])
def test_runner_bad_arguments_exit_2_with_one_line(args, tmp_path):
    r = run_runner(*args, "--out", str(tmp_path / "never"))
    assert r.returncode == 2 and r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("baselines: error: ")
    assert not (tmp_path / "never").exists()
