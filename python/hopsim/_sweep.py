"""Parameter sweeps: ``hopsim sweep`` from Python, on local cores or a Dask cluster."""

from __future__ import annotations

import csv
import inspect
import io
import math
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _hopsim
from ._hopsim import Scene

#: Default number of chunks per worker thread of a Dask cluster: enough that runs of
#: unequal cost even out across the workers, few enough that each task is many runs.
CHUNKS_PER_THREAD = 16

#: Columns of the sweep table that hold text; every other column holds numbers.
TEXT_COLUMNS = ("label", "status", "error")


class SweepTable:
    """The rows of a sweep, one per run: the grid's points in row-major order (the last
    axis varies fastest), then the baselines; the columns of ``hopsim sweep``'s
    ``sweep.csv``: ``label`` (``grid`` or the baseline's name), one column per grid
    key, ``status`` (``ok`` or ``error``), ``error``, then the run-summary figures
    (``mean_speed_mps``, ``hops``, ``impulse_per_distance_Nms_per_m``, …,
    ``wall_time_s``).

    ``table[name]`` is a column: a float numpy array (NaN where empty) or, for
    ``label``, ``status`` and ``error``, a list of strings. ``csv`` is the exact text of
    ``sweep.csv``; ``to_pandas()`` gives a ``pandas.DataFrame``.
    """

    def __init__(self, header: Sequence[str], rows: Sequence[Sequence[str]], text: str):
        self._csv = text
        self.header: List[str] = list(header)
        self._rows: List[List[str]] = [list(r) for r in rows]
        self._columns: Dict[str, Any] = {}
        for i, name in enumerate(self.header):
            cells = [r[i] for r in self._rows]
            if name in TEXT_COLUMNS:
                self._columns[name] = cells
            else:
                self._columns[name] = np.array(
                    [float(c) if c != "" else math.nan for c in cells], dtype=np.float64
                )

    @classmethod
    def _from_csv_parts(cls, parts: Iterable[str]) -> "SweepTable":
        header: Optional[List[str]] = None
        rows: List[List[str]] = []
        texts: List[str] = []
        for text in parts:
            reader = csv.reader(io.StringIO(text))
            part_header = next(reader)
            if header is None:
                header = part_header
                texts.append(text)
            elif part_header != header:
                raise RuntimeError("sweep chunks returned different columns")
            else:
                texts.append(text.split("\n", 1)[1])
            rows.extend(reader)
        if header is None:
            raise ValueError("a sweep without runs")
        return cls(header, rows, "".join(texts))

    def __len__(self) -> int:
        return len(self._rows)

    def __getitem__(self, name: str) -> Any:
        return self._columns[name]

    def __contains__(self, name: object) -> bool:
        return name in self._columns

    def __repr__(self) -> str:
        failed = sum(s != "ok" for s in self._columns["status"])
        return f"SweepTable({len(self)} runs, {failed} failed, {len(self.header)} columns)"

    @property
    def columns(self) -> List[str]:
        """The column names, in order."""
        return list(self.header)

    @property
    def rows(self) -> List[List[str]]:
        """The rows as the CSV's text cells."""
        return [list(r) for r in self._rows]

    @property
    def csv(self) -> str:
        """The table as ``hopsim sweep`` writes ``sweep.csv``."""
        return self._csv

    def to_pandas(self) -> "pandas.DataFrame":  # noqa: F821
        """The table as a ``pandas.DataFrame`` (numbers as float64, NaN where empty)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("to_pandas() needs pandas: pip install pandas") from e
        return pd.DataFrame({name: self._columns[name] for name in self.header})


GridItems = List[Tuple[str, List[float]]]
Baselines = Optional[Dict[str, Dict[str, Any]]]


def _grid_items(grid: Mapping[str, Iterable[float]]) -> GridItems:
    if not isinstance(grid, Mapping) or not grid:
        raise ValueError("grid must be a non-empty {key: values} mapping")
    items = []
    for key, values in grid.items():
        if not isinstance(key, str):
            raise TypeError(f"grid keys must be scene keys as strings, got {key!r}")
        arr = np.asarray(list(values) if not isinstance(values, np.ndarray) else values)
        if arr.ndim != 1 or arr.dtype.kind not in "fiu":
            raise TypeError(f"grid axis {key}: values must be a 1-D sequence of numbers")
        items.append((key, [float(v) for v in arr]))
    return items


def _baselines(baselines: Optional[Mapping[str, Mapping[str, Any]]]) -> Baselines:
    if baselines is None:
        return None
    return {str(name): dict(overrides) for name, overrides in baselines.items()}


def _run_chunk(
    scene: Scene,
    grid: GridItems,
    baselines: Baselines,
    start: int,
    stop: int,
) -> str:
    """A chunk of a sweep on a Dask worker: its runs on the worker's threads."""
    threads = None
    try:
        from distributed import get_worker

        threads = get_worker().state.nthreads
    except (ImportError, ValueError, AttributeError):
        pass
    return _hopsim.sweep_csv(scene, grid, baselines, start, stop, threads)


