"""minigolf.env.PuttEnv against the rules Gymnasium's check_env enforces (gymnasium is not in
Debian 12, so they are written out here), and its reproducibility."""
import copy
import inspect
import subprocess
import sys

import numpy as np
import pytest

import minigolf
from minigolf.env import Box, PuttEnv
from conftest import ROOT


def data_equivalence(a, b):
    """gymnasium.utils.env_checker.data_equivalence for the types this env returns."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(data_equivalence(a[k], b[k]) for k in a)
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(data_equivalence(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray):
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b, equal_nan=True)
    if isinstance(a, float) and np.isnan(a):
        return isinstance(b, float) and np.isnan(b)
    return a == b


def check_space(space):
    """check_env: spaces are Box-like, sample() lies in them, contains() rejects what lies outside."""
    for attr in ("shape", "dtype", "low", "high", "sample", "contains", "seed"):
        assert hasattr(space, attr), attr
    assert space.low.shape == space.shape == space.high.shape
    assert space.low.dtype == space.dtype and space.high.dtype == space.dtype
    assert np.all(space.low <= space.high) and np.all(np.isfinite(space.low)) and np.all(np.isfinite(space.high))
    space.seed(7)
    a = [space.sample() for _ in range(20)]
    space.seed(7)
    b = [space.sample() for _ in range(20)]
    assert all(np.array_equal(x, y) for x, y in zip(a, b))  # seeded sampling is reproducible
    assert all(space.contains(x) and x in space and x.dtype == space.dtype for x in a)
    assert not space.contains(space.high + 1.0)
    assert not space.contains(space.low - 1.0)
    assert not space.contains(np.zeros(space.shape[0] + 1))
    assert not space.contains(np.full(space.shape, np.nan))


def check_env(env):
    """The checks of gymnasium.utils.env_checker.check_env (0.29) and the passive checker."""
    # spaces
    check_space(env.action_space)
    check_space(env.observation_space)
    # reset: keyword-only seed and options
    params = inspect.signature(env.reset).parameters
    assert "seed" in params and params["seed"].default is None
    assert "options" in params and params["options"].default is None
    # check_reset_return_type / info
    result = env.reset()
    assert isinstance(result, tuple) and len(result) == 2
    obs, info = result
    assert isinstance(info, dict)
    assert isinstance(obs, np.ndarray) and obs.dtype == env.observation_space.dtype
    assert env.observation_space.contains(obs)
    # check_reset_seed
    obs_1, _ = env.reset(seed=123)
    assert obs_1 in env.observation_space
    assert isinstance(env.unwrapped.np_random, np.random.Generator)
    seed_123_rng = copy.deepcopy(env.unwrapped._np_random)
    obs_2, _ = env.reset(seed=123)
    assert data_equivalence(obs_1, obs_2)
    assert env.unwrapped._np_random.bit_generator.state == seed_123_rng.bit_generator.state
    obs_3, _ = env.reset(seed=456)
    assert env.unwrapped._np_random.bit_generator.state != seed_123_rng.bit_generator.state
    # reset(seed=None) continues the generator: it does not reseed it
    generator = env.unwrapped._np_random
    state = copy.deepcopy(generator.bit_generator.state)
    env.reset(seed=None)
    assert env.unwrapped._np_random is generator and generator.bit_generator.state != state
    # check_reset_options
    env.reset(options={})
    # step: passive checker's return types
    env.reset(seed=5)
    action = env.action_space.sample()
    result = env.step(action)
    assert isinstance(result, tuple) and len(result) == 5
    obs, reward, terminated, truncated, info = result
    assert isinstance(obs, np.ndarray) and obs.dtype == env.observation_space.dtype
    assert env.observation_space.contains(obs)
    assert isinstance(reward, (float, int, np.floating, np.integer)) and np.isfinite(reward)
    assert isinstance(terminated, (bool, np.bool_)) and isinstance(truncated, (bool, np.bool_))
    assert isinstance(info, dict)
    # check_step_determinism
    env.action_space.seed(42)
    action = env.action_space.sample()
    env.reset(seed=11)
    r1 = env.step(action)
    env.reset(seed=11)
    r2 = env.step(action)
    for x, y in zip(r1, r2):
        assert data_equivalence(x, y), (x, y)
    # render and close
    assert isinstance(env.metadata.get("render_modes"), list)
    assert env.render_mode is None or env.render_mode in env.metadata["render_modes"]
    env.render()
    env.close()


@pytest.mark.parametrize("kwargs", [dict(field="flat", mode="ball"), dict(field=["flat", "regular-hill"], mode="ball"),
                                    dict(field="flat", mode="arm")])
def test_check_env_rules(kwargs):
    env = PuttEnv(**kwargs)
    try:
        import gymnasium  # noqa: F401
        assert isinstance(env, gymnasium.Env)
    except ImportError:
        pass
    check_env(env)


def test_observation_action_and_reward():
    env = PuttEnv(field="flat", mode="ball")
    system = minigolf.System(field="flat")
    obs, info = env.reset(seed=3)
    tee = np.array(system.field.tee)
    assert np.array_equal(obs, np.array(info["hole"]) - tee)
    xi = obs
    aim = float(np.arctan2(xi[1], xi[0]))
    obs2, reward, terminated, truncated, info = env.step(np.array([aim, 1.2]))
    direct = system.putt(aim, 1.2, hole=tuple(info["hole"]), ball_only=True)
    assert reward == (1.0 if direct.sunk else 0.0) and terminated and not truncated
    assert info["closest_approach"] == direct.closest_approach
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.array([aim, 1.2]))  # one putt per episode
    env.reset(seed=3)
    _, _, _, _, info = env.step(np.array([10.0, -1.0]))  # clipped into the safe envelope
    assert info["clipped"] and env.action_space.contains(np.array(info["action"]))
    env.reset()
    with pytest.raises(ValueError, match="action"):
        env.step(np.array([np.nan, 1.0]))
    with pytest.raises(ValueError, match="mode"):
        PuttEnv(mode="fly")
    # the field id in the observation with several fields
    multi = PuttEnv(field=["flat", "regular-hill"], mode="ball")
    seen = {multi.reset(seed=s)[0][2] for s in range(20)}
    assert seen == {0.0, 1.0}
    obs, _ = multi.reset(options={"field": 1, "hole": (2.0, 0.05)})
    assert obs[2] == 1.0


def test_a_plant_is_the_world_the_episodes_happen_in(tmp_path):
    plant = tmp_path / "slow.yaml"
    plant.write_text("field:\n  rolling_resistance_scale: 1.2\n")
    real = PuttEnv(field="flat", mode="ball", plant=str(plant))
    nominal = PuttEnv(field="flat", mode="ball")
    a = np.array([0.0, 2.4])
    real.reset(seed=1), nominal.reset(seed=1)
    _, _, _, _, ir = real.step(a)
    _, _, _, _, inom = nominal.step(a)
    assert ir["hole"] == inom["hole"]  # the robot sees the same situation
    assert ir["closest_approach"] != inom["closest_approach"]  # the ball rolls in another world
    with pytest.raises(ValueError, match="plant"):
        PuttEnv(field="flat", mode="ball", plant=str(tmp_path / "missing.yaml"))


def test_reproducible_with_a_seed():
    def episodes(seed):
        env = PuttEnv(field="regular-hill", mode="ball")
        env.action_space.seed(seed)
        out = []
        obs, _ = env.reset(seed=seed)
        for _ in range(5):
            a = env.action_space.sample()
            o, r, term, trunc, info = env.step(a)
            out.append((obs.tolist(), a.tolist(), r, info["closest_approach"]))
            obs, _ = env.reset()
        return out
    assert episodes(9) == episodes(9)
    assert episodes(9) != episodes(10)


def test_the_example_trains_a_policy():
    r = subprocess.run([sys.executable, str(ROOT / "examples" / "train_policy.py"), "--test", "40"],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    last = r.stdout.strip().splitlines()[-1]
    assert last.startswith("success ratio")
    ratio = float(last.split()[2])
    assert ratio >= 0.8, r.stdout  # a linear policy learns the flat field (its start: 0)


def test_reset_refuses_a_hole_on_the_tee_or_off_the_lane():
    env = PuttEnv(field="flat", mode="ball")
    tee = tuple(env.systems[0].field.tee)
    for hole in (tee, (9.0, 0.0)):
        with pytest.raises(ValueError, match="options\\['hole'\\]"):
            env.reset(seed=0, options={"hole": hole})
