"""The minigolf Python module against the CLI and against itself (tests/python)."""
import json
import subprocess
import threading
import time

import numpy as np
import pytest

import minigolf
from conftest import BINARY, ROOT


def cli(*args, check=True):
    r = subprocess.run([BINARY, *args], capture_output=True, text=True, timeout=600)
    if check and r.returncode != 0:
        raise AssertionError(f"minigolf {' '.join(args)} failed: {r.stderr}")
    return r


def cli_error(*args):
    """The CLI's one-line message for a bad input (after 'minigolf: error: ')."""
    r = cli(*args, check=False)
    assert r.returncode == 2, r
    line = r.stderr.strip()
    assert line.startswith("minigolf: error: ") and "\n" not in line, line
    return line[len("minigolf: error: "):]


def as_json(d):
    return json.loads(json.dumps(d))  # tuples -> lists, as the CLI's JSON


@pytest.fixture(scope="module")
def flat():
    return minigolf.System(field="flat")


def test_ball_putt_equals_cli_json_bit_for_bit(flat):
    for angle, speed in [(0.0, 1.3), (0.013, 1.1), (-0.05, 2.2)]:
        ours = flat.putt(angle, speed, ball_only=True, record_interval=0.0).to_dict()
        theirs = json.loads(cli("putt", "--field", "flat", "--angle", repr(angle), "--speed", repr(speed),
                                "--ball-only", "--json").stdout)
        assert as_json(ours) == theirs  # floats compare exactly (shortest round-trip JSON)
        # recording a trajectory changes nothing
        recorded = flat.putt(angle, speed, ball_only=True, record_interval=0.01)
        assert as_json(recorded.to_dict()) == theirs
        traj = recorded.trajectory
        assert traj.ndim == 2 and traj.shape[1] == 7 and traj.shape[0] > 10
        assert np.all(np.diff(traj[:, 0]) > 0)
        assert abs(traj[0, 1] - flat.field.tee[0]) < 1e-9 and abs(traj[0, 2] - flat.field.tee[1]) < 1e-9


def test_arm_putt_equals_cli_json_bit_for_bit(flat):
    angle, speed = 0.02, 1.2
    ours = as_json(flat.putt(angle, speed).to_dict())
    theirs = json.loads(cli("putt", "--field", "flat", "--angle", repr(angle), "--speed", repr(speed),
                            "--json").stdout)
    ours.pop("timing"), theirs.pop("timing")  # wall-clock times of the core update
    assert ours == theirs
    assert ours["launch"]["speed"] > 0.5
    # the ball's path, from the club's first contact (the default records every 10 ms)
    recorded = flat.putt(angle, speed)
    plain = as_json(flat.putt(angle, speed, record_interval=0.0).to_dict())
    plain.pop("timing")
    assert plain == theirs and flat.putt(angle, speed, record_interval=0.0).trajectory.shape == (0, 7)
    traj = recorded.trajectory
    assert traj.shape[1] == 7 and traj.shape[0] > 50
    assert traj[0, 0] == 0.0 and np.all(np.diff(traj[:, 0]) > 0)
    assert abs(traj[-1, 0] - theirs["duration"]) < 1e-9
    assert np.hypot(traj[0, 1] - flat.field.tee[0], traj[0, 2] - flat.field.tee[1]) < 0.01
    assert np.hypot(traj[-1, 1] - theirs["rest_position"][0], traj[-1, 2] - theirs["rest_position"][1]) < 0.01


def test_putt_from_wherever_the_ball_lies_equals_the_cli(flat):
    ours = as_json(flat.putt(0.0, 0.6, ball=(1.0, 0.3), record_interval=0.0).to_dict())
    theirs = json.loads(cli("putt", "--field", "flat", "--ball", "1.0,0.3", "--angle", "0",
                            "--speed", "0.6", "--json").stdout)
    ours.pop("timing"), theirs.pop("timing")
    assert ours == theirs and ours["ball"] == [1.0, 0.3]
    assert abs(ours["aim"] - np.arctan2(-0.3, 1.0)) < 1e-12  # facing the hole (2, 0)
    rolled = flat.putt(0.0, 1.0, ball_only=True, ball=(0.5, 0.2))
    assert list(rolled.ball) == [0.5, 0.2] and rolled.rest_position[0] > 0.6
    with pytest.raises(ValueError, match="ball"):
        flat.putt(0.0, 0.6, ball=(9.0, 0.0))
    with pytest.raises(ValueError, match="aim"):
        flat.putt(0.0, 0.6, ball_only=True, aim=1.0)


