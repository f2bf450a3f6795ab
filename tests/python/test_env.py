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
    env = PuttEnv(field="flat", mode="ball", observation="varying")
    system = minigolf.System(field="flat")
    obs, info = env.reset(seed=3)
    tee = np.array(system.field.tee)
    xi = np.array(info["hole"]) - tee
    assert np.array_equal(info["xi"], xi) and info["xi"].dtype == np.float64
    assert env.observation_names == ("xi_y",)  # xi_x is 2.0 for every situation of the flat line
    assert obs.dtype == np.float32 and obs.shape == (1,) and obs[0] == np.float32(xi[1])
    aim = float(np.arctan2(xi[1], xi[0]))
    obs2, reward, terminated, truncated, info = env.step(np.array([aim, 1.2]))
    direct = system.putt(aim, 1.2, hole=tuple(info["hole"]), ball_only=True)
    assert reward == (1.0 if direct.sunk else 0.0) and terminated and not truncated
    assert info["closest_approach"] == direct.closest_approach and info["sunk"] == direct.sunk
    with pytest.raises(RuntimeError, match="reset"):
        env.step(np.array([aim, 1.2]))  # one putt per episode
    env.reset(seed=3)
    _, _, _, _, info = env.step(np.array([10.0, -1.0]))  # clipped into the safe envelope
    e = system.envelope
    assert info["clipped"] and tuple(info["action"]) == (e["angle_max"], e["speed_min"])
    env.reset()
    for bad in (np.array([np.nan, 1.0]), np.zeros(3), "left", None):
        with pytest.raises(ValueError, match="action"):
            env.step(bad)
    with pytest.raises(ValueError, match="mode"):
        PuttEnv(mode="fly")
    # the field id in the observation with several fields
    multi = PuttEnv(field=["flat", "regular-hill"], mode="ball", observation="varying")
    assert multi.observation_names[-1] == "field"
    seen = {multi.reset(seed=s)[0][-1] for s in range(20)}
    assert seen == {0.0, 1.0}
    obs, _ = multi.reset(options={"field": 1, "hole": (2.0, 0.05)})
    assert obs[-1] == 1.0


def test_one_observation_layout_for_every_field():
    """The default layout: xi_x, xi_y and the field's one-hot, the same names and bounds on every
    shipped field (a policy moves between fields); its xi is the hole's."""
    names = tuple(sorted(minigolf.Field.shipped()))
    envs = [PuttEnv(field=n, mode="ball") for n in names] + [PuttEnv(field=list(names[:2]), mode="ball")]
    layout = ("xi_x", "xi_y") + tuple(f"field_{n}" for n in names) + ("field_other",)
    for env in envs:
        assert env.observation_names == layout and env.observation_space == envs[0].observation_space
    for n, env in zip(names, envs):
        obs, info = env.reset(seed=2)
        assert np.array_equal(obs[:2], np.float32(info["xi"]))
        onehot = obs[2:]
        assert onehot.sum() == 1.0 and onehot[names.index(n)] == 1.0
    multi = envs[-1]
    assert {tuple(multi.reset(seed=s)[0][2:4]) for s in range(10)} == {(1.0, 0.0), (0.0, 1.0)}


def test_spaces_are_float32_without_zero_width_dimensions():
    for name in minigolf.Field.shipped():
        for mode in ("ball", "arm"):
            env = PuttEnv(field=name, mode=mode)
            for space in (env.observation_space, env.action_space):
                assert space.dtype == np.float32
                assert np.all(space.high - space.low > 0), (name, space)
            assert len(env.observation_names) == env.observation_space.shape[0]
            one = PuttEnv(field=name, mode=mode, observe_field=True, observation="varying")  # one field's index
            assert np.all(one.observation_space.high - one.observation_space.low > 0)
            varying = PuttEnv(field=name, mode=mode, observation="varying")
            assert np.all(varying.observation_space.high - varying.observation_space.low > 0)
            # every action of the space is a putt inside the envelope, exactly
            e = env.systems[0].envelope
            assert env.action_space.low[0] >= e["angle_min"] and env.action_space.high[0] <= e["angle_max"]
            assert env.action_space.low[1] >= e["speed_min"] and env.action_space.high[1] <= e["speed_max"]
            # every observation lies in the space; a copy of Gymnasium's RescaleObservation stays finite
            low, high = env.observation_space.low, env.observation_space.high
            for seed in range(30):
                obs, _ = env.reset(seed=seed)
                assert env.observation_space.contains(obs), (name, obs)
                scaled = 2.0 * (obs - low) / (high - low) - 1.0
                assert np.all(np.isfinite(scaled)) and np.all(np.abs(scaled) <= 1.0 + 1e-6)


