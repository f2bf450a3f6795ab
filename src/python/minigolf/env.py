"""A Gymnasium-compatible minigolf environment: one putt per episode.

    env = PuttEnv(field="flat")
    obs, info = env.reset(seed=0)          # obs: the situation xi = hole - tee [m]
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Observation: xi = (hole_x - tee_x, hole_y - tee_y) [m]; with several fields (or observe_field=True)
also the field's index (a float) as a third entry. The hole is drawn uniformly from the field's
region of situations (the library's own sampler, seeded from the environment's generator).
Action: (theta [rad], v [m/s]) inside the module's safe envelope (the arm: hitting angle and club
speed; mode="ball": the ball's launch angle and speed, same bounds); actions outside the box are
clipped to it (info["clipped"]). Reward: 1.0 if the ball is sunk, else 0.0; every episode
terminates after its putt (truncated is always False). info: closest_approach [m], rest_position
[m], end, hole [m], field, action (as putted).

When `gymnasium` can be imported the class subclasses `gymnasium.Env` and its spaces are
`gymnasium.spaces.Box`; otherwise it provides the same interface with the `Box` below. The
generator is numpy's `default_rng(seed)` either way (what Gymnasium's seeding makes), so a seed
gives the same episodes with or without Gymnasium.
"""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from . import _minigolf

try:  # pragma: no cover - gymnasium is not in Debian 12
    import gymnasium as _gym
    from gymnasium.spaces import Box as _GymBox
except ImportError:  # the same interface without it
    _gym = None
    _GymBox = None


class Box:
    """A box in R^n (Gymnasium's `spaces.Box` interface: shape, dtype, low, high, seed(),
    sample(), contains(), `in`)."""

    def __init__(self, low, high, shape: Optional[Sequence[int]] = None, dtype=np.float64, seed=None):
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


_Base = _gym.Env if _gym is not None else object
_Space = _GymBox if _GymBox is not None else Box


class PuttEnv(_Base):
    """One putt per episode on the simulated WAM (see the module docstring).

    field: a shipped field name or path, or a sequence of them (each episode draws one).
    mode: "arm" (the full system: the WAM hits the ball) or "ball" (the ball alone: fast).
    observe_field: append the field's index to the observation (default: with several fields).
    config, hitting_model, plant: as for `minigolf.System` (plant: the world as it really is).
    max_duration: of the ball's roll [s].
    """

    metadata = {"render_modes": []}

    def __init__(self, field="flat", mode: str = "arm", observe_field: Optional[bool] = None,
                 config: str = "", hitting_model: str = "", max_duration: float = 30.0,
                 render_mode: Optional[str] = None, plant: str = ""):
        if mode not in ("arm", "ball"):
            raise ValueError(f"PuttEnv: mode: expected 'arm' or 'ball', got '{mode}'")
        if render_mode is not None:
            raise ValueError(f"PuttEnv: render_mode: expected None (no rendering), got '{render_mode}'")
        names = [field] if isinstance(field, str) else list(field)
        if not names:
            raise ValueError("PuttEnv: field: expected at least one field")
        self.render_mode = None
        self.mode = mode
        self.max_duration = float(max_duration)
        self.systems = [_minigolf.System(field=n, config=config, hitting_model=hitting_model, plant=plant)
                        for n in names]
        self._data = [s.make_data() for s in self.systems]
        self.observe_field = len(names) > 1 if observe_field is None else bool(observe_field)
        lows, highs = [], []
        for s in self.systems:
            xi = s.field.situations.collection_points() - np.asarray(s.field.tee)
            lows.append(xi.min(axis=0))
            highs.append(xi.max(axis=0))
        low, high = np.min(lows, axis=0), np.max(highs, axis=0)
        if self.observe_field:
            low, high = np.append(low, 0.0), np.append(high, float(len(names) - 1))
        self.observation_space = _Space(low=low, high=high, dtype=np.float64)
        e = self.systems[0].envelope
        self.action_space = _Space(low=np.array([e["angle_min"], e["speed_min"]]),
                                   high=np.array([e["angle_max"], e["speed_max"]]), dtype=np.float64)
        self._np_random = None
        self._field = 0
        self._hole = np.asarray(self.systems[0].field.hole_position, dtype=np.float64)
        self._done = True

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

    def _observation(self) -> np.ndarray:
        xi = self._hole - np.asarray(self.systems[self._field].field.tee)
        if self.observe_field:
            xi = np.append(xi, float(self._field))
        return xi.astype(np.float64)

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        """Starts an episode: draws a field and a hole (options: "field" index, "hole" (x, y) [m]
        to choose them). Returns (observation, info)."""
        if _gym is not None:
            super().reset(seed=seed)
        elif seed is not None or self._np_random is None:
            self._np_random = np.random.default_rng(seed)
        options = options or {}
        rng = self.np_random
        n = len(self.systems)
        self._field = int(rng.integers(n)) if n > 1 else 0
        if "field" in options:
            k = options["field"]
            if not isinstance(k, (int, np.integer)) or not 0 <= k < n:
                raise ValueError(f"PuttEnv.reset: options['field']: expected an index 0..{n - 1}, got {k!r}")
            self._field = int(k)
        system = self.systems[self._field]
        stream = int(rng.integers(0, 2**63 - 1))
        hole = system.field.situations.sample(1, stream)[0]
        if "hole" in options:
            hole = np.asarray(options["hole"], dtype=np.float64)
            if hole.shape != (2,) or not np.all(np.isfinite(hole)):
                raise ValueError(f"PuttEnv.reset: options['hole']: expected (x, y) [m], got {options['hole']!r}")
            try:
                system.field.check_hole((float(hole[0]), float(hole[1])))
            except ValueError as e:
                raise ValueError(f"PuttEnv.reset: options['hole']: {e}") from None
        self._hole = np.asarray(hole, dtype=np.float64)
        self._done = False
        return self._observation(), {"hole": tuple(self._hole), "field": system.field.name}

    def step(self, action):
        """Putts with (theta [rad], v [m/s]). Returns (obs, reward, terminated, truncated, info)."""
        if self._done:
            raise RuntimeError("PuttEnv.step: the episode is over (one putt per episode); call reset()")
        a = np.asarray(action, dtype=np.float64)
        if a.shape != (2,) or not np.all(np.isfinite(a)):
            raise ValueError(f"PuttEnv.step: action: expected finite (theta [rad], v [m/s]), got {action!r}")
        clipped = np.clip(a, self.action_space.low, self.action_space.high)
        system, data = self.systems[self._field], self._data[self._field]
        info: dict[str, Any] = {"hole": tuple(self._hole), "field": system.field.name,
                                "action": tuple(clipped), "clipped": bool(np.any(clipped != a))}
        try:
            r = system.putt(float(clipped[0]), float(clipped[1]), hole=tuple(self._hole),
                            ball_only=self.mode == "ball", max_duration=self.max_duration,
                            record_interval=0.0, data=data)
            sunk = r.sunk
            info.update(closest_approach=r.closest_approach, rest_position=tuple(r.rest_position), end=r.end)
        except _minigolf.NumericalError as e:  # the club did not reach the ball: a miss
            sunk = False
            info.update(closest_approach=float("nan"), rest_position=tuple(system.field.tee), end="no contact",
                        error=str(e))
        self._done = True
        return self._observation(), 1.0 if sunk else 0.0, True, False, info

    def render(self):
        return None

    def close(self):
        pass