def test_a_world_direction_picks_its_stance_as_the_cli(flat):
    ours = as_json(flat.putt(2.8, 0.6, ball=(1.0, 0.3), world=True, record_interval=0.0).to_dict())
    theirs = json.loads(cli("putt", "--field", "flat", "--ball", "1.0,0.3", "--world", "--angle",
                            "2.8", "--speed", "0.6", "--json").stdout)
    ours.pop("timing"), theirs.pop("timing")
    assert ours == theirs and abs(ours["aim"] - 2.8) < 1e-12  # turned: the fixed arm cannot
    assert flat.putt(0.2, 0.6, ball=(1.0, 0.3), world=True).aim == 0.0  # within its reach
    with pytest.raises(ValueError, match="world"):
        flat.putt(0.0, 0.6, world=True, aim=1.0)


def test_putt_on_another_hole_and_field():
    hill = minigolf.System(field="regular-hill")
    r = hill.putt(0.0, 1.5, hole=(1.8, 0.1), ball_only=True)
    theirs = json.loads(cli("putt", "--field", "regular-hill", "--hole", "1.8,0.1", "--angle", "0",
                            "--speed", "1.5", "--ball-only", "--json").stdout)
    assert as_json(r.to_dict()) == theirs


def test_views_alias_the_live_data(flat):
    data = flat.make_data()
    qpos = data.ball.qpos  # taken before the putt
    bq = flat.ball_world.ball_qpos
    r = flat.putt(0.0, 1.0, ball_only=True, data=data)
    assert qpos[bq] == r.rest_position[0] and qpos[bq + 1] == r.rest_position[1]  # it saw the putt
    qpos[bq] = 0.5  # and a write goes into the mjData
    assert data.ball.qpos[bq] == 0.5

    world = flat.ball_world
    d = world.make_data()
    q, v = d.qpos, d.qvel
    z0 = q[bq + 2]
    q[bq + 2] = z0 + 0.05  # lift the ball: it falls under gravity
    t0 = d.time
    world.step(d, 100)
    assert d.time == pytest.approx(t0 + 100 * world.timestep)
    assert v[flat.ball_world.ball_dof + 2] < -0.5  # the view saw the fall: about -g t
    world.reset(d)
    assert q[bq + 2] == z0 and d.time == 0.0

    masses = flat.arm_world.model_body_mass  # read-only view of the shared model
    assert masses.shape == (flat.arm_world.nbody,)
    assert masses[flat.arm_world.body_id("ball")] == pytest.approx(flat.field.ball_mass)
    with pytest.raises(ValueError):
        masses[0] = 1.0
    assert d.xpos.shape == (world.nbody, 3)


def test_bad_arguments_raise_the_cli_messages(flat):
    msg = cli_error("putt", "--field", "no-such-field", "--angle", "0", "--speed", "1", "--ball-only")
    with pytest.raises(ValueError) as e:
        minigolf.System(field="no-such-field")
    assert str(e.value) == msg

    msg = cli_error("putt", "--field", "flat", "--angle", "0", "--speed", "9")
    with pytest.raises(ValueError) as e:
        flat.putt(0.0, 9.0)
    assert str(e.value) == msg

    msg = cli_error("putt", "--field", "flat", "--hole", "9,0", "--angle", "0", "--speed", "1", "--ball-only")
    with pytest.raises(ValueError) as e:
        flat.putt(0.0, 1.0, hole=(9.0, 0.0), ball_only=True)
    assert str(e.value) == msg

    msg = cli_error("evaluate", "--field", "flat", "--model", "/nonexistent/model.json")
    with pytest.raises(OSError) as e:
        minigolf.Model.load("/nonexistent/model.json")
    assert str(e.value) == msg

    with pytest.raises(ValueError, match="method"):
        minigolf.train(np.zeros((3, 2)), np.zeros((3, 2)), method="svm")


