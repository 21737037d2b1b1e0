"""Trajectories of runs and recordings read back, as numpy arrays (and pandas frames)."""

from __future__ import annotations

import json
from typing import Any, Dict, List, Optional

import numpy as np


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("to_pandas() needs pandas: pip install pandas") from e
    return pandas


class Trajectory:
    """The frames of a run and its summary.

    ``frames`` has one row per recorded frame and the columns of ``hopsim run --csv``
    (``columns``: ``t_s``, ``step``, ``<q>_<unit>``, ``<q>_dot_<unit>``, ``com_x_m``,
    ``com_y_m``, the energies in J, ``actuator_torque_Nm``). ``t``, ``q``, ``u``, ``com``,
    ``energy`` and ``actuator_torque`` are views of it; ``steps`` holds the step indices
    as integers. ``events`` lists every event of the run (``t_s``, ``step``, ``kind`` and
    the kind's fields); ``summary`` is the document ``hopsim run --summary`` writes
    (NaN figures are None, as in JSON).
    """

    columns: List[str]
    coordinates: List[str]
    frames: np.ndarray
    steps: np.ndarray
    events: List[Dict[str, Any]]
    summary: Dict[str, Any]

    @classmethod
    def _from_run(cls, raw: Dict[str, Any]) -> "Trajectory":
        self = cls.__new__(cls)
        self.columns = list(raw["columns"])
        self.coordinates = list(raw["coordinates"])
        self.frames = raw["frames"]
        self.steps = raw["steps"].astype(np.int64)
        self.events = json.loads(raw["events"])
        summary = raw["summary"]
        self.summary = None if summary is None else json.loads(summary)
        return self

    def __len__(self) -> int:
        return self.frames.shape[0]

    def __repr__(self) -> str:
        return (
            f"Trajectory({len(self)} frames, t = {self.t[0]:g} … {self.t[-1]:g} s, "
            f"{len(self.events)} events)"
            if len(self)
            else "Trajectory(0 frames)"
        )

    @property
    def t(self) -> np.ndarray:
        """Time of each frame, s."""
        return self.frames[:, 0]

    @property
    def q(self) -> np.ndarray:
        """Generalised coordinates, shape ``(frames, coordinates)``."""
        n = len(self.coordinates)
        return self.frames[:, 2 : 2 + n]

    @property
    def u(self) -> np.ndarray:
        """Generalised velocities, shape ``(frames, coordinates)``."""
        n = len(self.coordinates)
        return self.frames[:, 2 + n : 2 + 2 * n]

    @property
    def com(self) -> np.ndarray:
        """Whole-robot centre of mass, m, shape ``(frames, 2)``."""
        n = len(self.coordinates)
        return self.frames[:, 2 + 2 * n : 4 + 2 * n]

    @property
    def energy(self) -> Dict[str, np.ndarray]:
        """Energies, J: kinetic, potential, spring, actuator_work, dissipated,
        balance_error (docs/physics.md §6)."""
        return {
            name[: -len("_J")]: self.frames[:, i]
            for i, name in enumerate(self.columns)
            if name.endswith("_J")
        }

    @property
    def actuator(self) -> np.ndarray:
        """The motor's command in the frame's step: a torque in N m, or a force in N on a
        prismatic joint (the last column's name says which)."""
        return self.frames[:, -1]

    @property
    def actuator_torque(self) -> np.ndarray:
        """``actuator`` (the name of older versions; N on a prismatic joint)."""
        return self.actuator

    def to_pandas(self) -> "pandas.DataFrame":  # noqa: F821
        """The frames as a ``pandas.DataFrame`` with the CSV recorder's columns (``step``
        as integers)."""
        frame = _pandas().DataFrame(self.frames, columns=self.columns)
        frame["step"] = self.steps
        return frame


class Recording:
    """A hopsim MCAP recording read back (see :func:`hopsim.read_mcap`).

    ``steps``, ``t``, ``q``, ``u``: the recorded states, one row per frame.
    ``impulses``: ``step``, ``t``, ``channel``, ``normal``, ``tangent`` of every contact
    percussion (N s) and brake impulse (channel ``brake``, N m s). ``events``: every event.
    ``metadata``: scene name, ``dt``, coordinates, bodies, contacts, springs, hopsim
    version. ``scene_text``: the scene file stored in the recording. ``stopped``: None for
    a complete run; for a recording kept after the run stopped early
    (``FILE.partial.mcap``), ``{"reason": str, "step": int, "t": float}``: why, and the
    last step completed with its end time (s).
    """

    metadata: Dict[str, Any]
    scene_text: Optional[str]
    steps: np.ndarray
    t: np.ndarray
    q: np.ndarray
    u: np.ndarray
    impulses: Dict[str, Any]
    events: List[Dict[str, Any]]
    stopped: Optional[Dict[str, Any]]

    @classmethod
    def _from_raw(cls, raw: Dict[str, Any]) -> "Recording":
        self = cls.__new__(cls)
        self.metadata = raw["metadata"]
        self.scene_text = raw["scene_text"]
        self.steps = raw["steps"].astype(np.int64)
        self.t = raw["t"]
        self.q = raw["q"]
        self.u = raw["u"]
        self.impulses = dict(raw["impulses"])
        self.impulses["step"] = self.impulses["step"].astype(np.int64)
        self.events = json.loads(raw["events"])
        self.stopped = raw["stopped"]
        return self

    def __len__(self) -> int:
        return self.t.shape[0]

    def __repr__(self) -> str:
        stopped = "" if self.stopped is None else f", stopped after step {self.stopped['step']}"
        return (
            f"Recording({self.metadata['scene']!r}, {len(self)} states, "
            f"{len(self.events)} events{stopped})"
        )

    def to_pandas(self) -> "pandas.DataFrame":  # noqa: F821
        """The states as a ``pandas.DataFrame``: ``t_s``, ``step``, then each coordinate
        and its rate (``<name>_dot``)."""
        pd = _pandas()
        names = self.metadata["coordinates"]
        columns: Dict[str, Any] = {"t_s": self.t, "step": self.steps}
        columns.update({name: self.q[:, i] for i, name in enumerate(names)})
        columns.update({f"{name}_dot": self.u[:, i] for i, name in enumerate(names)})
        return pd.DataFrame(columns)
