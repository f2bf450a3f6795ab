"""minigolf.Renderer and PuttEnv's render modes. Drawing needs a display: ctest runs this file under
`xvfb-run -a` (python_render); without a display every test skips."""
import os
import pickle

import numpy as np
import pytest

import minigolf
from minigolf.env import PuttEnv

pytestmark = pytest.mark.skipif(not os.environ.get("DISPLAY"), reason="no display (ctest runs this under xvfb-run)")

SIZE = (160, 120)


def test_the_renderer_draws_a_world_without_changing_it():
    system = minigolf.System(field="flat")
    data = system.make_data()
    r = minigolf.Renderer(system.arm_world, *SIZE, camera="top")
    qpos = np.array(data.arm.qpos)
    on_tee = r.render(data.arm)
    assert on_tee.shape == (SIZE[1], SIZE[0], 3) and on_tee.dtype == np.uint8
    assert r.width == SIZE[0] and r.height == SIZE[1]
    moved = r.render(data.arm, ball=(1.5, 0.2, 0.03), path=np.array([[0.0, 0.0], [1.5, 0.2]]))
    assert np.count_nonzero(np.any(moved != on_tee, axis=2)) > 20  # the ball moved, the path is drawn
    assert np.array_equal(np.array(data.arm.qpos), qpos)  # the drawn data is a copy
    assert np.array_equal(r.render(data.arm), on_tee)  # deterministic
    with pytest.raises(ValueError, match="another world"):
        r.render(data.ball)
    with pytest.raises(ValueError, match="path"):
        r.render(data.arm, path=np.zeros((3, 4)))
    with pytest.raises(ValueError, match="off screen"):
        r.show(data.arm)
    other = minigolf.Renderer(system.arm_world, *SIZE, camera="top")
    r.close(), r.close()
    assert r.closed
    assert np.array_equal(other.render(data.arm), on_tee)  # closing one renderer leaves the others
    other.close()
    with pytest.raises(ValueError, match="closed"):
        r.render(data.arm)
    with pytest.raises(ValueError, match="camera"):
        minigolf.Renderer(system.arm_world, camera="nope")
    with pytest.raises(ValueError, match="image size"):
        minigolf.Renderer(system.arm_world, 8, 8)


def run(env, seed, action):
    obs, _ = env.reset(seed=seed)
    return obs, env.step(np.asarray(action, dtype=np.float32))


@pytest.mark.parametrize("mode", ["ball", "arm"])
def test_rgb_array_frames_and_the_same_putt_as_without_rendering(mode):
    action = [0.02, 1.6] if mode == "arm" else [0.0, 1.3]
    plain = PuttEnv(field="flat", mode=mode)
    drawn = PuttEnv(field="flat", mode=mode, render_mode="rgb_array", render_size=SIZE)
    assert drawn.metadata["render_fps"] > 0 and "rgb_array" in drawn.metadata["render_modes"]
    drawn.reset(seed=2)
    start = drawn.render()
    assert start.shape == (SIZE[1], SIZE[0], 3) and start.dtype == np.uint8
    _, ref = run(plain, 2, action)
    _, got = run(drawn, 2, action)
    for k in ("closest_approach", "rest_position", "end", "sunk"):
        assert np.array_equal(ref[4][k], got[4][k]), k  # rendering never changes a putt
    assert ref[1] == got[1]
    end = drawn.render()
    assert np.count_nonzero(np.any(end != start, axis=2)) > 20
    drawn.close()
    assert drawn._renderer is None
    again = drawn.render()  # a closed env renders again with a new renderer
    assert np.array_equal(again, end)
    drawn.close()


def test_rgb_array_list_has_every_frame_of_the_roll():
    env = PuttEnv(field="arctan", mode="ball", render_mode="rgb_array_list", render_size=SIZE, camera="top")
    env.reset(seed=1)
    _, _, _, _, info = env.step(np.array([0.1, 1.8], dtype=np.float32))
    frames = env.render()
    roll = minigolf.System(field="arctan").putt(0.1, 1.8, hole=info["hole"], ball_only=True, record_interval=0.01)
    duration = roll.trajectory[-1, 0] - roll.trajectory[0, 0]
    fps = env.metadata["render_fps"]
    # reset's frame, one per 1/fps of the roll (both ends), and the last
    assert len(frames) == 1 + (int(np.floor(duration * fps + 1e-9)) + 1) + 1
    assert all(f.shape == (SIZE[1], SIZE[0], 3) for f in frames)
    changed = [np.count_nonzero(np.any(a != b, axis=2)) for a, b in zip(frames[1:], frames[2:])]
    assert sum(c > 0 for c in changed) > len(changed) // 2  # the ball moves from frame to frame
    assert env.render() == []  # handed over
    env.close()