def test_bad_perception_values_are_one_line_errors():
    """System(perception=...): 'truth' (the default) or 'camera'; rig and calibration only with
    the cameras; a missing or bad file is the command line's message (no display needed)."""
    for kwargs, kind, needle in [
        (dict(perception="eyes"), ValueError, "perception: expected 'truth' or 'camera', got 'eyes'"),
        (dict(rig="stereo"), ValueError, "rig: only with perception='camera'"),
        (dict(calibration="c.yaml"), ValueError, "calibration: only with perception='camera'"),
        (dict(perception="camera", rig="/no/such/rig.yaml"), Exception, "/no/such/rig.yaml"),
        (dict(perception="camera", calibration="/no/such/c.yaml"), Exception, "/no/such/c.yaml"),
    ]:
        with pytest.raises(kind) as e:
            minigolf.System(field="flat", **kwargs)
        assert needle in str(e.value) and "\n" not in str(e.value), (kwargs, str(e.value))
    msg = cli_error("putt", "--angle", "0", "--speed", "1", "--perception", "camera", "--rig", "/no/such/rig.yaml")
    with pytest.raises(Exception) as e:
        minigolf.System(field="flat", perception="camera", rig="/no/such/rig.yaml")
    assert str(e.value) == msg


def test_long_calls_release_the_gil(flat):
    # While one thread putts, the interpreter keeps running Python code in another ...
    ticks = 0
    worker = threading.Thread(target=lambda: [flat.putt(0.0, 2.5, ball_only=True) for _ in range(8)])
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    assert ticks > 20
    # ... and two threads are inside putts at the same time (with the GIL held they never would be,
    # whatever the number of cores).
    intervals = [[], []]

    def run(k):
        data = flat.make_data()
        for i in range(10):
            t = time.perf_counter()
            flat.putt(0.001 * i, 2.0, ball_only=True, data=data, record_interval=0.0)
            intervals[k].append((t, time.perf_counter()))

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    overlap = sum(max(0.0, min(b1, b2) - max(a1, a2)) for a1, b1 in intervals[0] for a2, b2 in intervals[1])
    busy = sum(b - a for a, b in intervals[0])
    assert overlap > 0.5 * busy, (overlap, busy)


