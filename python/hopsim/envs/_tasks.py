"""What a hopsim environment observes, rewards and ends on, for every copy of a batch at
once (the single environment is a batch of one)."""

from __future__ import annotations

from typing import Any, Callable, Dict, Optional, Sequence, Tuple

import numpy as np


class StepView:
    """The batch's arrays around one environment step, read-only for tasks: ``q_before``
    (n, nq), the coordinates before the step; ``q``, ``u`` (n, nq) and ``in_contact`` (n,)
    after it; ``actions`` (n, na), the actions of the step (as given, not clipped); ``dt``,
    the step's duration (s); ``coordinates``, their names."""

    __slots__ = ("q_before", "q", "u", "in_contact", "actions", "dt", "coordinates")

    def __init__(
        self, q_before: np.ndarray, q: np.ndarray, u: np.ndarray, in_contact: np.ndarray,
        actions: np.ndarray, dt: float, coordinates: Sequence[str],
    ) -> None:
        self.q_before, self.q, self.u, self.in_contact = q_before, q, u, in_contact
        self.actions, self.dt, self.coordinates = actions, dt, list(coordinates)


class Task:
    """Observation, reward and termination of an environment, each for all copies at once.

    ``observe(v)`` returns (n, k) observations, ``reward(v)`` (n,) rewards,
    ``terminated(v)`` (n,) flags and ``info(v)`` a dict of (n,) arrays, ``v`` a
    :class:`StepView`. ``observation_size(coordinates)`` is ``k`` for a scene of those
    coordinates (names)."""

    def observation_size(self, coordinates: Sequence[str]) -> int:
        raise NotImplementedError

    def observe(self, v: StepView) -> np.ndarray:
        raise NotImplementedError

    def reward(self, v: StepView) -> np.ndarray:
        raise NotImplementedError

    def terminated(self, v: StepView) -> np.ndarray:
        return np.zeros(len(v.q), dtype=bool)

    def info(self, v: StepView) -> Dict[str, np.ndarray]:
        return {}


def forward_speed(v: StepView, coordinate: int = 0) -> np.ndarray:
    """The mean speed of coordinate ``coordinate`` (the base's ``x``) over the step, m/s."""
    return (v.q[:, coordinate] - v.q_before[:, coordinate]) / v.dt


class StateTask(Task):
    """The default task of a model: observation = coordinates, velocities and the contact
    flag (1.0 when the world carried load in the last step), the coordinates named in
    ``exclude`` left out (a position the dynamics do not depend on, such as ``x``) and
    those in ``angles`` as their sine and cosine; reward = the forward speed
    (``reward="forward"``) or ``reward(view)``; termination = ``terminated(view)``, or
    never (a copy whose step failed always terminates). ``observation(view)`` replaces the
    observation; it must then give ``observation_size`` numbers per copy."""

    def __init__(
        self,
        reward: str | Callable[[StepView], np.ndarray] = "forward",
        terminated: Optional[Callable[[StepView], np.ndarray]] = None,
        observation: Optional[Callable[[StepView], np.ndarray]] = None,
        observation_size: Optional[int] = None,
        exclude: Sequence[str] = (),
        angles: Sequence[str] = (),
    ) -> None:
        if reward == "forward":
            reward = forward_speed
        if not callable(reward):
            raise ValueError(f"reward: expected 'forward' or a function of the step, got {reward!r}")
        if (observation is None) != (observation_size is None):
            raise ValueError("observation and observation_size go together")
        self._reward, self._terminated = reward, terminated
        self._observation, self._size = observation, observation_size
        self.exclude, self.angles = list(exclude), list(angles)
        self._known: Tuple[Sequence[str], np.ndarray, np.ndarray] | None = None

    def _columns(self, coordinates: Sequence[str]) -> Tuple[np.ndarray, np.ndarray]:
        """The coordinates observed as they are and as angles (indices), found once."""
        if self._known is not None and self._known[0] is coordinates:
            return self._known[1], self._known[2]
        unknown = [c for c in self.exclude + self.angles if c not in coordinates]
        if unknown:
            raise ValueError(f"no coordinates {unknown}; the coordinates are {list(coordinates)}")
        kept = [i for i, c in enumerate(coordinates) if c not in self.exclude + self.angles]
        angles = [list(coordinates).index(c) for c in self.angles]
        self._known = (coordinates, np.array(kept, dtype=np.intp), np.array(angles, dtype=np.intp))
        return self._known[1], self._known[2]

    def observation_size(self, coordinates: Sequence[str]) -> int:
        if self._size is not None:
            return self._size
        kept, angles = self._columns(coordinates)
        return len(kept) + 2 * len(angles) + len(coordinates) + 1

    def observe(self, v: StepView) -> np.ndarray:
        if self._observation is not None:
            return np.asarray(self._observation(v), dtype=np.float64)
        if not self.exclude and not self.angles:
            return np.concatenate((v.q, v.u, v.in_contact[:, None]), axis=1)
        kept, angles = self._columns(v.coordinates)
        n, nk, na, nq = len(v.q), len(kept), len(angles), v.q.shape[1]
        out = np.empty((n, nk + 2 * na + nq + 1))
        out[:, :nk] = v.q[:, kept]
        a = v.q[:, angles]
        np.sin(a, out=out[:, nk : nk + na])
        np.cos(a, out=out[:, nk + na : nk + 2 * na])
        out[:, nk + 2 * na : -1] = v.u
        out[:, -1] = v.in_contact
        return out

    def reward(self, v: StepView) -> np.ndarray:
        return np.asarray(self._reward(v), dtype=np.float64)

    def terminated(self, v: StepView) -> np.ndarray:
        if self._terminated is None:
            return super().terminated(v)
        return np.asarray(self._terminated(v), dtype=bool)


