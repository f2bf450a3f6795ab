"""A Gymnasium environment of minigolf: one putt per episode (docs/python.md).

    import minigolf
    env = minigolf.make("minigolf/PuttBall-v0")     # or gymnasium.make(...) when gymnasium is installed
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Registered ids (`REGISTERED`, `ENTRY_POINTS`): "minigolf/Putt-v0" (the WAM hits the ball),
"minigolf/PuttBall-v0" (the ball alone, MuJoCo) and "minigolf/PuttFast-v0" (the ball alone on the
planning path, sim::fast_putt), with a normalised action space and shaped rewards,
`max_episode_steps=1`; and "minigolf/Round-v0" (minigolf.round_env.RoundEnv: a hole stroke by
stroke). `make_vec` makes vector envs with same-step autoreset (gymnasium >= 1.1).

Observation (float32, `observation_names`), observation="fields" (default): xi = hole - tee [m]
(xi_x, xi_y) and a one-hot of the field (field_<name> per shipped field, field_other), the same
layout and bounds (the union of the shipped fields' situations and this env's) on every field.
observation="varying": the coordinates of xi that vary over the environment's situations (a
constant one, as xi_x on the flat field's line, is left out: a zero-width dimension breaks
rescaling wrappers), then the field's index when there are several fields (or
observe_field=True); a region of a single hole keeps both, widened by 1 cm each way. info["xi"]
always holds both.
Action (float32): (theta [rad], v [m/s]) inside the module's safe envelope (the arm: hitting angle
and club speed; mode="ball": the ball's launch angle and speed, the same bounds), or, with
normalize_actions=True, [-1, 1]^2 mapped linearly onto it (-1 and 1 exactly onto its ends). Actions
outside are clipped to [-1, 1] or to the envelope (info["clipped"]: the putt played differs from the
action); info["action"] is the putt as played, in physical units.
Reward: reward="sparse": 1 if the ball is sunk, else 0. reward="shaped": 1 if sunk, else
-closest_approach / reward_scale (the ball's closest approach to the hole [m]; a club that missed
the ball counts the tee's distance). info["reward_parts"] = {"sunk", "approach"} sum to the reward.
Rendering: render_mode "rgb_array" (the current frame: the ball on the tee, or where it stopped with
its path), "rgb_array_list" (every frame of the putt at render_fps since the last render), "human"
(a window: step plays the putt). Frames come from MuJoCo's renderer through GLFW, which needs a
display: on a server run under `xvfb-run -a`.

When `gymnasium` imports, PuttEnv subclasses `gymnasium.Env` with `gymnasium.spaces.Box` spaces and
the ids are registered with gymnasium; otherwise `minigolf.env.Box` and `minigolf.make` give the
same interface. The generator is numpy's `default_rng(seed)` either way (what Gymnasium's seeding
makes), so a seed gives the same episodes with or without Gymnasium. Environments pickle (the
System is rebuilt from the constructor's arguments and the plant file's content as it was read at
construction, so a clone plays the same world even if the file changed since) and deepcopy, so
AsyncVectorEnv works with any start method.
"""
from __future__ import annotations

import time
from typing import Any, Optional, Sequence

import numpy as np

from . import _minigolf

try:  # gymnasium is not in Debian 12: users install it
    import gymnasium as _gym
    from gymnasium.spaces import Box as _GymBox
except ImportError:  # the same interface without it
    _gym = None
    _GymBox = None

#: The registered ids and their constructor arguments (gymnasium.make or minigolf.make).
REGISTERED = {
    "minigolf/Putt-v0": dict(mode="arm", normalize_actions=True, reward="shaped"),
    "minigolf/PuttBall-v0": dict(mode="ball", normalize_actions=True, reward="shaped"),
    "minigolf/PuttFast-v0": dict(mode="fast", normalize_actions=True, reward="shaped"),
    "minigolf/Round-v0": dict(field="bank-shot", player="ball"),
}
#: Each id's entry point and Gymnasium `max_episode_steps` (None: the environment ends episodes).
ENTRY_POINTS = {
    "minigolf/Putt-v0": ("minigolf.env:PuttEnv", 1),
    "minigolf/PuttBall-v0": ("minigolf.env:PuttEnv", 1),
    "minigolf/PuttFast-v0": ("minigolf.env:PuttEnv", 1),
    "minigolf/Round-v0": ("minigolf.round_env:RoundEnv", None),
}
MAX_EPISODE_STEPS = 1  # one putt per episode