def rescale_action(env, a, min_action=-1.0, max_action=1.0):
    """gymnasium.wrappers.RescaleAction's map of an action in [min, max] onto env.action_space."""
    low, high = env.action_space.low, env.action_space.high
    gradient = (high - low) / (max_action - min_action)
    intercept = gradient * -min_action + low
    return np.clip(gradient * np.asarray(a, dtype=env.action_space.dtype) + intercept, low, high)


def test_actions_normalised_or_rescaled_reach_the_envelope_unclipped():
    system = minigolf.System(field="flat")
    e = system.envelope
    norm = PuttEnv(field="flat", mode="ball", normalize_actions=True)
    assert np.array_equal(norm.action_space.low, [-1, -1]) and np.array_equal(norm.action_space.high, [1, 1])
    assert tuple(norm.to_physical([1, 1])) == (e["angle_max"], e["speed_max"])
    assert tuple(norm.to_physical([-1, -1])) == (e["angle_min"], e["speed_min"])
    rng = np.random.default_rng(0)
    a = rng.uniform(-1, 1, size=(50, 2)).astype(np.float32)
    back = np.array([norm.from_physical(norm.to_physical(x)) for x in a])
    assert np.max(np.abs(back - a)) < 1e-6
    for corner in ([1, 1], [-1, -1], [1, -1]):
        norm.reset(seed=1)
        _, _, _, _, info = norm.step(np.array(corner, dtype=np.float32))
        assert not info["clipped"]
    physical = PuttEnv(field="flat", mode="ball")
    for corner in ([1, 1], [-1, -1]):
        physical.reset(seed=1)
        _, _, _, _, info = physical.step(rescale_action(physical, corner))
        assert not info["clipped"], info["action"]
        assert all(lo <= v <= hi for v, lo, hi in zip(info["action"], (e["angle_min"], e["speed_min"]),
                                                      (e["angle_max"], e["speed_max"])))


def test_shaped_reward_is_the_closest_approach_with_its_parts():
    sparse = PuttEnv(field="flat", mode="ball")
    shaped = PuttEnv(field="flat", mode="ball", reward="shaped", reward_scale=0.5)
    for action in ([0.0, 1.0], [0.05, 2.5], [0.0, 1.33]):
        sparse.reset(seed=4), shaped.reset(seed=4)
        _, rs, _, _, i_s = sparse.step(np.array(action))
        _, rh, _, _, i_h = shaped.step(np.array(action))
        assert i_s["closest_approach"] == i_h["closest_approach"]
        assert rh == sum(i_h["reward_parts"].values()) and rs == sum(i_s["reward_parts"].values())
        if i_h["sunk"]:
            assert rh == 1.0 and rs == 1.0
        else:
            assert rs == 0.0 and rh == pytest.approx(-i_h["closest_approach"] / 0.5, rel=0, abs=1e-15)
    for bad in (dict(reward="dense"), dict(reward_scale=0.0), dict(reward_scale=float("nan")),
                dict(max_duration=-1.0), dict(max_duration="long"), dict(render_mode="ascii"), dict(camera="nope"), dict(render_size=(8, 8))):
        with pytest.raises(ValueError, match=list(bad)[0]):
            PuttEnv(field="flat", mode="ball", **bad)


def test_a_plant_is_the_world_the_episodes_happen_in(tmp_path):
    plant = tmp_path / "slow.yaml"
    plant.write_text("format_version: 1\nfield:\n  rolling_resistance_scale: 1.2\n")
    real = PuttEnv(field="flat", mode="ball", plant=str(plant))
    nominal = PuttEnv(field="flat", mode="ball")
    a = np.array([0.0, 2.4])
    real.reset(seed=1), nominal.reset(seed=1)
    _, _, _, _, ir = real.step(a)
    _, _, _, _, inom = nominal.step(a)
    assert np.array_equal(ir["hole"], inom["hole"])  # the robot sees the same situation
    assert ir["closest_approach"] != inom["closest_approach"]  # the ball rolls in another world
    with pytest.raises(ValueError, match="plant"):
        PuttEnv(field="flat", mode="ball", plant=str(tmp_path / "missing.yaml"))