def sweep(
    scene: Scene,
    grid: Mapping[str, Iterable[float]],
    baselines: Optional[Mapping[str, Mapping[str, Any]]] = None,
    client: Any = None,
    chunk_size: Optional[int] = None,
    controller: Optional[Callable[..., Any]] = None,
) -> SweepTable:
    """Runs ``scene`` at every point of ``grid`` (``{key: values}``, the last key varying
    fastest) and each baseline (``{name: {key: value}}``), as ``hopsim sweep`` does, and
    returns the table of ``sweep.csv``. A run that fails is a row with its error.

    Without ``client`` the runs share all local cores (Rust threads, the GIL released);
    Ctrl-C stops them within about 50 ms, and the ``KeyboardInterrupt`` carries the
    ``table`` so far (the runs it stopped are rows with their error).
    With a ``dask.distributed.Client`` they are cut into chunks of ``chunk_size`` runs
    (default: about sixteen chunks per worker thread) run on the cluster's workers, each on
    its worker's threads; the rows and their order are the same either way (but for
    ``wall_time_s``). Raises ``SceneError`` if the grid's first point or a baseline is
    not a valid scene, ``ValueError`` for an axis given twice or a baseline named like
    another.

    With ``controller``, a factory of controllers written in Python, every run is driven
    by ``controller(**params)``: called before each step with the simulation, the
    controller returns an :class:`Actuation` for the step (or None: the scene's controller
    acts, under the controls it set). The grid keys (and baseline keys) that name a
    parameter of the factory are its ``params``; the others are scene keys. Such runs
    hold the GIL: without ``client`` they run one after the other in this process; with
    one, their chunks run on the cluster's workers (the factory must pickle). The table
    has the columns of a sweep over scene keys, its figures from the same run summary.
    """
    if controller is not None:
        return _controller_sweep(scene, grid, baselines, client, chunk_size, controller)
    items = _grid_items(grid)
    lines = _baselines(baselines)
    runs = _hopsim.sweep_runs(scene, items, lines)
    if client is None:
        try:
            return SweepTable._from_csv_parts([_hopsim.sweep_csv(scene, items, lines)])
        except KeyboardInterrupt as error:
            partial = getattr(error, "_partial_csv", None)
            if partial is not None:
                error.table = SweepTable._from_csv_parts([partial])
            raise
    chunk_size = _chunk_size(client, runs, chunk_size)
    [scene_future] = client.scatter([scene], broadcast=True)
    futures = [
        client.submit(
            _run_chunk,
            scene_future,
            items,
            lines,
            start,
            min(start + chunk_size, runs),
            pure=False,
        )
        for start in range(0, runs, chunk_size)
    ]
    return SweepTable._from_csv_parts(client.gather(futures))


def _chunk_size(client: Any, runs: int, chunk_size: Optional[int]) -> int:
    """Runs per chunk on a Dask cluster: ``chunk_size``, or about sixteen chunks per worker
    thread."""
    if chunk_size is None:
        threads = sum(client.nthreads().values()) or 1
        chunk_size = max(1, math.ceil(runs / (CHUNKS_PER_THREAD * threads)))
    if chunk_size < 1:
        raise ValueError(f"chunk_size must be at least 1, got {chunk_size}")
    return chunk_size


