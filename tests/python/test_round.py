"""minigolf.round_env.RoundEnv (minigolf/Round-v0) and the fast putt environment
(minigolf/PuttFast-v0) against Gymnasium's documented rules (test_env.check_env, its copy of
check_env and the passive checker), and against the round they stand for (`minigolf play`)."""
import copy
import pickle

import numpy as np
import pytest

import minigolf
from minigolf.round_env import RoundEnv, observation_names
from minigolf.round_baselines import LinearRoundPolicy, PlannerPolicy, learning_curve, play_episode
from test_env import check_env, data_equivalence


@pytest.mark.parametrize("kwargs", [dict(player="fast"), dict(player="ball", field="flat"),
                                    dict(player="fast", course="obstacles"),
                                    dict(player="fast", field="arctan", situations="box:1.5,2.5:-0.3,0.3:3,3",
                                         balls="box:0.0,0.4:-0.2,0.2:2,2")])
def test_check_env_rules(kwargs):
    env = RoundEnv(**kwargs)
    check_env(env)


def test_one_observation_layout_for_every_field():
    names = observation_names()
    spaces = []
    for field in minigolf.Field.shipped():
        env = RoundEnv(field=field, player="fast")
        assert env.observation_names == names
        obs, _ = env.reset(seed=0)
        assert obs in env.observation_space
        onehot = obs[names.index("field_" + field)]
        assert onehot == 1.0 and obs[-len(minigolf.Field.shipped()) - 1:].sum() == 1.0
        spaces.append(env.observation_space)
    assert all(s == spaces[0] for s in spaces)   # the same bounds too
    assert np.all(spaces[0].high > spaces[0].low)  # no zero-width dimension


def test_the_action_maps_to_a_direction_and_speed_from_the_ball():
    env = RoundEnv(field="flat", player="fast")
    env.reset(seed=0)
    d = env.hole - env.ball
    direction, speed = env.to_physical([0.0, -1.0])
    assert direction == pytest.approx(np.arctan2(d[1], d[0])) and speed == pytest.approx(0.35)
    assert env.to_physical([0.0, 1.0])[1] == pytest.approx(4.2)
    for a in ([0.3, -0.2], [-0.9, 0.7], [0.999, 0.1]):
        assert np.allclose(env.from_physical(env.to_physical(a)), a, atol=1e-6)


def test_strokes_penalties_and_truncation_as_the_round_counts_them():
    env = RoundEnv(field="l-shape", player="fast", max_strokes=3)
    rng = np.random.default_rng(4)
    seen_penalty = False
    for episode in range(6):
        env.reset(seed=episode)
        total = 0.0
        while True:
            before = env.strokes
            obs, reward, terminated, truncated, info = env.step(rng.uniform(-1, 1, 2))
            total += reward
            # -1 a stroke, -1 more out of play, capped at max_strokes
            assert reward == -min(1 + info["penalty"], 3 - before)
            seen_penalty |= info["left_lane"]
            if not info["sunk"]:
                assert env.unwrapped._lane()[0].contains(tuple(info["ball"]))  # the next ball is in play
            if terminated or truncated:
                assert terminated == info["sunk"] and truncated == (not info["sunk"])
                assert -total == info["total_strokes"] <= 3
                break
    assert seen_penalty   # random strokes on the L leave the playable part


def test_the_planner_policy_replays_the_exact_oracle_round():
    """The env's rules are the round's: the planner with exact launches plays `minigolf play
    --player exact-oracle` stroke for stroke (the same strokes per hole, the same rests up to the
    float32 action's rounding)."""
    course = "open-lane"
    played = minigolf.play(course, player="exact-oracle", seed=1, threads=0)
    env = RoundEnv(course=course, player="ball")
    policy = PlannerPolicy(env, angle_error=0.0, speed_error=0.0)
    obs, _ = env.reset(seed=0)
    strokes, rests, sunk = [], [], []
    while True:
        obs, reward, terminated, truncated, info = env.step(policy(obs, env))
        rests.append(tuple(info["rest"]))
        sunk.append(info["sunk"])
        if "hole_strokes" in info:
            strokes.append(info["hole_strokes"])
        if terminated or truncated:
            break
    assert strokes == [h["strokes"] for h in played["holes"]]
    assert sunk == [p["sunk"] for h in played["holes"] for p in h["putts"]]
    # the action is float32: its direction rounds by ~1e-7 rad; rests agree to well under a
    # millimetre on the lane, a few in the cup (a sunk ball's rest rolls round the cup)
    want = np.array([p["rest"] for h in played["holes"] for p in h["putts"]])
    assert len(rests) == len(want) and np.max(np.abs(np.array(rests) - want)) < 0.01
    assert info["total_strokes"] == played["total_strokes"]


def test_pickle_mid_episode_plays_the_same_bits():
    env = RoundEnv(field="bank-shot", player="fast", balls="box:0.0,0.6:-0.4,0.4:3,3")
    env.reset(seed=3)
    env.step(np.array([0.1, -0.5], dtype=np.float32))
    clones = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
    a = np.array([-0.05, -0.2], dtype=np.float32)
    ref = env.step(a)
    for c in clones:
        assert data_equivalence(ref, c.step(a))
    assert all(data_equivalence(env.reset(seed=4), c.reset(seed=4)) for c in clones)  # the same draws