_CONSTANT = 1e-9   # [m] a coordinate spanning less is constant over the situations
_WIDEN = 0.01      # [m] each way, for a region of a single hole
_UNPICKLED = ("systems", "_data", "_regions", "_renderer", "_skills")


class Box:
    """A box in R^n (Gymnasium's `spaces.Box` interface: shape, dtype, low, high, seed(),
    sample(), contains(), `in`)."""

    def __init__(self, low, high, shape: Optional[Sequence[int]] = None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        low = np.asarray(low, dtype=self.dtype)
        high = np.asarray(high, dtype=self.dtype)
        if shape is not None:
            low = np.broadcast_to(low, shape).copy()
            high = np.broadcast_to(high, shape).copy()
        if low.shape != high.shape:
            raise ValueError(f"Box: low has shape {low.shape}, high {high.shape}")
        if not np.all(low <= high):
            raise ValueError("Box: expected low <= high")
        self.low, self.high = low, high
        self.shape = low.shape
        self._np_random = None
        if seed is not None:
            self.seed(seed)

    @property
    def np_random(self) -> np.random.Generator:
        if self._np_random is None:
            self.seed()
        return self._np_random

    def seed(self, seed: Optional[int] = None) -> list:
        self._np_random = np.random.default_rng(seed)
        return [seed]

    def is_bounded(self, manner: str = "both") -> bool:
        below, above = bool(np.all(np.isfinite(self.low))), bool(np.all(np.isfinite(self.high)))
        return {"both": below and above, "below": below, "above": above}[manner]

    def sample(self, mask=None) -> np.ndarray:
        if mask is not None:
            raise ValueError("Box.sample: masks are not supported")
        return self.np_random.uniform(self.low, self.high).astype(self.dtype)

    def contains(self, x) -> bool:
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError):
                return False
        return bool(
            np.can_cast(x.dtype, self.dtype)
            and x.shape == self.shape
            and np.all(x >= self.low)
            and np.all(x <= self.high)
        )

    def __contains__(self, x) -> bool:
        return self.contains(x)

    def __eq__(self, other) -> bool:
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))

    def __repr__(self) -> str:
        return f"Box({self.low}, {self.high}, {self.shape}, {self.dtype})"


_shipped: dict = {}


def _shipped_field_names() -> tuple:
    """The shipped fields' names, sorted (cached)."""
    if "names" not in _shipped:
        _shipped["names"] = tuple(sorted(_minigolf.Field.shipped()))
    return _shipped["names"]


def shipped_xi_bounds() -> tuple:
    """(low, high) of xi = hole - tee [m] over every shipped field's situations (cached)."""
    if "xi" not in _shipped:
        lows, highs = [], []
        for n in _shipped_field_names():
            f = _minigolf.Field.load(n)
            b, t = np.array(f.region("").bounds), np.asarray(f.tee, dtype=np.float64)
            lows.append(b[[0, 2]] - t)
            highs.append(b[[1, 3]] - t)
        _shipped["xi"] = (np.min(lows, axis=0), np.max(highs, axis=0))
    low, high = _shipped["xi"]
    return low.copy(), high.copy()


_Base = _gym.Env if _gym is not None else object
_Space = _GymBox if _GymBox is not None else Box


def _float32_inside(low, high):
    """float32 bounds inside [low, high] (every float32 action between them lies in the envelope)."""
    lo, hi = np.asarray(low, np.float32), np.asarray(high, np.float32)
    lo = np.where(lo.astype(np.float64) < low, np.nextafter(lo, np.float32(np.inf)), lo)
    hi = np.where(hi.astype(np.float64) > high, np.nextafter(hi, np.float32(-np.inf)), hi)
    return lo.astype(np.float32), hi.astype(np.float32)


