"""A Gymnasium environment of a round of minigolf: a hole (or a course) played stroke by stroke
(docs/python.md, "The round environment").

    import minigolf
    env = minigolf.make("minigolf/Round-v0")          # bank-shot, the ball alone (MuJoCo)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

The rules are the round's own (`minigolf play`, docs/round.md), through the library:
`minigolf.end_of_stroke` decides whether a ball is out of play (it left the lane, or stopped where
it cannot roll to the hole) and where the next stroke is played from; `minigolf.LaneRegion` is
the playable part of the lane. Reward -1 per stroke and -1 per penalty stroke, a hole's total
capped at `max_strokes` (the course's, 6 by default) as the round counts it; terminated when the
(last) hole is sunk, truncated when it ends unsunk at `max_strokes`.

Observation (float32, `observation_names`, the same layout on every field; OBSERVATION_NAMES):
ball_x, ball_y, hole_x, hole_y [m], to_hole_x, to_hole_y (hole - ball) [m], distance [m],
line_blocked (1 when an obstacle lies on the straight line to the hole), stroke_fraction (strokes
so far / max_strokes), lane_x_min, lane_x_max, lane_y_min, lane_y_max [m] (the lane's borders),
then a one-hot of the field: one entry per shipped field (`field_<name>`) and `field_other`.
Bounds: the union of the shipped fields' lanes (and of the environment's own fields).

Action (float32, [-1, 1]^2): a[0] the direction relative to the line from the ball to the hole,
times pi (0: straight at the hole); a[1] the speed, linear from its least (-1) to its most (+1):
the ball's launch speed in [0.35, 4.2] m/s (the planner's range) for player "ball" and "fast", the
club speed the arm gives (the safe envelope, capped by its top speed: `club_speed_range`) for
player "arm". `to_physical`/`from_physical` map actions to
(direction [rad, world], speed [m/s]) and back for the current ball and hole.
"""
from __future__ import annotations

import math
from typing import Any, Optional, Sequence

import numpy as np

from . import _minigolf
from .env import _Base, _Space, _float32_around, _gym

PLAYERS = ("ball", "fast", "arm")
LAUNCH_SPEEDS = (0.35, 4.2)  # [m/s] the planner's launch speeds (game::PlannerOptions)
PATH_INTERVAL = 0.01         # [s] between path points, as the round records them
DEFAULT_MAX_STROKES = 6      # a single field's hole (a course says its own)
_UNPICKLED = ("_systems", "_data", "_renderer", "_lanes", "_region")

_BASE_NAMES = ("ball_x", "ball_y", "hole_x", "hole_y", "to_hole_x", "to_hole_y", "distance",
               "line_blocked", "stroke_fraction", "lane_x_min", "lane_x_max", "lane_y_min",
               "lane_y_max")
_shipped_cache: dict = {}


def shipped_fields() -> tuple:
    """Names and lane bounds (x_min, x_max, y_min, y_max) [m] of the shipped fields (cached)."""
    if not _shipped_cache:
        names = tuple(sorted(_minigolf.Field.shipped()))
        _shipped_cache["names"] = names
        _shipped_cache["bounds"] = np.array([_minigolf.Field.load(n).bounds for n in names], dtype=np.float64)
    return _shipped_cache["names"], _shipped_cache["bounds"]


def observation_names() -> tuple:
    """The observation's names, the same for every field (shipped fields' one-hot last)."""
    names, _ = shipped_fields()
    return _BASE_NAMES + tuple(f"field_{n}" for n in names) + ("field_other",)


def observation_bounds(extra_bounds: Sequence = ()) -> tuple:
    """float64 (low, high) of the observation: the union of the shipped lanes and `extra_bounds`."""
    _, b = shipped_fields()
    if len(extra_bounds):
        b = np.vstack([b, np.asarray(extra_bounds, dtype=np.float64).reshape(-1, 4)])
    x0, x1, y0, y1 = b[:, 0].min(), b[:, 1].max(), b[:, 2].min(), b[:, 3].max()
    w, h = x1 - x0, y1 - y0
    n_fields = len(shipped_fields()[0]) + 1
    low = [x0, y0, x0, y0, -w, -h, 0.0, 0.0, 0.0, x0, x0, y0, y0] + [0.0] * n_fields
    high = [x1, y1, x1, y1, w, h, math.hypot(w, h), 1.0, 1.0, x1, x1, y1, y1] + [1.0] * n_fields
    return np.array(low), np.array(high)


