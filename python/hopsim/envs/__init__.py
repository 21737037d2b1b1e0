"""Gymnasium environments of hopsim (gymnasium is an optional dependency).

* :class:`HopsimEnv`: any scene with actuators as a ``gymnasium.Env`` (actions = the
  actuators' controls, brakes and switchable shapes; observation, reward and termination
  from a :class:`Task`: :class:`StateTask` by default, presets or functions of the step).
* :class:`HopsimVectorEnv`: ``num_envs`` copies on a :class:`hopsim.Batch`, copy ``i``
  equal to a :class:`HopsimEnv` with the same seed and actions.
* Registered ids (by ``import hopsim`` when gymnasium is installed):
  ``hopsim/Robbit-v0``, ``hopsim/CaneBot-v0`` and ``hopsim/Hopper-v0`` (Gymnasium's
  hopper.xml with Hopper-v5's definitions), each with its vector entry point, so that
  ``gymnasium.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")`` returns
  a :class:`HopsimVectorEnv`.

See docs/python.md, "Gymnasium environments".
"""

from __future__ import annotations

import gymnasium

from ._env import EnvConfig, HopsimEnv, HopsimVectorEnv, Rollout, actuator_ranges
from ._robots import canebot_config, hopper_config, repository_scene, robbit_config
from ._tasks import HopperV5, StateTask, StepView, Task, forward_speed

__all__ = [
    "EnvConfig",
    "HopperV5",
    "HopsimEnv",
    "HopsimVectorEnv",
    "Rollout",
    "StateTask",
    "StepView",
    "Task",
    "actuator_ranges",
    "canebot_config",
    "forward_speed",
    "hopper_config",
    "register",
    "repository_scene",
    "robbit_config",
]

#: The registered environments: id, maker's name in ``hopsim.envs._robots``, episode steps.
ENVIRONMENTS = (
    ("hopsim/Robbit-v0", "robbit", 2000),
    ("hopsim/CaneBot-v0", "canebot", 2500),
    ("hopsim/Hopper-v0", "hopper", 1000),
)


def register() -> None:
    """Registers the environments with Gymnasium (again: nothing happens)."""
    for env_id, maker, steps in ENVIRONMENTS:
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(
            id=env_id,
            entry_point=f"hopsim.envs._robots:make_{maker}",
            vector_entry_point=f"hopsim.envs._robots:make_{maker}_vector",
            max_episode_steps=steps,
        )


register()
