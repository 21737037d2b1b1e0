"""Recordings of runs stepped from Python: :class:`Recorder`, made by
``Simulation.record`` and ``Batch.record``."""

from __future__ import annotations

import json
import os
from types import TracebackType
from typing import Any, Callable, Optional, Union

Output = Union[str, "os.PathLike[str]"]


def outputs_of(outputs: tuple[Output, ...]) -> list[str]:
    """The outputs as strings (paths, or ``"live"``)."""
    return [os.fspath(o) for o in outputs]


def speed_of(speed: Union[float, str]) -> str:
    """The live stream's pace as ``hopsim run --speed`` takes it."""
    return speed if isinstance(speed, str) else repr(float(speed))


class Recorder:
    """A recording under way of a :class:`Simulation` (``sim.record(...)``) or of one copy
    of a :class:`Batch` (``batch.record(i, ...)``): every step taken from now on, by the
    scene's controller or by an :class:`Actuation`, goes to the recorders of
    ``hopsim run`` (MCAP, Rerun ``.rrd`` or a live viewer, CSV), with the same channels;
    without outputs, to the run summary only.

    ``close()`` completes the files (each written under a hidden temporary name and renamed
    into place only then) and returns the run summary of the span recorded, the document
    of ``hopsim run --summary``. Used as a context manager it closes at the end of the
    block; a block that raises keeps what was recorded under the outputs' partial names
    (``run.partial.mcap``, with the exception as the stop's reason) and never leaves a
    file that looks complete. A recording dropped unclosed leaves no file at all.
    """

    def __init__(
        self,
        outputs: list[str],
        close: Callable[[], tuple[str, list[tuple[str, float]]]],
        abort: Callable[[str], list[str]],
    ) -> None:
        self.outputs: list[str] = outputs
        """The outputs, as given."""
        self.summary: Optional[dict[str, Any]] = None
        """The run summary, once closed."""
        self.kept: list[str] = []
        """The partial recordings kept by ``abort``."""
        self.figures: list[tuple[str, float]] = []
        """The figures ``hopsim.sweep`` reports of the run (its table's columns after
        ``error``), once closed."""
        self._close: Optional[Callable[[], tuple[str, list[tuple[str, float]]]]] = close
        self._abort = abort

    @property
    def closed(self) -> bool:
        """Whether the recording has ended (closed or aborted)."""
        return self._close is None

    def close(self) -> dict[str, Any]:
        """Completes the recording and returns the run summary of the span recorded (as
        ``hopsim run --summary`` writes it; its speed window is the last
        ``summary.speed_window`` seconds of that span). A recorded run whose step failed
        raises ``SimulationError`` naming the partial recordings it kept."""
        close = self._take()
        summary, self.figures = close()
        self.summary = json.loads(summary)
        return self.summary

    def abort(self, reason: str = "the recording was aborted") -> list[str]:
        """Ends the recording without completing it: what was recorded is kept under the
        outputs' partial names with ``reason`` in them; returns those paths."""
        self._take()
        self.kept = [os.fspath(p) for p in self._abort(reason)]
        return self.kept

    def _take(self) -> Callable[[], tuple[str, list[tuple[str, float]]]]:
        close = self._close
        if close is None:
            raise RuntimeError("the recording has already ended")
        self._close = None
        return close

    def __enter__(self) -> "Recorder":
        return self

    def __exit__(
        self,
        kind: Optional[type[BaseException]],
        error: Optional[BaseException],
        traceback: Optional[TracebackType],
    ) -> None:
        if self.closed:
            return
        if error is None:
            self.close()
        else:
            self.abort(f"{type(error).__name__}: {error}")

    def __repr__(self) -> str:
        state = "closed" if self.closed else "recording"
        return f"Recorder({self.outputs!r}, {state})"