def _float32_around(low, high):
    """float32 bounds around [low, high] (every float64 value between them rounds into the box)."""
    lo, hi = np.asarray(low, np.float32), np.asarray(high, np.float32)
    lo = np.where(lo.astype(np.float64) > low, np.nextafter(lo, np.float32(-np.inf)), lo)
    hi = np.where(hi.astype(np.float64) < high, np.nextafter(hi, np.float32(np.inf)), hi)
    return lo.astype(np.float32), hi.astype(np.float32)


class PuttEnv(_Base):
    """One putt per episode on the simulated WAM (see the module docstring).

    field: a shipped field name or path, or a sequence of them (each episode draws one).
    mode: "arm" (the full system: the WAM hits the ball), "ball" (the ball alone, MuJoCo) or "fast"
        (the ball alone on the planning path, sim::fast_putt: MuJoCo's outcome, ~10x faster).
    club_action: with mode "ball" or "fast", the action is the arm's (hitting angle [rad], club
        speed [m/s]) and becomes a launch through the robot's launch skill (calibrated with
        `skill_putts` arm putts from the tee, as `minigolf play` does; "fast" also starts the ball
        as it leaves the club): a policy trained on it plays Putt-v0's actions.
    situations: where holes are drawn (a `--situations` spec, e.g. "box:1.5,2.5:-0.3,0.3:3,3";
        default: each field's own region).
    normalize_actions: the action space is [-1, 1]^2, mapped linearly onto the safe envelope.
    reward: "sparse" (1 sunk / 0) or "shaped" (1 sunk, else -closest_approach / reward_scale [m]).
    observation: "fields" (default): one layout on every field: xi_x, xi_y and a one-hot of the
        field (`field_<name>` per shipped field, `field_other`), bounds the union of the shipped
        fields' situations and this env's; "varying": the coordinates of xi that vary over this
        env's situations, then the field's index with several fields (or observe_field=True).
    observe_field: ("varying" only) append the field's index (default: with several fields).
    config, hitting_model, plant: as for `minigolf.System` (plant: the world as it really is).
    max_duration: of the ball's roll [s].
    render_mode: None, "rgb_array", "rgb_array_list" or "human"; render_size (width, height)
        [pixels]; camera: "overview", "side", "top" or "follow".
    """

    metadata = {"render_modes": ["rgb_array", "rgb_array_list", "human"], "render_fps": 30}

    def __init__(self, field="flat", mode: str = "arm", observe_field: Optional[bool] = None,
                 config: str = "", hitting_model: str = "", max_duration: float = 30.0,
                 render_mode: Optional[str] = None, plant: str = "", normalize_actions: bool = False,
                 reward: str = "sparse", reward_scale: float = 1.0, situations: str = "",
                 render_size: Sequence[int] = (640, 480), camera: str = "overview",
                 club_action: bool = False, skill_putts: int = 10, observation: str = "fields"):
        self._init_kwargs = dict(field=field, mode=mode, observe_field=observe_field, config=config,
                                 hitting_model=hitting_model, max_duration=max_duration,
                                 render_mode=render_mode, plant=plant, normalize_actions=normalize_actions,
                                 reward=reward, reward_scale=reward_scale, situations=situations,
                                 render_size=tuple(render_size), camera=camera, club_action=club_action,
                                 skill_putts=skill_putts, observation=observation)
        if observation not in ("fields", "varying"):
            raise ValueError(f"PuttEnv: observation: expected 'fields' or 'varying', got '{observation}'")
        self.observation_layout = observation
        if mode not in ("arm", "ball", "fast"):
            raise ValueError(f"PuttEnv: mode: expected 'arm', 'ball' or 'fast', got '{mode}'")
        if club_action and mode == "arm":
            raise ValueError("PuttEnv: club_action: only with mode 'ball' or 'fast' (the arm's actions are club hits)")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"PuttEnv: render_mode: expected None or one of {self.metadata['render_modes']}, "
                             f"got '{render_mode}'")
        if reward not in ("sparse", "shaped"):
            raise ValueError(f"PuttEnv: reward: expected 'sparse' or 'shaped', got '{reward}'")
        if not (isinstance(reward_scale, (int, float)) and np.isfinite(reward_scale) and 1e-3 <= reward_scale <= 100):
            raise ValueError(f"PuttEnv: reward_scale: expected a length in [0.001, 100] m, got {reward_scale!r}")
        if not (isinstance(max_duration, (int, float)) and np.isfinite(max_duration) and 0.01 <= max_duration <= 600):
            raise ValueError(f"PuttEnv: max_duration: expected a value in [0.01, 600] s, got {max_duration!r}")
        if camera not in ("overview", "side", "top", "follow"):
            raise ValueError(f"PuttEnv: camera: expected overview, side, top or follow, got '{camera}'")
        size = tuple(render_size)
        if len(size) != 2 or not all(isinstance(v, (int, np.integer)) and 16 <= v <= 4096 for v in size):
            raise ValueError(f"PuttEnv: render_size: expected (width, height), 16..4096 pixels each, got {render_size!r}")
        names = [field] if isinstance(field, str) else list(field)
        if not names:
            raise ValueError("PuttEnv: field: expected at least one field")
        self.render_mode = render_mode
        self.mode = mode
        self.club_action = bool(club_action)
        self.reward_mode = reward
        self.reward_scale = float(reward_scale)
        self.max_duration = float(max_duration)
        self.normalize_actions = bool(normalize_actions)
        # The plant's content, read once: pickling keeps it (not the path, whose file may change).
        self._plant_text = _minigolf.read_plant_file(plant) if plant else None
        self._build_systems()
        self.observe_field = len(names) > 1 if observe_field is None else bool(observe_field)
        self._set_spaces()
        self._np_random = None
        self._field = 0
        self._hole = np.asarray(self.systems[0].field.hole_position, dtype=np.float64)
        self._done = True
        self._trajectory = None   # (N, 7) of the last putt: t, x, y, z, vx, vy, vz
        self._frames = []

    # ---- construction (also what unpickling rebuilds)
    def _build_systems(self):
        k = self._init_kwargs
        names = [k["field"]] if isinstance(k["field"], str) else list(k["field"])
        self.systems = [_minigolf.System(field=n, config=k["config"], hitting_model=k["hitting_model"],
                                         plant=k["plant"], plant_text=self._plant_text) for n in names]
        self._data = [s.make_data() for s in self.systems]
        self._regions = [s.field.region(k["situations"]) for s in self.systems]
        self._renderer = None
        self._skills = None
        if k.get("club_action"):
            self._skills = [_minigolf.calibrate_launch_skill(s, putts=k.get("skill_putts", 10)) for s in self.systems]

    def _set_spaces(self):
        if self.observation_layout == "fields":
            self._set_field_spaces()
        else:
            self._set_varying_spaces()
        e = self.systems[0].envelope
        self._envelope_low = np.array([e["angle_min"], e["speed_min"]], dtype=np.float64)
        self._envelope_high = np.array([e["angle_max"], e["speed_max"]], dtype=np.float64)
        if self.normalize_actions:
            alow, ahigh = np.full(2, -1.0, np.float32), np.full(2, 1.0, np.float32)
        else:
            alow, ahigh = _float32_inside(self._envelope_low, self._envelope_high)
        self.action_space = _Space(low=alow, high=ahigh, dtype=np.float32)

    def _set_field_spaces(self):
        low, high = shipped_xi_bounds()
        for r, s in zip(self._regions, self.systems):  # this env's situations too
            b, t = np.array(r.bounds), np.asarray(s.field.tee, dtype=np.float64)
            low = np.minimum(low, b[[0, 2]] - t)
            high = np.maximum(high, b[[1, 3]] - t)
        names = _shipped_field_names()
        self._onehot = []
        for s in self.systems:
            v = np.zeros(len(names) + 1)
            shipped = s.field.name in names and _minigolf.Field.load(s.field.name).source == s.field.source
            v[names.index(s.field.name) if shipped else len(names)] = 1.0
            self._onehot.append(v)
        self._kept = np.array([0, 1])
        self.observation_names = ("xi_x", "xi_y") + tuple(f"field_{n}" for n in names) + ("field_other",)
        olow, ohigh = _float32_around(np.concatenate([low, np.zeros(len(names) + 1)]),
                                      np.concatenate([high, np.ones(len(names) + 1)]))
        self.observation_space = _Space(low=olow, high=ohigh, dtype=np.float32)

    def _set_varying_spaces(self):
        tees = [np.asarray(s.field.tee, dtype=np.float64) for s in self.systems]
        lows = [np.array(r.bounds)[[0, 2]] - t for r, t in zip(self._regions, tees)]
        highs = [np.array(r.bounds)[[1, 3]] - t for r, t in zip(self._regions, tees)]
        low, high = np.min(lows, axis=0), np.max(highs, axis=0)
        self._xi_low, self._xi_high = low, high
        varying = high - low > _CONSTANT
        if not varying.any():  # one hole: both coordinates, widened
            varying[:] = True
            low, high = low - _WIDEN, high + _WIDEN
        self._kept = np.flatnonzero(varying)
        names = [("xi_x", "xi_y")[i] for i in self._kept]
        low, high = low[self._kept], high[self._kept]
        if self.observe_field:
            # [0, 1] with one field: a constant index would be a zero-width dimension
            low, high = np.append(low, 0.0), np.append(high, float(max(len(self.systems) - 1, 1)))
            names.append("field")
        self.observation_names = tuple(names)
        olow, ohigh = _float32_around(low, high)
        self.observation_space = _Space(low=olow, high=ohigh, dtype=np.float32)

    # ---- pickling: the System and its MuJoCo data are rebuilt from the constructor's arguments
    # and the plant's content (_plant_text)
    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k not in _UNPICKLED}

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._build_systems()

    # Gymnasium's Env provides np_random; the same without it.
    if _gym is None:
        @property
        def np_random(self) -> np.random.Generator:
            if self._np_random is None:
                self._np_random = np.random.default_rng()
            return self._np_random

        @property
        def unwrapped(self):
            return self

        def get_wrapper_attr(self, name: str):
            """Gymnasium's Env.get_wrapper_attr without it (to_physical, from_physical, ...)."""
            return getattr(self, name)

    # ---- the action and observation maps
    def to_physical(self, action) -> np.ndarray:
        """(theta [rad], v [m/s]) of an action (clipped into [-1, 1], or into the safe envelope)."""
        a = np.asarray(action, dtype=np.float64)
        if self.normalize_actions:
            a = np.clip(a, -1.0, 1.0)
            a = 0.5 * (1.0 - a) * self._envelope_low + 0.5 * (1.0 + a) * self._envelope_high  # exact at -1, 1
        return np.clip(a, self._envelope_low, self._envelope_high)

    def from_physical(self, putt) -> np.ndarray:
        """The action that plays (theta [rad], v [m/s]) (inverse of to_physical inside the envelope)."""
        p = np.asarray(putt, dtype=np.float64)
        if self.normalize_actions:
            p = 2.0 * (p - self._envelope_low) / (self._envelope_high - self._envelope_low) - 1.0
        return np.clip(p, self.action_space.low, self.action_space.high).astype(np.float32)

    def _xi(self) -> np.ndarray:
        return self._hole - np.asarray(self.systems[self._field].field.tee, dtype=np.float64)

    def _observation(self) -> np.ndarray:
        obs = self._xi()[self._kept]
        if self.observation_layout == "fields":
            obs = np.concatenate([obs, self._onehot[self._field]])
        elif self.observe_field:
            obs = np.append(obs, float(self._field))
        return np.clip(obs.astype(np.float32), self.observation_space.low, self.observation_space.high)

    def _check_hole(self, system, region_index, hole):
        try:
            system.field.check_hole((float(hole[0]), float(hole[1])))
        except ValueError as e:
            raise ValueError(f"PuttEnv.reset: options['hole']: {e}") from None
        b = self._regions[region_index].bounds  # this field's situations, not the union's
        if not (b[0] - 1e-9 <= hole[0] <= b[1] + 1e-9 and b[2] - 1e-9 <= hole[1] <= b[3] + 1e-9):
            raise ValueError(
                f"PuttEnv.reset: options['hole']: ({hole[0]:g}, {hole[1]:g}) lies outside this environment's "
                f"situations (holes x {b[0]:g}..{b[1]:g}, y {b[2]:g}..{b[3]:g} m on {system.field.name}); "
                f"make the environment with situations='box:X0,X1:Y0,Y1:NX,NY' to widen them")

    # ---- the Gymnasium API
    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode: draws a field and a hole (options: "field" index, "hole" (x, y) [m]
        to choose them; a hole is checked against the lane and the situations). Returns
        (observation, info)."""
        if _gym is not None:
            super().reset(seed=seed)
        elif seed is not None or self._np_random is None:
            self._np_random = np.random.default_rng(seed)
        options = options or {}
        unknown = set(options) - {"field", "hole"}
        if unknown:
            raise ValueError(f"PuttEnv.reset: options: unknown key(s) {sorted(unknown)} (expected 'field', 'hole')")
        rng = self.np_random
        n = len(self.systems)
        self._field = int(rng.integers(n)) if n > 1 else 0
        if "field" in options:
            k = options["field"]
            if not isinstance(k, (int, np.integer)) or isinstance(k, bool) or not 0 <= k < n:
                raise ValueError(f"PuttEnv.reset: options['field']: expected an index 0..{n - 1}, got {k!r}")
            self._field = int(k)
        system = self.systems[self._field]
        stream = int(rng.integers(0, 2**63 - 1))
        hole = self._regions[self._field].sample(1, stream)[0]
        if "hole" in options:
            try:
                hole = np.asarray(options["hole"], dtype=np.float64)
            except (TypeError, ValueError):
                hole = None
            if hole is None or hole.shape != (2,) or not np.all(np.isfinite(hole)):
                raise ValueError(f"PuttEnv.reset: options['hole']: expected (x, y) [m], got {options['hole']!r}")
            self._check_hole(system, self._field, hole)
        self._hole = np.asarray(hole, dtype=np.float64)
        self._done = False
        self._trajectory = None
        self._frames = []
        if self.render_mode in ("rgb_array_list", "human"):
            self._emit(self._frame())
        return self._observation(), {"hole": self._hole.copy(), "xi": self._xi(), "field": system.field.name,
                                     "field_index": self._field}

    def step(self, action):
        """Putts. Returns (obs, reward, terminated, truncated, info); the episode always terminates."""
        if self._done:
            raise RuntimeError("PuttEnv.step: the episode is over (one putt per episode); call reset()")
        try:
            a = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            a = None
        if a is None or a.shape != (2,) or not np.all(np.isfinite(a)):
            what = "[-1, 1]^2" if self.normalize_actions else "(theta [rad], v [m/s])"
            raise ValueError(f"PuttEnv.step: action: expected finite {what} of shape (2,), got {action!r}")
        putt = self.to_physical(a)
        if self.normalize_actions:
            clipped = bool(np.any(np.abs(a) > 1.0))
        else:
            clipped = bool(np.any(putt != a))
        system, data = self.systems[self._field], self._data[self._field]
        info: dict[str, Any] = {"hole": self._hole.copy(), "xi": self._xi(), "field": system.field.name,
                                "field_index": self._field, "action": np.array(putt), "clipped": clipped}
        record = 1.0 / self.metadata["render_fps"] / 2 if self.render_mode is not None else 0.0
        club = None
        if self._skills is not None:  # a club hit, launched as the robot's skill says
            skill, hit = self._skills[self._field], putt
            putt = np.array([hit[0] + skill.angle_offset(hit[1]), skill.launch_speed(hit[1])])
            club = skill.club_launch(putt[1]) if self.mode == "fast" else None
            info["club"] = np.array(hit)
            info["action"] = np.array(putt)
        if self.mode == "fast":
            sunk, end, rest, approach, path = _minigolf.fast_putt(
                system, float(putt[0]), float(putt[1]), hole=tuple(self._hole), club=club,
                max_duration=self.max_duration, record_interval=record, data=data)
            info.update(closest_approach=approach, rest_position=np.array(rest), end=end)
            self._trajectory = None
            if record > 0:
                z = np.asarray(system.field.height(path[:, 1], path[:, 2])) + system.field.ball_radius
                self._trajectory = np.column_stack([path, z, np.zeros((len(path), 3))])
        else:
            try:
                r = system.putt(float(putt[0]), float(putt[1]), hole=tuple(self._hole),
                                ball_only=self.mode == "ball", max_duration=self.max_duration,
                                record_interval=record, data=data)
                sunk, approach = r.sunk, r.closest_approach
                info.update(closest_approach=approach, rest_position=np.array(r.rest_position), end=r.end)
                self._trajectory = r.trajectory if record > 0 else None
            except _minigolf.NumericalError as e:  # the club did not reach the ball: a miss
                sunk, approach = False, float(np.hypot(*self._xi()))
                info.update(closest_approach=float("nan"), rest_position=np.array(system.field.tee), end="no contact",
                            error=str(e))
                self._trajectory = None
        if self.reward_mode == "sparse":
            parts = {"sunk": 1.0 if sunk else 0.0, "approach": 0.0}
        else:
            parts = {"sunk": 1.0 if sunk else 0.0, "approach": 0.0 if sunk else -approach / self.reward_scale}
        info["sunk"] = bool(sunk)
        info["reward_parts"] = parts
        self._done = True
        if self.render_mode in ("rgb_array_list", "human"):
            self._play_putt()
        return self._observation(), float(parts["sunk"] + parts["approach"]), True, False, info

    # ---- rendering
    def _ensure_renderer(self):
        if self._renderer is None:
            w, h = self._init_kwargs["render_size"]
            self._renderer = _Renderers(self.systems, w, h, self.render_mode == "human", self._init_kwargs["camera"])
        return self._renderer

    def _frame(self, ball=None, path=None):
        """The frame now, or with the ball at `ball` [m] and `path` drawn (None in human mode: the
        frame went to the window)."""
        renderers = self._ensure_renderer()
        if ball is None and self._trajectory is not None and len(self._trajectory):
            path = self._trajectory[:, 1:4]
            ball = tuple(path[-1])
        arm_pose = self._data[self._field].arm if (self.mode == "arm" and self._done) else None
        return renderers.draw(self._field, self._hole, arm_pose, ball, path)

    def _emit(self, frame):
        if self.render_mode == "rgb_array_list":
            self._frames.append(frame)

    def _play_putt(self):
        """The putt's frames at render_fps: the ball along its recorded path."""
        fps = self.metadata["render_fps"]
        traj = self._trajectory
        if traj is None or len(traj) == 0:
            self._emit(self._frame())
            return
        t = traj[:, 0] - traj[0, 0]
        start = time.monotonic()
        for k, tk in enumerate(np.arange(0.0, t[-1] + 1e-9, 1.0 / fps)):
            i = int(np.searchsorted(t, tk, side="right"))
            ball = tuple(traj[max(i - 1, 0), 1:4])
            frame = self._frame(ball=ball, path=traj[:max(i, 1), 1:4])
            self._emit(frame)
            if self.render_mode == "human":
                time.sleep(max(0.0, start + (k + 1) / fps - time.monotonic()))
        self._emit(self._frame())

    def render(self):
        """rgb_array: the current frame, (height, width, 3) uint8. rgb_array_list: the frames since
        the last call (reset's and the putt's). human: draws the current frame in the window.
        None without a render_mode."""
        if self.render_mode is None:
            return None
        if self.render_mode == "rgb_array_list":
            frames, self._frames = self._frames, []
            return frames
        return self._frame()

    def close(self):
        """Frees the renderer (its OpenGL context and window); the env can still putt and render."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


class _Renderers:
    """One minigolf.Renderer per field (each draws its own world), and a Data per field holding the
    start pose with the episode's hole."""

    def __init__(self, systems, width, height, visible, camera):
        self._systems = systems
        self._renderers = [_minigolf.Renderer(s.arm_world, width, height, visible=visible, camera=camera)
                           for s in systems]
        self._start = [s.arm_world.make_data() for s in systems]
        self.visible = visible
        self.closed = False

    def draw(self, k, hole, arm_pose, ball, path):
        """The frame of field k (None for a window: drawn there). arm_pose: the arm's Data after
        the hit (its hole is the episode's), else the start pose with `hole`."""
        data = arm_pose
        if data is None:
            world, data = self._systems[k].arm_world, self._start[k]
            world.reset(data)
            world.set_hole(data, (float(hole[0]), float(hole[1])))
        args = dict(ball=None if ball is None else tuple(float(c) for c in ball),
                    path=np.zeros((0, 2)) if path is None else np.asarray(path, dtype=np.float64))
        r = self._renderers[k]
        if self.visible:
            r.show(data, **args)
            return None
        return r.render(data, **args)

    def close(self):
        for r in self._renderers:
            r.close()
        self.closed = True


