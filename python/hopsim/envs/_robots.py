"""The registered environments' scenes: Robbit and CaneBot from the repository's scene
files, their built-in controllers replaced by actions, and Gymnasium's own hopper.xml."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Optional

from .. import Scene
from ._env import EnvConfig, HopsimEnv, HopsimVectorEnv
from ._tasks import HopperV5, StateTask


def repository_scene(name: str) -> Path:
    """``scenes/<name>`` of the hopsim repository: found from the working directory or a
    folder above it, from the folder ``HOPSIM_REPO`` names, or above this package's source."""
    here = Path.cwd().resolve()
    folders = [here, *here.parents]
    if "HOPSIM_REPO" in os.environ:
        folders.append(Path(os.environ["HOPSIM_REPO"]))
    folders.extend(Path(__file__).resolve().parents)
    for folder in folders:
        if (folder / "scenes" / name).is_file():
            return folder / "scenes" / name
    raise FileNotFoundError(
        f"scenes/{name} is neither in {here} nor above it: work inside the hopsim repository, "
        "set HOPSIM_REPO to its folder, or pass scene=hopsim.Scene.load(...)"
    )


def _driven(scene: Scene, actuator: dict[str, Any]) -> Scene:
    """``scene`` without its controller (every key removed: passive), with ``actuator``."""
    model = scene.model
    keys = model._tables["controller"].keys
    model.controller(**{key: None for key in keys if key != "type"}, type="passive")
    return model.actuator(**actuator).scene()


def robbit_config(scene: Optional[Scene] = None, frame_skip: int = 5, **task: Any) -> EnvConfig:
    """Robbit (scenes/robbit.toml) driven by its actions: the flywheel's motor torque
    (N m, within ± the scene's controller torque) and the disc–flywheel brake (engaged
    above 0.5). Observation: ``y``, ``sin φ``, ``cos φ``, the four velocities and the
    contact flag (``x`` and the flywheel's angle ``ψ``, on which nothing depends, left
    out). Reward: forward speed (m/s). Control every ``frame_skip`` steps (1 ms)."""
    scene = scene or Scene.load(repository_scene("robbit.toml"))
    c = scene.controller
    flywheel = c["flywheel"]
    disc = scene.bodies[flywheel]["parent"]
    name = scene.bodies[flywheel]["name"]
    torque = c["torque"]
    driven = _driven(scene, {"name": "motor", "joint": name, "kind": "motor",
                             "ctrl_range": [-torque, torque]})
    q = scene.coordinates
    observed = {"exclude": [q[0], q[flywheel + 2]], "angles": [q[2]], **task}
    return EnvConfig(
        driven, StateTask(**observed), frame_skip, brakes=[(disc, flywheel)],
        reset_noise_q=[0.0, 0.0, 0.0, 0.01], reset_noise_u=0.01,
    )


def canebot_config(scene: Optional[Scene] = None, frame_skip: int = 10, **task: Any) -> EnvConfig:
    """CaneBot (scenes/canebot.toml) driven by its actions: the joint motor's torque (N m,
    within ± the pulse's torque) and the cane (extended above 0.5). Observation: the
    coordinates but ``x``, ``φ`` as its sine and cosine, the velocities and the contact
    flag. Reward: forward speed (m/s). Control every ``frame_skip`` steps (about 2 ms)."""
    scene = scene or Scene.load(repository_scene("canebot.toml"))
    c = scene.controller
    torque, cane, joint = c["torque"], c["cane_shape"], scene.bodies[c["joint_body"]]["name"]
    driven = _driven(scene, {"name": "motor", "joint": joint, "kind": "motor",
                             "ctrl_range": [-torque, torque]})
    q = scene.coordinates
    nq = len(q)
    observed = {"exclude": [q[0]], "angles": [q[2]], **task}
    return EnvConfig(
        driven, StateTask(**observed), frame_skip, switches=[cane],
        reset_noise_q=[0.01] + [0.0] * (nq - 1), reset_noise_u=0.01,
    )


def gymnasium_hopper_xml() -> Path:
    """Gymnasium's hopper.xml (gymnasium/envs/mujoco/assets), the model of Hopper-v5."""
    import gymnasium

    return Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "hopper.xml"


def hopper_config(
    xml_file: Optional[str] = None, frame_skip: int = 4, reset_noise_scale: float = 5e-3, **task: Any
) -> EnvConfig:
    """Hopper-v5 on Gymnasium's hopper.xml imported by hopsim (docs/mjcf.md): v5's
    observation, reward and termination (:class:`HopperV5`, keywords as v5's), its
    ``frame_skip`` (4: dt = 0.008 s) and reset noise (uniform ±5e-3 on qpos and qvel, by
    values only: the thigh and leg start at their stops)."""
    scene = Scene.load(xml_file or gymnasium_hopper_xml())
    return EnvConfig(
        scene, HopperV5(**task), frame_skip, reset_noise_q=reset_noise_scale,
        reset_noise_u=reset_noise_scale, restore_reset=True,
    )


def _maker(config):  # type: ignore[no-untyped-def]
    def single(render_mode: Optional[str] = None, **keys: Any) -> HopsimEnv:
        return HopsimEnv(config(**keys), render_mode=render_mode)

    def vector(
        num_envs: int = 1, max_episode_steps: Optional[int] = None, threads: Optional[int] = None,
        autoreset_mode: Any = "NextStep", render_mode: Optional[str] = None, **keys: Any,
    ) -> HopsimVectorEnv:
        return HopsimVectorEnv(num_envs, config(**keys), max_episode_steps, threads,
                               autoreset_mode, render_mode)

    return single, vector


make_robbit, make_robbit_vector = _maker(robbit_config)
make_canebot, make_canebot_vector = _maker(canebot_config)
make_hopper, make_hopper_vector = _maker(hopper_config)