#: One run of a sweep over a Python controller: its label, its grid values (NaN for a
#: baseline), its scene overrides and the controller factory's parameters.
ControlledRun = Tuple[str, List[float], Dict[str, Any], Dict[str, Any]]


def _controlled_runs(
    scene: Scene,
    grid: Mapping[str, Iterable[float]],
    baselines: Optional[Mapping[str, Mapping[str, Any]]],
    controller: Callable[..., Any],
) -> Tuple[List[str], List[ControlledRun]]:
    """The grid's keys and the runs (grid points in row-major order, then the baselines),
    each point's keys split between the factory's parameters and the scene; the grid's
    first point and every baseline checked as scenes."""
    items = _grid_items(grid)
    params = inspect.signature(controller).parameters
    keys = [key for key, _ in items]

    def split(point: Mapping[str, Any]) -> Tuple[Dict[str, Any], Dict[str, Any]]:
        own = {k: v for k, v in point.items() if k in params}
        return {k: v for k, v in point.items() if k not in params}, own

    runs: List[ControlledRun] = []
    for values in np.ndindex(*(len(v) for _, v in items)):
        point = [items[a][1][i] for a, i in enumerate(values)]
        runs.append(("grid", point, *split(dict(zip(keys, point)))))
    checked = runs[:1]
    for name, overrides in (_baselines(baselines) or {}).items():
        if name == "grid":
            raise ValueError("a baseline cannot be named 'grid': that label marks the grid's rows")
        checked.append((name, [math.nan] * len(keys), *split(overrides)))
    for _, _, overrides, _ in checked:
        scene.with_overrides(overrides)
    return keys, runs + checked[1:]


def _controlled_run(scene: Scene, run: ControlledRun, controller: Callable[..., Any]) -> List[str]:
    """One run of a sweep over a Python controller: its row of the table (CSV cells)."""
    from . import HopsimError, Simulation

    label, point, overrides, params = run
    values = [_number(v) for v in point]
    try:
        run_scene = scene.with_overrides(overrides)
        drive = controller(**params)
        sim = Simulation(run_scene)
        recorder = sim.record()
        for _ in range(round(run_scene.duration / run_scene.dt)):
            actuation = drive(sim)
            if actuation is None:
                sim.step()
            else:
                sim.step(actuation=actuation)
        recorder.close()
    except HopsimError as error:
        return [label, *values, "error", str(error)] + [""] * len(_hopsim.sweep_figure_names())
    return [label, *values, "ok", ""] + [_number(v) for _, v in recorder.figures]


def _number(x: float) -> str:
    """A number as ``sweep.csv`` writes it (the shortest text that reads back exactly,
    never an exponent); empty when not finite."""
    x = float(x)
    if not math.isfinite(x):
        return ""
    return np.format_float_positional(x, trim="-")


def _controlled_chunk(scene: Scene, runs: List[ControlledRun], controller: Callable[..., Any]) -> List[List[str]]:
    """A chunk of a sweep over a Python controller, on a Dask worker."""
    return [_controlled_run(scene, run, controller) for run in runs]


def _controller_sweep(
    scene: Scene,
    grid: Mapping[str, Iterable[float]],
    baselines: Optional[Mapping[str, Mapping[str, Any]]],
    client: Any,
    chunk_size: Optional[int],
    controller: Callable[..., Any],
) -> SweepTable:
    """:func:`sweep` with a controller factory (see there)."""
    keys, runs = _controlled_runs(scene, grid, baselines, controller)
    if client is None:
        rows = [_controlled_run(scene, run, controller) for run in runs]
    else:
        size = _chunk_size(client, len(runs), chunk_size)
        [scene_future] = client.scatter([scene], broadcast=True)
        futures = [
            client.submit(_controlled_chunk, scene_future, runs[i : i + size], controller, pure=False)
            for i in range(0, len(runs), size)
        ]
        rows = [row for chunk in client.gather(futures) for row in chunk]
    header = ["label", *keys, "status", "error", *_hopsim.sweep_figure_names()]
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return SweepTable(header, rows, text.getvalue())