class HopperV5(Task):
    """Gymnasium's Hopper-v5 definitions (gymnasium/envs/mujoco/hopper_v5.py) on MuJoCo's
    ``qpos``/``qvel`` (hopsim's coordinates and velocities of the imported hopper.xml):

    * observation: ``qpos[1:]`` and ``clip(qvel, -10, 10)`` (11 numbers);
    * reward: ``forward_reward_weight · ẋ + healthy_reward · healthy −
      ctrl_cost_weight · Σ action²``, ``ẋ`` the torso's mean x speed over the step;
    * terminated: not healthy, where healthy is ``z ∈ healthy_z_range`` (``qpos[1]``),
      ``angle ∈ healthy_angle_range`` (``qpos[2]``) and every entry of
      ``(qpos, qvel)[2:]`` in ``healthy_state_range``, all open intervals.

    The defaults are v5's."""

    def __init__(
        self,
        forward_reward_weight: float = 1.0,
        ctrl_cost_weight: float = 1e-3,
        healthy_reward: float = 1.0,
        terminate_when_unhealthy: bool = True,
        healthy_state_range: Tuple[float, float] = (-100.0, 100.0),
        healthy_z_range: Tuple[float, float] = (0.7, float("inf")),
        healthy_angle_range: Tuple[float, float] = (-0.2, 0.2),
    ) -> None:
        self.forward_reward_weight, self.ctrl_cost_weight = forward_reward_weight, ctrl_cost_weight
        self.healthy_reward, self.terminate_when_unhealthy = healthy_reward, terminate_when_unhealthy
        self.healthy_state_range, self.healthy_z_range = healthy_state_range, healthy_z_range
        self.healthy_angle_range = healthy_angle_range

    def observation_size(self, coordinates: Sequence[str]) -> int:
        return 2 * len(coordinates) - 1

    def observe(self, v: StepView) -> np.ndarray:
        return np.concatenate((v.q[:, 1:], np.clip(v.u, -10.0, 10.0)), axis=1)

    def healthy(self, v: StepView) -> np.ndarray:
        z, angle = v.q[:, 1], v.q[:, 2]
        state = np.concatenate((v.q, v.u), axis=1)[:, 2:]
        inside = lambda x, r: (r[0] < x) & (x < r[1])  # noqa: E731
        return (
            inside(state, self.healthy_state_range).all(axis=1)
            & inside(z, self.healthy_z_range)
            & inside(angle, self.healthy_angle_range)
        )

    def _parts(self, v: StepView) -> Dict[str, np.ndarray]:
        forward = self.forward_reward_weight * forward_speed(v)
        survive = self.healthy(v) * self.healthy_reward
        ctrl = self.ctrl_cost_weight * np.sum(np.square(v.actions), axis=1)
        return {"reward_forward": forward, "reward_ctrl": -ctrl, "reward_survive": survive}

    def reward(self, v: StepView) -> np.ndarray:
        p = self._parts(v)
        return p["reward_forward"] + p["reward_survive"] + p["reward_ctrl"]

    def terminated(self, v: StepView) -> np.ndarray:
        if not self.terminate_when_unhealthy:
            return super().terminated(v)
        return ~self.healthy(v)

    def info(self, v: StepView) -> Dict[str, Any]:
        return {"x_position": v.q[:, 0].copy(), "x_velocity": forward_speed(v), **self._parts(v)}