def test_human_mode_plays_the_putt_in_a_window_and_the_env_still_pickles():
    env = PuttEnv(field="flat", mode="ball", render_mode="human", render_size=SIZE)
    env.reset(seed=0)
    _, reward, terminated, _, _ = env.step(np.array([0.0, 0.6], dtype=np.float32))
    assert terminated and env.render() is None
    clone = pickle.loads(pickle.dumps(env))  # the window is not pickled; the clone opens its own
    assert clone._renderer is None
    clone.reset(seed=0)
    assert clone.step(np.array([0.0, 0.6], dtype=np.float32))[1] == reward
    env.close(), clone.close()


def check_render_return(mode, result):
    """gymnasium.utils.passive_env_checker's rules for what render() returns in each mode."""
    if mode == "human":
        assert result is None
    elif mode == "rgb_array":
        assert isinstance(result, np.ndarray) and result.dtype == np.uint8
        assert result.ndim == 3 and result.shape[2] == 3
    elif mode.endswith("_list"):
        assert isinstance(result, list)
        for item in result:
            check_render_return(mode[: -len("_list")], item)


def check_render(env):
    """env_render_passive_checker: declared modes and fps, the env's mode among them, the return."""
    modes = env.metadata.get("render_modes")
    assert isinstance(modes, (list, tuple)) and all(isinstance(m, str) for m in modes)
    fps = env.metadata.get("render_fps")
    assert isinstance(fps, (int, float, np.integer, np.floating)) and fps > 0
    assert env.render_mode is None or env.render_mode in modes
    result = env.render()
    if env.render_mode is not None:
        check_render_return(env.render_mode, result)


@pytest.mark.parametrize("mode", PuttEnv.metadata["render_modes"])
def test_every_declared_render_mode_follows_gymnasiums_rules(mode):
    env = minigolf.make("minigolf/PuttBall-v0", render_mode=mode, render_size=SIZE)
    env.reset(seed=0)
    check_render(env)
    env.step(env.action_space.sample())
    check_render(env)
    env.close(), env.close()  # closing twice is allowed


def test_gymnasium_check_env_with_its_render_checks():
    try:
        import gymnasium as gym
        from gymnasium.utils.env_checker import check_env
    except ImportError:
        pytest.skip("gymnasium is not installed (not in Debian 12); the rules above are its copy")
    env = gym.make("minigolf/PuttBall-v0", render_mode="rgb_array", render_size=SIZE)
    check_env(env.unwrapped)  # renders every declared mode through env.spec.make


@pytest.mark.parametrize("player", ["fast", "arm"])
def test_the_round_environment_draws_the_lane_the_ball_and_its_path(player):
    from minigolf.round_env import RoundEnv
    env = RoundEnv(field="bank-shot", player=player, render_mode="rgb_array", render_size=SIZE)
    assert env.metadata["render_fps"] > 0 and env.metadata["render_modes"] == ["rgb_array"]
    assert RoundEnv(field="bank-shot", player=player).render() is None
    env.reset(seed=0)
    start = env.render()
    assert start.shape == (SIZE[1], SIZE[0], 3) and start.dtype == np.uint8
    plain = RoundEnv(field="bank-shot", player=player)
    plain.reset(seed=0)
    a = np.array([0.1, -0.3], dtype=np.float32)
    ref, got = plain.step(a), env.step(a)
    assert np.array_equal(ref[0], got[0]) and ref[1] == got[1]  # drawing never changes a stroke
    after = env.render()
    assert np.count_nonzero(np.any(after != start, axis=2)) > 20  # the ball moved, its path drawn
    env.close()
    assert np.array_equal(env.render(), after)  # a closed env draws again
    env.close()


def test_a_system_with_cameras_putts_as_the_truth(tmp_path):
    """System(perception="camera"): the module reads the rig's cameras (a 320x240 copy of the
    shipped rig at 30 Hz here); the putt is played as with the simulator's truth."""
    rig = tmp_path / "small.yaml"
    text = open(os.path.join(os.path.dirname(__file__), "..", "..", "data", "rigs", "stereo.yaml")).read()
    rig.write_text(text.replace("width: 640", "width: 320").replace("height: 480", "height: 240").replace("rate_hz: 60", "rate_hz: 30"))
    truth = minigolf.System(field="flat").putt(0.0, 1.2)
    seen = minigolf.System(field="flat", perception="camera", rig=str(rig)).putt(0.0, 1.2)
    assert seen.sunk == truth.sunk
    assert np.allclose(seen.rest_position, truth.rest_position, atol=0.05)