def test_reset_checks_its_options():
    env = RoundEnv(field="flat", player="fast")
    obs, info = env.reset(options={"ball": (0.3, 0.1), "hole": (2.0, 0.2)})
    assert np.allclose(info["ball"], (0.3, 0.1)) and np.allclose(info["hole"], (2.0, 0.2))
    with pytest.raises(ValueError, match="hole"):
        env.reset(options={"hole": (50.0, 0.0)})
    with pytest.raises(ValueError, match="unknown"):
        env.reset(options={"tee": (0.0, 0.0)})
    with pytest.raises(ValueError, match="player"):
        RoundEnv(player="dog")


def test_infos_are_numeric_for_vector_envs():
    env = RoundEnv(field="flat", player="fast")
    _, info = env.reset(seed=0)
    _, _, _, _, step_info = env.step(np.zeros(2, np.float32))
    for i in (info, step_info):
        for k, v in i.items():
            assert isinstance(v, (bool, int, float, np.ndarray)), (k, v)
            if isinstance(v, np.ndarray):
                assert v.dtype.kind in "fib", k


def test_a_numpy_learner_runs_and_records_its_checkpoints():
    env = RoundEnv(field="flat", player="fast", max_strokes=4)
    rows = learning_curve(env, checkpoints=[20, 60], seed=0, test_seeds=range(2), episodes=1)
    assert [r["strokes_played"] for r in rows] == [20, 60]
    assert all(r["spent"] <= r["strokes_played"] and 1 <= r["mean_strokes"] <= 4 for r in rows)
    policy = LinearRoundPolicy(env)
    assert policy.dim == 10
    theta = np.zeros(10)
    theta[4], theta[9] = 1.0, -1.0   # the biases: the direction scaled by 0.1, the speed not
    assert np.allclose(policy.act(theta, env.reset(seed=0)[0]), [0.1, -1.0])


# ---- PuttFast-v0 and the arm-faithful action
def test_putt_fast_passes_the_rules_and_agrees_with_the_mujoco_ball():
    fast, ball = minigolf.make("minigolf/PuttFast-v0", field="arctan"), minigolf.make("minigolf/PuttBall-v0", field="arctan")
    check_env(fast)
    rng = np.random.default_rng(0)
    agree = 0
    for seed in range(20):
        a = rng.uniform(-1, 1, 2).astype(np.float32)
        fast.reset(seed=seed), ball.reset(seed=seed)
        f, b = fast.step(a), ball.step(a)
        agree += f[4]["sunk"] == b[4]["sunk"] and np.hypot(*np.subtract(f[4]["rest_position"], b[4]["rest_position"])) < 0.01
    assert agree >= 19


def test_club_actions_launch_through_the_robot_s_skill():
    env = minigolf.env.PuttEnv(field="flat", mode="fast", normalize_actions=True, club_action=True, skill_putts=4)
    check_env(env)
    env.reset(seed=0)
    _, _, _, _, info = env.step(np.array([0.0, 0.0], np.float32))
    hit, launch = info["club"], info["action"]
    skill = env._skills[0]
    assert launch[1] == pytest.approx(skill.launch_speed(hit[1])) and launch[1] > hit[1]  # the putter's gain
    with pytest.raises(ValueError, match="club_action"):
        minigolf.env.PuttEnv(mode="arm", club_action=True)


def test_registered_ids():
    from minigolf.env import ENTRY_POINTS, REGISTERED
    assert set(REGISTERED) == set(ENTRY_POINTS) >= {"minigolf/Round-v0", "minigolf/PuttFast-v0"}
    env = minigolf.make("minigolf/Round-v0", player="fast")
    assert isinstance(env, RoundEnv) and env.holes[0]["field_name"] == "bank-shot"
    assert minigolf.make("minigolf/PuttFast-v0").mode == "fast"


# ---- with Gymnasium installed (not in Debian 12: these skip without it)
def _gymnasium():
    try:
        import gymnasium as gym
    except ImportError:
        pytest.skip("gymnasium is not installed (not in Debian 12); test_env.check_env is its copy")
    return gym


def test_gymnasium_check_env_and_same_step_vector_envs():
    gym = _gymnasium()
    from gymnasium.utils.env_checker import check_env as gym_check_env
    from gymnasium.vector import AutoresetMode
    for env_id, kwargs in (("minigolf/Round-v0", dict(player="fast")), ("minigolf/PuttFast-v0", {})):
        env = gym.make(env_id, **kwargs)
        gym_check_env(env.unwrapped, skip_render_check=True)
        assert env.get_wrapper_attr("to_physical") is not None  # reachable through the wrappers
    vec = minigolf.make_vec("minigolf/PuttFast-v0", num_envs=2)
    assert vec.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    vec.reset(seed=[1, 2])
    for _ in range(3):  # every vector step plays a putt in every sub-environment
        _, _, terminated, _, info = vec.step(np.zeros((2, 2), dtype=np.float32))
        assert np.all(terminated) and "final_obs" in info
    vec.close()