def test_a_pickled_environment_keeps_the_plant_it_was_made_with(tmp_path):
    """Unpickling re-read the plant file, so a clone played another world."""
    import pickle
    plant = tmp_path / "slow.yaml"
    plant.write_text("format_version: 1\nfield:\n  rolling_resistance_scale: 1.2\n")
    env = PuttEnv(field="flat", mode="ball", plant=str(plant))
    payload = pickle.dumps(env)
    plant.write_text("format_version: 1\nfield:\n  rolling_resistance_scale: 0.5\n")  # changed after
    clone = pickle.loads(payload)
    assert clone.systems[0].plant == env.systems[0].plant  # the same path and content hash
    a = np.array([0.0, 2.4])
    env.reset(seed=1), clone.reset(seed=1)
    assert env.step(a)[4]["closest_approach"] == clone.step(a)[4]["closest_approach"]
    plant.unlink()
    assert pickle.loads(payload).systems[0].plant == env.systems[0].plant  # even without the file


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


def test_reset_checks_the_hole_against_the_situations_and_widens_on_request():
    env = PuttEnv(field="flat", mode="ball")
    with pytest.raises(ValueError, match="outside this environment's situations"):
        env.reset(seed=0, options={"hole": (2.5, 0.0)})  # on the lane, but off the flat line
    for bad in ({"hole": "here"}, {"hole": (2.0,)}, {"hole": (2.0, float("nan"))}):
        with pytest.raises(ValueError, match="options\\['hole'\\]"):
            env.reset(seed=0, options=bad)
    with pytest.raises(ValueError, match="unknown key"):
        env.reset(seed=0, options={"hole_position": (2.0, 0.0)})
    with pytest.raises(ValueError, match="options\\['field'\\]"):
        env.reset(seed=0, options={"field": True})
    multi = PuttEnv(field=["flat", "arctan"], mode="ball")  # each field's own situations count
    multi.reset(seed=0, options={"field": 1, "hole": (2.1, 0.2)})
    with pytest.raises(ValueError, match="on flat"):
        multi.reset(seed=0, options={"field": 0, "hole": (2.1, 0.2)})
    wide = PuttEnv(field="flat", mode="ball", situations="box:1.5,2.5:-0.3,0.3:3,3")
    assert wide.observation_names[:2] == ("xi_x", "xi_y")
    obs, info = wide.reset(seed=0, options={"hole": (2.5, 0.0)})
    assert wide.observation_space.contains(obs) and tuple(info["hole"]) == (2.5, 0.0)
    holes = np.array([wide.reset(seed=s)[1]["hole"] for s in range(40)])
    assert holes[:, 0].min() >= 1.5 and holes[:, 0].max() <= 2.5 and np.ptp(holes[:, 0]) > 0.5
    with pytest.raises(ValueError, match="situations"):
        PuttEnv(field="flat", mode="ball", situations="box:1.5,9:-0.3,0.3:3,3")  # off the lane


def test_registered_ids_without_gymnasium():
    from minigolf.env import REGISTERED, MAX_EPISODE_STEPS
    assert set(REGISTERED) == {"minigolf/Putt-v0", "minigolf/PuttBall-v0", "minigolf/PuttFast-v0",
                               "minigolf/Round-v0"} and MAX_EPISODE_STEPS == 1
    arm, ball = minigolf.make("minigolf/Putt-v0"), minigolf.make("minigolf/PuttBall-v0")
    assert arm.mode == "arm" and ball.mode == "ball"
    for env in (arm, ball):
        assert env.normalize_actions and env.reward_mode == "shaped"
        check_env(env)
    assert minigolf.make("minigolf/PuttBall-v0", field="arctan").systems[0].field.name == "arctan"
    with pytest.raises(ValueError, match="unknown id"):
        minigolf.make("minigolf/Fly-v0")