def test_one_system_data_per_thread(flat):
    data = flat.make_data()
    errors = []

    def run():
        try:
            for _ in range(4):
                flat.putt(0.0, 2.8, ball_only=True, data=data)
        except RuntimeError as e:
            errors.append(str(e))

    threads = [threading.Thread(target=run) for _ in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert all("in use by another thread" in e for e in errors)


def test_fields():
    assert "flat" in minigolf.Field.shipped()
    f = minigolf.Field.load("regular-hill")
    h = f.height(np.array([0.0, 1.0, 2.0]), 0.0)
    assert h.shape == (3,) and h[1] == pytest.approx(f.height(1.0, 0.0))
    pts = f.situations.collection_points()
    assert pts.ndim == 2 and pts.shape[1] == 2
    s = f.situations.sample(5, 3)
    assert np.array_equal(s, f.situations.sample(5, 3))


def test_a_ball_region_gives_ball_hole_pairs(tmp_path):
    text = (ROOT / "data" / "fields" / "flat.yaml").read_text()
    start = text.index("situations:")
    end = text.find("\n", text.index("strategy:", start))
    rest = "" if end < 0 else text[end + 1:]
    path = tmp_path / "anywhere.yaml"
    path.write_text(text[:start] + (
        "situations:\n"
        "  grid: {x: [1.6, 2.2], y: [-0.2, 0.3], counts: [2, 2]}\n"
        "  ball: {list: {points: [[0.0, 0.0], [0.3, 0.1], [0.2, -0.1]]}}\n") + rest)
    f = minigolf.Field.load(str(path))
    region = f.situations
    assert tuple(region.ball_bounds) == (0.0, 0.3, -0.1, 0.1)
    assert region.learner_inputs == ["xi_x", "xi_y"]  # flat: xi = hole - ball is enough
    pairs = f.collection_situations(region)
    assert pairs.shape == (12, 4)
    assert np.array_equal(pairs[4, :2], [0.3, 0.1]) and np.array_equal(pairs[4, 2:], [1.6, -0.2])
    drawn = f.sample_situations(region, 6, seed=2)
    assert drawn.shape == (6, 4)
    assert np.array_equal(drawn[:, 2:], region.sample(6, 2))  # the holes of a tee-only region
    flat = minigolf.Field.load("flat")
    assert flat.situations.ball_bounds is None
    assert tuple(flat.region("", balls="list:0.3,0.1").ball_bounds) == (0.3, 0.3, 0.1, 0.1)
    with pytest.raises(ValueError, match="--balls"):
        flat.region("", balls="list:0.3,0.9")
    e = minigolf.System(field="flat").teach((2.0, 0.1), ball=(0.4, -0.2))
    assert e.found and tuple(e.ball) == (0.4, -0.2) and tuple(e.hole) == (2.0, 0.1)


def test_learners_train_predict_and_files(tmp_path):
    x, y = minigolf.load_dataset(str(ROOT / "data" / "datasets" / "flat.csv"))
    assert x.shape[1] == 2 and y.shape[1] == 2 and x.shape[0] == y.shape[0]
    for method in ["gpr", "gmr", "joint-gmr"]:
        m = minigolf.train(x, y, method=method, restarts=2, seed=3)
        mean, std = m.predict(x)
        assert mean.shape == y.shape and std.shape == y.shape and np.all(std > 0)
        assert np.sqrt(np.mean((mean[:, 0] - y[:, 0]) ** 2)) < 0.5 * np.std(y[:, 0])
        path = tmp_path / f"{method}.json"
        m.save(str(path))
        again = minigolf.Model.load(str(path))
        assert again.method == method and again.input_names == ["xi_x", "xi_y"]
        assert np.array_equal(again.predict(x)[0], mean)


def test_learner_equals_cli_train_and_predict(tmp_path):
    model = tmp_path / "cli.json"
    cli("train", str(ROOT / "data" / "datasets" / "flat.csv"), "--method", "gpr", "--seed", "1",
        "-o", str(model))
    x, y = minigolf.load_dataset(str(ROOT / "data" / "datasets" / "flat.csv"))
    ours = minigolf.train(x, y, method="gpr", seed=1)
    assert np.array_equal(ours.predict(x)[0], minigolf.Model.load(str(model)).predict(x)[0])


def test_ds_rollout_reaches_the_ball():
    h = minigolf.HittingModel.load()
    start = np.array(h.x_star) + np.array([-0.3, 0.05, 0.02])
    r = h.rollout(angle=0.1, speed=1.5, start=start)
    assert r["reached"] and r["stop_reason"] == "reached"
    assert r["x"].shape == (len(r["t"]), 3) and r["position_error"] < 0.005
    assert np.linalg.norm(r["x"][-1] - np.array(h.x_star)) < 0.02


def test_a_data_of_another_world_is_refused(flat):
    d = flat.arm_world.make_data()
    with pytest.raises(ValueError, match="another world"):
        flat.ball_world.step(d)


def test_collect_equals_the_cli_file(flat, tmp_path):
    spec = "list:1.9,0.05;2.0,-0.05"
    cli("collect", "--field", "flat", "--situations", spec, "--max-full-putts", "12", "-o", str(tmp_path / "cli.csv"))
    examples = flat.collect(str(tmp_path / "py.csv"), situations=spec, max_full_putts=12)
    assert (tmp_path / "py.csv").read_bytes() == (tmp_path / "cli.csv").read_bytes()
    assert [list(e.hole) for e in examples] == [[1.9, 0.05], [2.0, -0.05]]


def test_a_plant_is_the_world_and_equals_the_cli(tmp_path):
    plant = tmp_path / "slow.yaml"
    plant.write_text("format_version: 1\nfield:\n  rolling_resistance_scale: 1.2\n")
    real = minigolf.System(field="flat", plant=str(plant))
    assert real.plant["path"] == str(plant) and len(real.plant["hash"]) == 16
    assert minigolf.System(field="flat").plant is None
    ours = as_json(real.putt(0.0, 2.4, ball_only=True, record_interval=0.0).to_dict())
    theirs = json.loads(cli("putt", "--field", "flat", "--angle", "0.0", "--speed", "2.4", "--ball-only",
                            "--json", "--plant", str(plant)).stdout)
    assert ours == theirs
    nominal = minigolf.System(field="flat").putt(0.0, 2.4, ball_only=True).to_dict()
    assert ours["rest_position"][0] < nominal["rest_position"][0] - 0.05  # slower grass: shorter roll
    (tmp_path / "bad.yaml").write_text("format_version: 1\narm:\n  club_speed_scale: 9\n")
    with pytest.raises(ValueError, match="arm.club_speed_scale"):
        minigolf.System(field="flat", plant=str(tmp_path / "bad.yaml"))


def test_hostile_inputs_raise_instead_of_returning_nan(flat):
    """Bounded, finite answers or a ValueError/OSError."""
    f = flat.field
    for x, y in [(float("nan"), 0.0), (0.0, float("inf")), (None, None), ([0.0, float("nan")], [0.0, 0.0])]:
        with pytest.raises((ValueError, TypeError)):
            f.height(x, y)
    assert np.isfinite(f.height([0.0, 1.0], [0.0, 0.1])).all()
    h = minigolf.HittingModel.load()
    for start in ([1e308, 0.0, 0.0], [float("nan"), 0.0, 0.0], np.array(h.x_star) + [10.0, 0.0, 0.0]):
        with pytest.raises(ValueError, match="start"):
            h.rollout(angle=0.1, speed=1.5, start=start)
    with pytest.raises((ValueError, OSError)):
        minigolf.System(field="x" * 100000)
    with pytest.raises(ValueError, match="max_duration"):
        flat.putt(0.0, 1.0, max_duration=1e308)
    with pytest.raises(ValueError, match="tee"):
        flat.teach(tuple(f.tee))
    with pytest.raises(ValueError, match="tee"):
        f.check_hole(tuple(f.tee))
    f.check_hole(tuple(f.hole_position))


def test_hostile_input_files_are_refused_at_once(tmp_path):
    """/dev/zero and FIFOs as input files raise OSError at once."""
    import os
    fifo = tmp_path / "model.fifo"
    os.mkfifo(fifo)
    t0 = time.monotonic()
    for path in ("/dev/zero", str(fifo)):
        with pytest.raises(OSError, match="regular files"):
            minigolf.Model.load(path)
    assert time.monotonic() - t0 < 5.0


def test_a_system_data_of_another_system_is_refused(flat):
    """Another System's data made MuJoCo wait for Enter (or crash)."""
    bank = minigolf.System(field="bank-shot")
    other = flat.make_data()
    for kwargs in (dict(), dict(ball_only=True)):
        with pytest.raises(ValueError, match="another System"):
            bank.putt(0.01, 1.5, data=other, **kwargs)
    with pytest.raises(ValueError, match="another System"):
        bank.teach(tuple(bank.field.hole_position), data=other)
    assert bank.putt(0.01, 1.5, data=bank.make_data()).end  # its own data plays


def test_a_belief_is_the_field_file_as_the_robot_believes_it(tmp_path, flat):
    belief = tmp_path / "belief.yaml"
    belief.write_text("format_version: 1\nfield: {rolling_resistance_scale: 1.1}\n"
                      "std: {field: {rolling_resistance_scale: 0.01}}\nputts: 5\n")
    s = minigolf.System(field="flat", belief=str(belief))
    assert s.field.rolling_resistance == pytest.approx(1.1 * flat.field.rolling_resistance)
    bad = tmp_path / "bad.yaml"
    bad.write_text("format_version: 1\nfield: {grass: 2}\n")
    with pytest.raises(ValueError, match="grass"):
        minigolf.System(field="flat", belief=str(bad))


def test_a_mujoco_error_never_waits_for_enter(tmp_path):
    """With stdin open, MuJoCo's own handler printed 'Press Enter to exit' and
    waited; the module's handler prints one line and ends the interpreter at once."""
    import sys
    script = ("import ctypes, ctypes.util, minigolf\n"
              "lib = ctypes.CDLL(ctypes.util.find_library('mujoco') or 'libmujoco.so')\n"
              "lib.mju_error(b'the stack is full')\n")
    r = subprocess.run([sys.executable, "-c", script], stdin=subprocess.PIPE, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 1, r
    assert r.stderr.strip() == "minigolf: error: MuJoCo: the stack is full", r.stderr
    assert "Press Enter" not in r.stdout


def test_world_angles_are_bounded_and_world_excludes_ball_only(flat):
    """angle=1e18 with world=True and aim=1e308 played; ball_only with world was
    accepted although its own message forbids it."""
    with pytest.raises(ValueError, match=r"angle \(world\): expected a value in \[-3.15, 3.15\]"):
        flat.putt(1e18, 1.6, world=True)
    for aim in (1e308, -1e18, 4.0):
        with pytest.raises(ValueError, match=r"aim: expected a value in \[-3.15, 3.15\]"):
            flat.putt(0.0, 1.6, aim=aim)
    with pytest.raises(ValueError, match="world"):
        flat.putt(0.0, 1.6, ball_only=True, world=True)
    for threads in (-1, 100000):
        with pytest.raises(ValueError, match="threads"):
            flat.sweep([0.0], [1.6], ball_only=True, threads=threads)
