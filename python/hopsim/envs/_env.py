"""Gymnasium environments on :class:`hopsim.Batch`: one environment is a batch of one,
the vector environment a batch of ``num_envs``; both step through :class:`Rollout`, so
copy ``i`` of the vector environment equals a single environment with the same seed and
actions."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from .. import Batch, Scene
from ._tasks import StateTask, StepView, Task

Noise = Union[float, Sequence[float]]


class EnvConfig:
    """What an environment is made of: the scene (its actuators are the actions), the
    brakes ``(body, other)`` and switchable shapes driven by further actions (engaged or
    on when the action is > 0.5, each in [0, 1]), the task, ``frame_skip`` steps of the
    scene's Δt per environment step, and the reset: the scene's initial state plus noise
    uniform in ``±reset_noise_q`` and ``±reset_noise_u`` (a number or one per coordinate),
    checked as ``Simulation.set_state`` checks, or by its values only with
    ``restore_reset`` (a start in contact or at a joint stop, where noise may penetrate
    slightly, as MuJoCo's soft constraints allow)."""

    def __init__(
        self,
        scene: Scene,
        task: Optional[Task] = None,
        frame_skip: int = 1,
        brakes: Sequence[Tuple[int, int]] = (),
        switches: Sequence[int] = (),
        reset_noise_q: Noise = 0.0,
        reset_noise_u: Noise = 0.0,
        restore_reset: bool = False,
    ) -> None:
        if int(frame_skip) != frame_skip or frame_skip < 1:
            raise ValueError(f"frame_skip: expected a positive integer, got {frame_skip!r}")
        self.scene, self.task = scene, task if task is not None else StateTask()
        self.frame_skip, self.brakes, self.switches = int(frame_skip), list(brakes), list(switches)
        nq = len(scene.coordinates)
        self.noise_q = np.broadcast_to(np.asarray(reset_noise_q, dtype=np.float64), (nq,)).copy()
        self.noise_u = np.broadcast_to(np.asarray(reset_noise_u, dtype=np.float64), (nq,)).copy()
        self.restore_reset = restore_reset
        self.ctrl_low, self.ctrl_high = actuator_ranges(scene)

    @property
    def dt(self) -> float:
        """The duration of one environment step, s."""
        return self.frame_skip * self.scene.dt

    def action_space(self) -> spaces.Box:
        nb = len(self.brakes) + len(self.switches)
        low = np.concatenate((self.ctrl_low, np.zeros(nb)))
        high = np.concatenate((self.ctrl_high, np.ones(nb)))
        return spaces.Box(low, high, dtype=np.float64)

    def observation_space(self) -> spaces.Box:
        k = self.task.observation_size(self.scene.coordinates)
        return spaces.Box(-np.inf, np.inf, shape=(k,), dtype=np.float64)


def actuator_ranges(scene: Scene) -> Tuple[np.ndarray, np.ndarray]:
    """The actuators' control ranges (``ctrl_range``; ±inf where none is given), in the
    order of the controls."""
    actuators = scene.model._arrays["actuators"]
    ranges = [a.keys.get("ctrl_range", ([-np.inf, np.inf],))[0] for a in actuators]
    if not ranges:
        raise ValueError(f"the scene '{scene.title}' has no actuators to act with")
    low, high = np.array(ranges, dtype=np.float64).T
    return low, high


class Rollout:
    """``n`` copies of an environment on a :class:`hopsim.Batch`: actions in, the task's
    observations, rewards and flags out."""

    def __init__(self, config: EnvConfig, n: int, threads: Optional[int] = None) -> None:
        self.config = config
        self.batch = Batch(config.scene, n, threads, config.brakes, config.switches)
        self.nu = len(config.ctrl_low)
        self.nb = len(config.brakes)
        self.q_before = np.empty_like(self.batch.q)
        self.actions = np.zeros((n, self.nu + self.nb + len(config.switches)))
        self.view = StepView(
            self.q_before, self.batch.q, self.batch.u, self.batch.in_contact, self.actions,
            config.dt, config.scene.coordinates,
        )
        self.q0, self.u0 = config.scene.initial_q, config.scene.initial_u

    def reset(self, i: int, rng: np.random.Generator) -> None:
        """Copy ``i`` anew at the initial state with noise drawn from ``rng`` (``q`` first,
        then ``u``, as Gymnasium's MuJoCo environments draw), its brakes released and
        switchable shapes off."""
        c = self.config
        q = self.q0 + rng.uniform(-c.noise_q, c.noise_q)
        u = self.u0 + rng.uniform(-c.noise_u, c.noise_u)
        self.batch.reset(i)
        self.batch.set_state(i, q, u, restore=c.restore_reset)
        self.batch.brakes[i] = False
        self.batch.switches[i] = False
        self.actions[i] = 0.0
        self.q_before[i] = self.batch.q[i]

    def step(self, actions: np.ndarray) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One environment step of every copy: observations, rewards, terminated flags (a
        copy whose step failed is terminated)."""
        np.copyto(self.actions, actions)
        nu, nb = self.nu, self.nb
        if nb:
            np.greater(self.actions[:, nu : nu + nb], 0.5, out=self.batch.brakes)
        if self.config.switches:
            np.greater(self.actions[:, nu + nb :], 0.5, out=self.batch.switches)
        np.copyto(self.q_before, self.batch.q)
        self.batch.step(self.config.frame_skip, controls=self.actions[:, :nu])
        task = self.config.task
        terminated = np.logical_or(task.terminated(self.view), self.batch.done)
        return task.observe(self.view), task.reward(self.view), terminated

    def observe(self) -> np.ndarray:
        return self.config.task.observe(self.view)


class HopsimEnv(gymnasium.Env):
    """A Gymnasium environment of any hopsim scene with actuators (an :class:`EnvConfig`,
    or a scene and the config's keywords): action = the actuators' controls (a ``Box`` of
    their control ranges) then one number in [0, 1] per brake and switchable shape;
    observation, reward and termination from the task (default: coordinates, velocities
    and the contact flag; forward speed; never). ``reset(seed=…)`` is reproducible: the
    start's noise comes from ``self.np_random``. It steps a :class:`hopsim.Batch` of one
    copy, as :class:`HopsimVectorEnv` steps ``num_envs``."""

    metadata: Dict[str, Any] = {"render_modes": []}

    def __init__(
        self, config: EnvConfig | Scene, render_mode: Optional[str] = None, **keys: Any
    ) -> None:
        if render_mode is not None:
            raise ValueError(f"render_mode: hopsim's environments do not render, got {render_mode!r}")
        self.config = config if isinstance(config, EnvConfig) else EnvConfig(config, **keys)
        self.render_mode = None
        self.action_space = self.config.action_space()
        self.observation_space = self.config.observation_space()
        self.metadata = {"render_modes": [], "render_fps": 1.0 / self.config.dt}
        self._rollout = Rollout(self.config, 1, threads=1)

    @property
    def dt(self) -> float:
        """The duration of one step, s."""
        return self.config.dt

    @property
    def q(self) -> np.ndarray:
        """The simulation's coordinates (a copy)."""
        return self._rollout.batch.q[0].copy()

    @property
    def u(self) -> np.ndarray:
        """The simulation's velocities (a copy)."""
        return self._rollout.batch.u[0].copy()

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        super().reset(seed=seed)
        self._rollout.reset(0, self.np_random)
        return self._rollout.observe()[0], {}

    def step(self, action: Any) -> Tuple[np.ndarray, float, bool, bool, Dict[str, Any]]:
        obs, reward, terminated = self._rollout.step(np.asarray(action, dtype=np.float64)[None])
        info = {k: v[0] for k, v in self.config.task.info(self._rollout.view).items()}
        error = self._rollout.batch.error(0)
        if error is not None:
            info["error"] = error
        return obs[0], float(reward[0]), bool(terminated[0]), False, info


class HopsimVectorEnv(VectorEnv):
    """``num_envs`` copies of a :class:`HopsimEnv` stepped together on a
    :class:`hopsim.Batch` (``threads`` Rust threads, the GIL released). Copy ``i`` equals a
    :class:`HopsimEnv` reset with seed ``seed + i`` (``reset(seed=seed)``; or the list's
    ``i``-th seed) and given the same actions. Episodes end by the task's termination or
    after ``max_episode_steps`` (truncation); ended copies are reset by the
    ``autoreset_mode``: ``NEXT_STEP`` (Gymnasium's default: the next ``step`` returns the
    copy's reset observation with reward 0) or ``SAME_STEP`` (the reset observation at
    once, the final one in ``infos["final_obs"]``). ``reset(options={"reset_mask": m})``
    resets the copies of ``m`` only."""

    def __init__(
        self,
        num_envs: int,
        config: EnvConfig | Scene,
        max_episode_steps: Optional[int] = None,
        threads: Optional[int] = None,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        render_mode: Optional[str] = None,
        **keys: Any,
    ) -> None:
        if render_mode is not None:
            raise ValueError(f"render_mode: hopsim's environments do not render, got {render_mode!r}")
        mode = AutoresetMode(autoreset_mode)
        if mode not in (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP):
            raise ValueError(f"autoreset_mode: expected NEXT_STEP or SAME_STEP, got {mode}")
        self.config = config if isinstance(config, EnvConfig) else EnvConfig(config, **keys)
        self.num_envs, self.render_mode = num_envs, None
        self.max_episode_steps = max_episode_steps
        self.metadata = {"autoreset_mode": mode, "render_modes": [], "render_fps": 1.0 / self.config.dt}
        self.single_action_space = self.config.action_space()
        self.single_observation_space = self.config.observation_space()
        self.action_space = batch_space(self.single_action_space, num_envs)
        self.observation_space = batch_space(self.single_observation_space, num_envs)
        self._rollout = Rollout(self.config, num_envs, threads)
        self._rngs: List[np.random.Generator] = []
        self._elapsed = np.zeros(num_envs, dtype=np.int64)
        self._ended = np.zeros(num_envs, dtype=bool)

    @property
    def batch(self) -> Batch:
        """The batch the copies step on."""
        return self._rollout.batch

    def reset(
        self,
        *,
        seed: Optional[Union[int, Sequence[Optional[int]]]] = None,
        options: Optional[Dict[str, Any]] = None,
    ) -> Tuple[np.ndarray, Dict[str, Any]]:
        n = self.num_envs
        seeds = [seed + i for i in range(n)] if isinstance(seed, int) else seed
        seeds = [None] * n if seeds is None else list(seeds)
        if len(seeds) != n:
            raise ValueError(f"seed: expected {n} seeds (num_envs), got {len(seeds)}")
        mask = np.ones(n, dtype=bool)
        if options is not None and "reset_mask" in options:
            mask = np.asarray(options["reset_mask"], dtype=bool)
            if mask.shape != (n,):
                raise ValueError(f"options['reset_mask']: expected shape ({n},), got {mask.shape}")
        if not self._rngs:
            self._rngs = [seeding.np_random(None)[0] for _ in range(n)]
        for i in np.flatnonzero(mask):
            if seeds[i] is not None:
                self._rngs[i] = seeding.np_random(seeds[i])[0]
            self._reset_copy(i)
        return self._rollout.observe(), {}

    def _reset_copy(self, i: int) -> None:
        self._rollout.reset(i, self._rngs[i])
        self._elapsed[i] = 0
        self._ended[i] = False

    def step(
        self, actions: Any
    ) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, Dict[str, Any]]:
        if not self._rngs:
            raise gymnasium.error.ResetNeeded("call reset before step")
        obs, reward, terminated = self._rollout.step(np.asarray(actions, dtype=np.float64))
        self._elapsed += 1
        limit = self.max_episode_steps
        truncated = (self._elapsed >= limit) if limit is not None else np.zeros(self.num_envs, bool)
        infos: Dict[str, Any] = {}
        mode = self.metadata["autoreset_mode"]
        if mode == AutoresetMode.NEXT_STEP:
            restarted = np.flatnonzero(self._ended)
            for i in restarted:
                self._reset_copy(i)
            if len(restarted):
                obs = self._rollout.observe()
                reward[restarted] = 0.0
                terminated[restarted] = truncated[restarted] = False
            self._ended = terminated | truncated
        else:
            ended = np.flatnonzero(terminated | truncated)
            if len(ended):
                mask = np.zeros(self.num_envs, dtype=bool)
                mask[ended] = True
                infos["final_obs"], infos["_final_obs"] = obs, mask
                for i in ended:
                    self._reset_copy(i)
                obs = self._rollout.observe()
        return obs, reward, terminated, truncated, infos