class RoundEnv(_Base):
    """A hole (or a course) played stroke by stroke (see the module docstring).

    field: a shipped field name or path: one hole from its tee to its hole (default), or with
        `situations` / `balls` (`--situations` specs, e.g. "box:1.5,2.5:-0.3,0.3:3,3") a hole and
        a ball drawn from those regions every episode (docs/play.md, "Where the ball lies").
    course: a course (shipped name or path): its holes in order, one episode; replaces `field`.
    player: "ball" (the ball launched in the true world, MuJoCo), "fast" (the same on the planning
        path, sim::fast_putt: ~10x faster, MuJoCo's outcome in > 99 % of putts) or "arm" (the WAM
        hits: it stands beside the ball facing the direction, the speed is its club speed).
    max_strokes: a hole ends after this many strokes, penalties included (default: the course's,
        or 6).
    plant: the world as it really is (docs/reality.md); config, hitting_model: as for System.
    render_mode: None or "rgb_array" (the lane, the ball and its last path); render_size, camera.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 4}

    def __init__(self, field: str = "bank-shot", course: Optional[str] = None, player: str = "ball",
                 situations: str = "", balls: str = "", max_strokes: Optional[int] = None,
                 plant: str = "", config: str = "", hitting_model: str = "",
                 render_mode: Optional[str] = None, render_size: Sequence[int] = (320, 240),
                 camera: str = "top"):
        self._init_kwargs = dict(field=field, course=course, player=player, situations=situations, balls=balls,
                                 max_strokes=max_strokes, plant=plant, config=config,
                                 hitting_model=hitting_model, render_mode=render_mode,
                                 render_size=tuple(render_size), camera=camera)
        if player not in PLAYERS:
            raise ValueError(f"RoundEnv: player: expected one of {PLAYERS}, got '{player}'")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"RoundEnv: render_mode: expected None or 'rgb_array', got '{render_mode}'")
        if course is not None and (situations or balls):
            raise ValueError("RoundEnv: situations/balls: not with a course (its holes say where)")
        if camera not in ("overview", "side", "top", "follow"):
            raise ValueError(f"RoundEnv: camera: expected overview, side, top or follow, got '{camera}'")
        self.player = player
        self.render_mode = render_mode
        self._plant_text = _minigolf.read_plant_file(plant) if plant else None
        if course is not None:
            c = _minigolf.load_course(course)
            self.course = c["name"]
            self.holes = [dict(field=h["field"], tee=tuple(h["tee"]), hole=tuple(h["hole"]), par=int(h["par"]))
                          for h in c["holes"]]
            default_max = int(c["max_strokes"])
        else:
            self.course = None
            self.holes = [dict(field=field, tee=None, hole=None, par=3)]
            default_max = DEFAULT_MAX_STROKES
        self.max_strokes = default_max if max_strokes is None else max_strokes
        if not isinstance(self.max_strokes, (int, np.integer)) or not 1 <= self.max_strokes <= 100:
            raise ValueError(f"RoundEnv: max_strokes: expected 1..100, got {max_strokes!r}")
        self._build()
        for h in self.holes:  # a single field's own tee and hole
            f = self._systems[h["field"]].field
            h["tee"] = h["tee"] or tuple(f.tee)
            h["hole"] = h["hole"] or tuple(f.hole_position)
            h["field_name"] = f.name
        self._set_spaces()
        self._np_random = None
        self._hole_index = 0
        self._ball = np.array(self.holes[0]["tee"], dtype=np.float64)
        self._hole = np.array(self.holes[0]["hole"], dtype=np.float64)
        self._strokes = 0
        self._total = 0
        self._done = True
        self._path = np.zeros((0, 2))

    # ---- construction (also what unpickling rebuilds)
    def _build(self):
        k = self._init_kwargs
        self._systems, self._data = {}, {}
        for h in self.holes:
            if h["field"] not in self._systems:
                s = _minigolf.System(field=h["field"], config=k["config"], hitting_model=k["hitting_model"],
                                     plant=k["plant"], plant_text=self._plant_text)
                self._systems[h["field"]] = s
                self._data[h["field"]] = s.make_data()
        self._lanes = {}    # (field, hole) -> (LaneRegion, cup)
        self._renderer = None
        self._region = None  # where holes and balls are drawn (situations, balls)
        if k["situations"] or k["balls"]:
            self._region = self._systems[k["field"]].field.region(k["situations"], k["balls"])

    def _set_spaces(self):
        names, _ = shipped_fields()
        self.observation_names = observation_names()
        low, high = observation_bounds([s.field.bounds for s in self._systems.values()])
        olow, ohigh = _float32_around(low, high)
        self.observation_space = _Space(low=olow, high=ohigh, dtype=np.float32)
        self.action_space = _Space(low=np.full(2, -1.0, np.float32), high=np.full(2, 1.0, np.float32),
                                   dtype=np.float32)
        if self.player == "arm":  # what the arm really gives (the envelope, capped by its top speed)
            self.speed_range = tuple(float(v) for v in _minigolf.club_speed_range(next(iter(self._systems.values()))))
        else:
            self.speed_range = LAUNCH_SPEEDS
        self._onehot = {}
        for key, s in self._systems.items():
            v = np.zeros(len(names) + 1)
            fname = s.field.name
            shipped = fname in names and _minigolf.Field.load(fname).source == s.field.source
            v[names.index(fname) if shipped else len(names)] = 1.0
            self._onehot[key] = v

    def __getstate__(self):
        return {k: v for k, v in self.__dict__.items() if k not in _UNPICKLED}

    def __setstate__(self, state):
        self.__dict__.update(state)
        self._build()

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

    # ---- state
    @property
    def system(self):
        """The System of the hole being played (its field; the plant's world)."""
        return self._systems[self.holes[self._hole_index]["field"]]

    @property
    def ball(self) -> np.ndarray:
        """Where the ball lies [m]."""
        return self._ball.copy()

    @property
    def hole(self) -> np.ndarray:
        """Where the hole is [m] (as the field says; a plant may move where the ball drops)."""
        return self._hole.copy()

    @property
    def strokes(self) -> int:
        """Strokes on this hole so far, penalties included."""
        return self._strokes

    def _lane(self):
        key = (self.holes[self._hole_index]["field"], float(self._hole[0]), float(self._hole[1]))
        if key not in self._lanes:
            s = self.system
            hole = (key[1], key[2])
            self._lanes[key] = (_minigolf.LaneRegion(s.field, hole), tuple(_minigolf.real_hole(s, hole)))
        return self._lanes[key]

    # ---- the action and observation maps
    def to_physical(self, action) -> np.ndarray:
        """(direction [rad, world], speed [m/s]) of an action (clipped into [-1, 1]) from the ball."""
        a = np.clip(np.asarray(action, dtype=np.float64), -1.0, 1.0)
        d = self._hole - self._ball
        direction = math.remainder(math.atan2(d[1], d[0]) + math.pi * a[0], 2.0 * math.pi)
        lo, hi = self.speed_range
        return np.array([direction, 0.5 * (1.0 - a[1]) * lo + 0.5 * (1.0 + a[1]) * hi])

    def from_physical(self, stroke) -> np.ndarray:
        """The action that plays (direction [rad, world], speed [m/s]) from the ball (inverse of
        to_physical; clipped into [-1, 1])."""
        p = np.asarray(stroke, dtype=np.float64)
        d = self._hole - self._ball
        rel = math.remainder(p[0] - math.atan2(d[1], d[0]), 2.0 * math.pi) / math.pi
        lo, hi = self.speed_range
        return np.clip([rel, 2.0 * (p[1] - lo) / (hi - lo) - 1.0], -1.0, 1.0).astype(np.float32)

    def _observation(self) -> np.ndarray:
        f = self.system.field
        d = self._hole - self._ball
        blocked = _minigolf.line_blocked(f, tuple(self._ball), tuple(self._hole), f.ball_radius)
        obs = np.concatenate([self._ball, self._hole, d, [math.hypot(*d), float(blocked),
                                                          self._strokes / self.max_strokes],
                              np.asarray(f.bounds, dtype=np.float64),
                              self._onehot[self.holes[self._hole_index]["field"]]])
        return np.clip(obs.astype(np.float32), self.observation_space.low, self.observation_space.high)

    def _info(self) -> dict:
        h = self.holes[self._hole_index]
        return {"ball": self._ball.copy(), "hole": self._hole.copy(), "strokes": self._strokes,
                "hole_index": self._hole_index, "par": h["par"], "total_strokes": self._total}

    def _start_hole(self, k: int, ball=None, hole=None):
        self._hole_index = k
        h = self.holes[k]
        self._ball = np.array(h["tee"] if ball is None else ball, dtype=np.float64)
        self._hole = np.array(h["hole"] if hole is None else hole, dtype=np.float64)
        self._strokes = 0
        self._path = np.zeros((0, 2))

    # ---- the Gymnasium API
    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode at the first hole's tee (or a ball and hole drawn from the
        situations). options: "ball", "hole" (x, y) [m] to choose them (checked: ValueError).
        Returns (observation, info)."""
        if _gym is not None:
            super().reset(seed=seed)
        elif seed is not None or self._np_random is None:
            self._np_random = np.random.default_rng(seed)
        options = options or {}
        unknown = set(options) - {"ball", "hole"}
        if unknown:
            raise ValueError(f"RoundEnv.reset: options: unknown key(s) {sorted(unknown)} (expected 'ball', 'hole')")
        ball = hole = None
        stream = int(self.np_random.integers(0, 2**63 - 1))  # drawn always: an episode's stream
        if self._region is not None:
            row = self.system.field.sample_situations(self._region, 1, stream)[0]
            ball, hole = row[:2], row[2:]
        for key in ("ball", "hole"):
            if key in options:
                try:
                    v = np.asarray(options[key], dtype=np.float64)
                except (TypeError, ValueError):
                    v = None
                if v is None or v.shape != (2,) or not np.all(np.isfinite(v)):
                    raise ValueError(f"RoundEnv.reset: options['{key}']: expected (x, y) [m], got {options[key]!r}")
                if key == "ball":
                    ball = v
                else:
                    hole = v
        self._start_hole(0, ball, hole)
        f = self.system.field
        try:
            f.check_hole(tuple(self._hole))
            region = self._lane()[0]
        except ValueError as e:
            raise ValueError(f"RoundEnv.reset: hole: {e}") from None
        if not region.contains(tuple(self._ball)):
            raise ValueError(f"RoundEnv.reset: ball ({self._ball[0]:g}, {self._ball[1]:g}) is not in play "
                             f"for the hole at ({self._hole[0]:g}, {self._hole[1]:g}) on {f.name}")
        self._total = 0
        self._done = False
        return self._observation(), self._info()

    def _putt(self, direction: float, speed: float):
        """One stroke: (sunk, end, rest, path (N, 2), launch (direction, speed))."""
        s, data = self.system, self._data[self.holes[self._hole_index]["field"]]
        ball, hole = tuple(self._ball), tuple(self._hole)
        if self.player == "fast":
            sunk, end, rest, _, path = _minigolf.fast_putt(s, direction, speed, hole=hole, ball=ball,
                                                           record_interval=PATH_INTERVAL, data=data)
            return sunk, end, np.asarray(rest), path[:, 1:3], (direction, speed)
        if self.player == "ball":
            r = s.putt(direction, speed, hole=hole, ball=ball, ball_only=True,
                       record_interval=PATH_INTERVAL, data=data)
            return r.sunk, r.end, np.asarray(r.rest_position), r.trajectory[:, 1:3], (direction, speed)
        try:  # the arm: it stands beside the ball facing `direction`, hitting angle 0
            r = s.putt(0.0, speed, hole=hole, ball=ball, aim=direction, record_interval=PATH_INTERVAL, data=data)
        except _minigolf.NumericalError:  # the club missed the ball: the stroke counts, the ball stays
            return False, "at_rest", self._ball.copy(), np.zeros((0, 2)), (direction, 0.0)
        launch = (math.remainder(r.launch[0] + r.aim, 2.0 * math.pi), r.launch[1])  # the base's frame -> world
        return r.sunk, r.end, np.asarray(r.rest_position), r.trajectory[:, 1:3], launch

    def step(self, action):
        """Plays one stroke. Returns (obs, reward, terminated, truncated, info)."""
        if self._done:
            raise RuntimeError("RoundEnv.step: the episode is over; call reset()")
        try:
            a = np.asarray(action, dtype=np.float64)
        except (TypeError, ValueError):
            a = None
        if a is None or a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ValueError(f"RoundEnv.step: action: expected finite [-1, 1]^2 of shape (2,), got {action!r}")
        direction, speed = self.to_physical(a)
        start = self._ball.copy()
        sunk, end, rest, path, launch = self._putt(float(direction), float(speed))
        before = self._strokes
        self._strokes += 1
        left_lane = False
        if not sunk:
            region, cup = self._lane()
            left_lane, nxt = _minigolf.end_of_stroke(self.system.field, region, cup, tuple(start), end,
                                                     tuple(rest), np.ascontiguousarray(path))
            self._ball = np.asarray(nxt, dtype=np.float64)
            self._strokes += int(left_lane)  # the penalty stroke
        self._strokes = min(self._strokes, self.max_strokes)
        reward = float(before - self._strokes)
        self._total += self._strokes - before
        self._path = np.asarray(path, dtype=np.float64).reshape(-1, 2)
        info = self._info()
        info.update(sunk=bool(sunk), left_lane=bool(left_lane), penalty=int(left_lane),
                    start=start, rest=np.asarray(rest, dtype=np.float64), launch=np.asarray(launch, dtype=np.float64),
                    clipped=bool(np.any(np.abs(a) > 1.0)))
        hole_over = sunk or self._strokes >= self.max_strokes
        terminated = truncated = False
        if hole_over:
            info["hole_strokes"] = self._strokes
            if self._hole_index + 1 < len(self.holes):
                self._start_hole(self._hole_index + 1)
            else:
                self._done = True
                terminated, truncated = bool(sunk), not sunk
        return self._observation(), reward, terminated, truncated, info

    # ---- rendering
    def render(self):
        """rgb_array: the lane with the ball where it lies and its last stroke's path, (height,
        width, 3) uint8 (the arm stands at its start pose for player "arm"). None without a
        render_mode."""
        if self.render_mode is None:
            return None
        k = self._init_kwargs
        s = self.system
        world = s.arm_world if self.player == "arm" else s.ball_world
        key = self.holes[self._hole_index]["field"]
        if self._renderer is None:
            self._renderer = {}
        if key not in self._renderer:
            w, h = k["render_size"]
            self._renderer[key] = (_minigolf.Renderer(world, int(w), int(h), visible=False, camera=k["camera"]),
                                   world.make_data())
        renderer, data = self._renderer[key]
        world.reset(data)
        world.set_hole(data, tuple(float(c) for c in self._hole))
        z = s.field.ball_radius
        ball = (float(self._ball[0]), float(self._ball[1]),
                float(s.field.height(self._ball[0], self._ball[1])) + z)
        path = np.zeros((0, 3))
        if len(self._path):
            path = np.column_stack([self._path, np.asarray(s.field.height(self._path[:, 0], self._path[:, 1])) + z])
        return renderer.render(data, ball=ball, path=path)

    def close(self):
        """Frees the renderers (OpenGL contexts); the env can still play and render."""
        if self._renderer:
            for r, _ in self._renderer.values():
                r.close()
        self._renderer = None
