"""hopsim: planar non-smooth multibody simulation from Python.

A Moreau midpoint time-stepper whose contact step is a frictional LCP solved by Lemke's
method, for impulse-actuated hopping robots described in TOML scene files. This package
wraps the Rust crates of hopsim (it re-implements nothing): the numbers are those of the
``hopsim`` command line, bit for bit.

* :class:`Scene`: a validated scene file (``Scene.load``, ``Scene.from_toml``); errors are
  :class:`SceneError` with ``file``, ``line``, ``column`` and ``key``.
* :class:`Model`: a model built in code with the scene format's keys (``body``, ``shape``,
  ``controller``, …), validated as a file; ``Model.scene()`` makes its :class:`Scene`, and
  ``Scene.model`` the model of a scene.
* :class:`Simulation`: ``step()``, the state as numpy arrays, ``contacts()``, per-step
  :class:`Actuation` from a controller written in Python, ``run()`` returning a
  :class:`Trajectory` with the run summary of ``hopsim run --summary``.
* :class:`Batch`: copies of a scene (or :class:`Model`) stepped together on Rust threads,
  their states, controls, contact flags and done mask in numpy arrays filled in place.
* :mod:`hopsim.lcp`: ``solve(M, q)`` by Lemke's method with its certificate.
* :mod:`hopsim.envs` (with gymnasium installed): Gymnasium environments of any scene with
  actuators, ``hopsim/Robbit-v0``, ``hopsim/CaneBot-v0`` and ``hopsim/Hopper-v0``
  (Hopper-v5's definitions), and their vector environment on :class:`Batch`.
* :func:`read_mcap`: a recording written by ``hopsim run --mcap`` as arrays.
* :func:`sweep`: a scene over a grid of parameters on all local cores, or on a Dask
  cluster in chunks, as the table of ``hopsim sweep``.
* :func:`optimize`: CMA-ES (the engine of ``hopsim optimize``) over parameters within
  bounds with any Python objective, on local threads or a Dask cluster, resumable.

Every exception hopsim raises derives from :class:`HopsimError` (an ``Exception``):
:class:`SceneError` (also a ``ValueError``), :class:`SimulationError` (also a
``RuntimeError``) and :class:`InternalError` (a bug in hopsim, caught where Python called
in). Long calls run Python's signal handlers about every 50 ms: Ctrl-C raises
``KeyboardInterrupt``.

See docs/python.md.
"""

from __future__ import annotations

# Imports the package uses itself are underscored, so that ``dir(hopsim)`` lists what it
# offers (``__all__``) and nothing else.
import json as _json
import os as _os
from typing import Any as _Any
from typing import Mapping as _Mapping
from typing import Sequence as _Sequence

import numpy as _np

from . import _hopsim, lcp
from ._hopsim import (
    Actuation,
    HopsimError,
    InternalError,
    Scene,
    SceneError,
    SimulationError,
)
from ._model import Model
from ._optimize import OptimizeResult, optimize
from ._recorder import Recorder
from ._recorder import outputs_of as _outputs_of
from ._recorder import speed_of as _speed_of
from ._sweep import SweepTable, sweep
from ._trajectory import Recording, Trajectory

__version__: str = _hopsim.__version__

__all__ = [
    "Actuation",
    "Batch",
    "HopsimError",
    "InternalError",
    "Model",
    "OptimizeResult",
    "Recorder",
    "Recording",
    "Scene",
    "SceneError",
    "Simulation",
    "SimulationError",
    "SweepTable",
    "Trajectory",
    "lcp",
    "optimize",
    "read_mcap",
    "sweep",
]


class _Named:
    """The names of a simulated scene's parts, in index order (every method that takes an
    index takes the name too)."""

    scene: Scene

    @property
    def body_names(self) -> list[str]:
        """The bodies' names."""
        return self.scene._part_names("body")

    @property
    def shape_names(self) -> list[str]:
        """The contact shapes' names."""
        return self.scene._part_names("shape")

    @property
    def joint_names(self) -> list[str]:
        """The revolute and prismatic joints' names (each named after its body)."""
        return self.scene._part_names("joint")

    @property
    def actuator_names(self) -> list[str]:
        """The actuators' names (the order of the controls)."""
        return self.scene._part_names("actuator")