def episode_bits(env, seeds, actions):
    out = []
    for seed, a in zip(seeds, actions):
        obs, _ = env.reset(seed=seed)
        o, r, term, trunc, info = env.step(a)
        out.append((obs.tobytes(), o.tobytes(), r, term, trunc, info["closest_approach"], tuple(info["rest_position"])))
    return out


def test_pickle_and_deepcopy_rebuild_the_same_environment():
    import pickle
    env = PuttEnv(field="regular-hill", mode="ball", normalize_actions=True, reward="shaped")
    env.reset(seed=21)
    env.action_space.seed(3)
    clones = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
    a = env.action_space.sample()
    ref = env.step(a)
    for c in clones:  # the clone is mid-episode with the same hole and generator
        assert c.systems[0] is not env.systems[0]
        assert data_equivalence(ref, c.step(a))
    next_hole = env.reset()[1]["hole"]
    assert all(np.array_equal(c.reset()[1]["hole"], next_hole) for c in clones)
    seeds, actions = [1, 2, 3], [np.array([0.1, -0.3]), np.array([-0.5, 0.2]), np.array([0.0, 0.0])]
    assert episode_bits(pickle.loads(pickle.dumps(env)), seeds, actions) == episode_bits(env, seeds, actions)


def _play_in_child(payload):
    import pickle as _pickle
    env = _pickle.loads(payload)
    return episode_bits(env, [5, 6], [np.array([0.2, 0.1]), np.array([-0.1, -0.4])])


def test_a_pickled_environment_plays_the_same_bits_in_a_spawned_process():
    """What AsyncVectorEnv does with the spawn start method: the env crosses by pickle."""
    import multiprocessing
    import pickle
    env = minigolf.make("minigolf/PuttBall-v0", field="arctan")
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        child = pool.apply(_play_in_child, (pickle.dumps(env),))
    assert child == episode_bits(env, [5, 6], [np.array([0.2, 0.1]), np.array([-0.1, -0.4])])


def _gymnasium():
    try:
        import gymnasium as gym
    except ImportError:
        pytest.skip("gymnasium is not installed (not in Debian 12); the rules above are its copy")
    return gym


def test_gymnasium_make_and_check_env():
    gym = _gymnasium()
    from gymnasium.utils.env_checker import check_env as gym_check_env
    for env_id in ("minigolf/Putt-v0", "minigolf/PuttBall-v0"):
        env = gym.make(env_id)
        assert env.spec.max_episode_steps == 1
        assert isinstance(env.unwrapped, PuttEnv) and isinstance(env.unwrapped, gym.Env)
        gym_check_env(env.unwrapped, skip_render_check=True)
        obs, _ = env.reset(seed=0)
        _, _, terminated, _, _ = env.step(env.action_space.sample())
        assert terminated
    for kwargs in (dict(field="flat", mode="ball"), dict(field=["flat", "arctan"], mode="ball")):
        gym_check_env(PuttEnv(**kwargs), skip_render_check=True)
    wrapped = gym.wrappers.RescaleObservation(PuttEnv(field="flat", mode="ball"), -1.0, 1.0)
    obs, _ = wrapped.reset(seed=0)
    assert np.all(np.isfinite(obs))


def test_gymnasium_vector_envs_sync_and_async():
    gym = _gymnasium()
    seeds = [3, 4]
    sync = gym.make_vec("minigolf/PuttBall-v0", num_envs=2, vectorization_mode="sync")
    obs_s, _ = sync.reset(seed=seeds)
    actions = np.array([[0.1, 0.0], [-0.2, 0.3]], dtype=np.float32)
    out_s = sync.step(actions)
    # a spawned child has not imported minigolf: "minigolf:" imports it before the lookup
    asyn = gym.vector.AsyncVectorEnv([lambda: gym.make("minigolf:minigolf/PuttBall-v0")] * 2, context="spawn")
    obs_a, _ = asyn.reset(seed=seeds)
    out_a = asyn.step(actions)
    assert np.array_equal(obs_s, obs_a) and np.array_equal(out_s[1], out_a[1])
    single = gym.make("minigolf/PuttBall-v0")
    for k in range(2):
        o, _ = single.reset(seed=seeds[k])
        assert np.array_equal(o, obs_s[k])
        assert single.step(actions[k])[1] == out_s[1][k]
    sync.close(), asyn.close()