def register_envs() -> bool:
    """Registers REGISTERED with gymnasium (done on `import minigolf`). False without gymnasium."""
    if _gym is None:
        return False
    for env_id, kwargs in REGISTERED.items():
        if env_id not in _gym.registry:
            entry, steps = ENTRY_POINTS[env_id]
            _gym.register(id=env_id, entry_point=entry, kwargs=dict(kwargs), max_episode_steps=steps)
    return True


def make_vec(env_id: str, num_envs: int = 1, vectorization_mode: str = "sync",
             autoreset_mode: str = "same-step", **kwargs):
    """gymnasium.make_vec with same-step autoreset by default: an ended episode is reset within
    the step that ends it (its last observation and info in info["final_obs"], info["final_info"]),
    so every vector step plays a putt. Gymnasium's own default (next-step) spends every second
    vector step of the one-putt ids on resets (reward 0). autoreset_mode: "same-step",
    "next-step" or "disabled". Needs gymnasium >= 1.1."""
    if _gym is None:
        raise ImportError("minigolf.make_vec: needs gymnasium (pip install gymnasium)")
    from gymnasium.vector import AutoresetMode
    modes = {"same-step": AutoresetMode.SAME_STEP, "next-step": AutoresetMode.NEXT_STEP,
             "disabled": AutoresetMode.DISABLED}
    if autoreset_mode not in modes:
        raise ValueError(f"minigolf.make_vec: autoreset_mode: expected one of {sorted(modes)}, got '{autoreset_mode}'")
    vector_kwargs = {"autoreset_mode": modes[autoreset_mode], **kwargs.pop("vector_kwargs", {})}
    return _gym.make_vec(env_id, num_envs=num_envs, vectorization_mode=vectorization_mode,
                         vector_kwargs=vector_kwargs, **kwargs)


def make(env_id: str, **kwargs):
    """A registered environment without gymnasium (gymnasium.make adds its wrappers: the order
    enforcer, the passive checker and, for the putts, the one-step time limit). kwargs override
    the id's."""
    if env_id not in REGISTERED:
        raise ValueError(f"minigolf.make: unknown id '{env_id}' (expected one of {sorted(REGISTERED)})")
    if ENTRY_POINTS[env_id][0].endswith(":RoundEnv"):
        from .round_env import RoundEnv
        return RoundEnv(**{**REGISTERED[env_id], **kwargs})
    return PuttEnv(**{**REGISTERED[env_id], **kwargs})