class Simulation(_Named, _hopsim.Simulation):
    """A scene being simulated, one step at a time or a span at a time.

    ``Simulation(scene)`` starts at the scene's initial state. ``t``, ``q``, ``u``,
    ``angular_velocities``, ``body_positions`` and ``body_angles`` are new numpy arrays
    at each access (copies: changing them changes nothing; use ``set_state``).
    ``step(n=1, actuation=None)`` takes steps with the scene's controller, or with the
    commands of an :class:`Actuation` in its place.
    """

    def run(
        self,
        duration: float | None = None,
        record_rate: float | None = None,
        frames: bool = True,
    ) -> Trajectory:
        """Continues for ``duration`` seconds (default: the scene's ``simulation.duration``;
        at most ``simulation.max_steps`` steps, else ``ValueError``) with the scene's
        controller, the GIL released, recording a frame at ``record_rate`` Hz (default: the
        scene's ``simulation.record_rate``) and at every step with an event, as
        ``hopsim run`` records. With ``frames=False`` it keeps no frames and no events, only
        the summary, so memory stays bounded however long the run. For a new simulation and
        the scene's duration the trajectory and its ``summary`` are those of
        ``hopsim run SCENE --summary FILE`` (but for the wall time).

        A run that stops early (``SimulationError``, ``InternalError``, or Ctrl-C's
        ``KeyboardInterrupt``, raised within about 50 ms) keeps what it recorded: the
        exception's ``trajectory`` holds the frames up to the stop (its ``summary`` is
        None), and the simulation stays at the last completed step."""
        try:
            raw = self._run(duration, record_rate, frames)
        except BaseException as error:
            partial = getattr(error, "_partial_run", None)
            if partial is not None:
                error.trajectory = Trajectory._from_run(partial)
            raise
        return Trajectory._from_run(raw)

    def events(self) -> list[dict[str, _Any]]:
        """The events of the last step (take-off, touchdown, brake, ...), as recorded."""
        return _json.loads(self._events())

    def record(
        self,
        *outputs: str | _os.PathLike[str],
        record_rate: float | None = None,
        speed: float | str = 1.0,
    ) -> Recorder:
        """Records the run from the current state on to ``outputs``, with the recorders
        and channels of ``hopsim run``: paths ending in ``.mcap``, ``.rrd`` or ``.csv``
        (events in ``FILE.events.csv``), or ``"live"`` (a Rerun viewer, paced by ``speed``
        simulated seconds per second, or ``"max"``); with none, to the run summary only.
        Frames at ``record_rate`` Hz (default:
        the scene's ``simulation.record_rate``) and at every step with an event, whoever
        steps: ``step`` with the scene's controller or an :class:`Actuation`, and ``run``.
        Returns a :class:`Recorder`; ``close()`` (or the end of a ``with`` block) completes
        the files and returns the run summary. ``set_state`` is refused while recording."""
        self._record_open(_outputs_of(outputs), record_rate, _speed_of(speed))
        return Recorder(list(outputs), self._record_close, self._record_abort)

    @property
    def state(self) -> tuple[float, _np.ndarray, _np.ndarray]:
        """``(t, q, u)`` (copies)."""
        return self.t, self.q, self.u


def read_mcap(path: str | _os.PathLike[str]) -> Recording:
    """Reads a recording written by ``hopsim run --mcap`` (numbers bit for bit): the
    recorded states, contact and brake impulses, events, metadata and the scene file. A
    recording kept after its run stopped early (``FILE.partial.mcap``) says why in
    ``stopped``. Raises ``ValueError`` for a file that is not a hopsim recording."""
    return Recording._from_raw(_hopsim.read_mcap(path))



# The future import binds the name ``annotations`` in this module; it is no part of the API.
del annotations


class Batch(_Named, _hopsim.Batch):
    """``n`` copies of a scene (or of a :class:`Model`'s scene) stepped together on
    ``threads`` Rust threads (default: the machine's cores), the GIL released; copy ``i``
    equals a :class:`Simulation` of the scene with the same start and controls bit for bit,
    whatever the thread count.

    ``t`` (n,), ``q`` and ``u`` (n, nq), ``in_contact`` and ``done`` (n,) are read-only
    numpy arrays owned by the batch and filled in place by every ``step``, ``reset`` and
    ``set_state`` (keep them: no array is allocated per step). ``controls`` (n, nu) is
    written by the caller (in place or by assignment) and read before each step; after
    it, it holds the controls that acted. ``step(n=1, controls=None)`` takes ``n`` steps
    of every copy that is not done; a copy whose step fails is marked ``done`` with its
    message in ``error(i)`` while the others go on. ``reset(i=None)`` restarts a copy (or
    all) at the scene's initial state; ``set_state(i, q, u, t=None)`` restarts one at a
    state, checked as :meth:`Simulation.set_state` checks (``restore=True``: its values
    only, for a state a run reached).

    ``brakes=[(body, other), …]`` and ``switches=[shape, …]`` (indices) give the batch
    brakes and switchable shapes driven per copy by the bool arrays ``brakes`` (n, nb),
    whether each brake locks ``θ̇_body = θ̇_other`` in the copy's steps, and ``switches``
    (n, ns), whether each shape is on; a step that brakes or switches takes them in place
    of the scene's controller, as ``Simulation.step(actuation=…)`` does.

    ``overrides=[{key: value, …}, …]`` (one mapping per copy) gives each copy its own
    parameters (masses, friction, restitution, controller keys: domain randomisation): copy
    ``i`` is then a simulation of ``scene.with_overrides(overrides[i])``, and every copy must
    keep the scene's coordinates, actuators and shapes.
    """

    def __new__(
        cls,
        scene: Scene | Model,
        n: int,
        threads: int | None = None,
        brakes: list[tuple[int, int]] | None = None,
        switches: list[int] | None = None,
        overrides: _Sequence[_Mapping[str, _Any]] | None = None,
    ) -> "Batch":
        if isinstance(scene, Model):
            scene = scene.scene()
        copies = None if overrides is None else [scene.with_overrides(o) for o in overrides]
        return super().__new__(cls, scene, n, threads, brakes, switches, copies)

    def record(
        self,
        i: int,
        *outputs: str | _os.PathLike[str],
        record_rate: float | None = None,
        speed: float | str = 1.0,
    ) -> Recorder:
        """Records copy ``i`` from its current state on, as :meth:`Simulation.record`
        records a simulation (the same recorders, channels and summary; the copy's energy
        account is switched on while it is recorded). Several copies can be recorded at
        once. ``reset`` and ``set_state`` of a copy being recorded are refused
        (``RuntimeError``) until its recording ends; a copy whose step fails stops its
        recording, and ``close()`` then raises naming the partial files kept."""
        self._record_open(i, _outputs_of(outputs), record_rate, _speed_of(speed))
        return Recorder(
            list(outputs),
            lambda: self._record_close(i),
            lambda reason: self._record_abort(i, reason),
        )


# Gymnasium's environments (hopsim.envs) are registered when gymnasium is installed.
try:
    import gymnasium as _gymnasium  # noqa: F401
except ImportError:
    pass
else:
    from . import envs

    __all__.append("envs")
