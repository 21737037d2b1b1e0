"""CMA-ES from Python: the search of ``hopsim optimize`` (the Rust engine, ask and tell)
with any Python objective, evaluated on local threads or on a Dask cluster."""

from __future__ import annotations

import json
import math
import os
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple

from . import _hopsim

#: The initial step size, as a fraction of each parameter's span (``hopsim optimize --sigma``).
DEFAULT_SIGMA = 0.3

Outcome = Tuple[Optional[float], Optional[str]]


class OptimizeResult:
    """The record of a search: ``best`` (``{key: value}`` of the best accepted point),
    ``value`` (its objective), ``evaluations`` (one dict per point, in the order CMA-ES
    sampled them: ``generation``, ``index``, ``values``, ``objective`` — ``None`` when
    rejected — and ``error``), ``generations``, ``rejected``, ``stop`` (why it ended, or
    ``None`` when interrupted), ``csv`` (the text of ``evaluations.csv``) and ``text``
    (the summary ``hopsim optimize`` prints)."""

    def __init__(self, report: Dict[str, Any], csv: str, text: str):
        self.report = report
        keys = [p["key"] for p in report["problem"]["parameters"]]
        self.evaluations: List[Dict[str, Any]] = [
            {
                "generation": g,
                "index": i,
                "values": dict(zip(keys, e["values"])),
                "objective": e["objective"],
                "error": e["error"],
            }
            for g, generation in enumerate(report["generations"])
            for i, e in enumerate(generation)
        ]
        best = report["best"]
        self.best: Optional[Dict[str, float]] = (
            dict(zip(keys, best["values"])) if best is not None else None
        )
        self.value: Optional[float] = best["objective"] if best is not None else None
        self.generations: int = len(report["generations"])
        self.rejected: int = report["rejected"]
        stop = report["stop"]
        if isinstance(stop, dict):  # {"Converged": [criteria]}
            stop = "; ".join(f"{k}: {', '.join(v)}" for k, v in stop.items())
        self.stop: Optional[str] = stop
        self.csv = csv
        self.text = text

    def __repr__(self) -> str:
        return (
            f"OptimizeResult(value={self.value!r}, best={self.best!r}, "
            f"{len(self.evaluations)} evaluations, {self.rejected} rejected)"
        )


def _parameters(params: Mapping[str, Sequence[Any]]) -> List[Tuple[str, float, float, bool]]:
    if not isinstance(params, Mapping) or not params:
        raise ValueError("params must be a non-empty {key: (lower, upper)} mapping")
    out = []
    for key, spec in params.items():
        spec = tuple(spec)
        if len(spec) == 2:
            integer = False
        elif len(spec) == 3 and spec[2] == "int":
            integer = True
        else:
            raise ValueError(f"{key}: expected (lower, upper) or (lower, upper, 'int'), got {spec!r}")
        out.append((str(key), float(spec[0]), float(spec[1]), integer))
    return out


def _evaluate(objective: Callable[[Dict[str, float]], Any], values: Dict[str, float]) -> Outcome:
    """One point: its objective, or ``(None, reason)`` if the objective raised or did not
    give a finite number."""
    try:
        value = objective(values)
    except Exception as error:  # noqa: BLE001 - any failure rejects the point
        return None, f"{type(error).__name__}: {error}"
    if value is None:
        return None, "the objective gave None"
    value = float(value)
    if not math.isfinite(value):
        return None, f"the objective is {value}"
    return value, None


def optimize(
    objective: Callable[[Dict[str, float]], Any],
    params: Mapping[str, Sequence[Any]],
    *,
    maximize: bool = False,
    start: Optional[Mapping[str, float]] = None,
    sigma: float = DEFAULT_SIGMA,
    population: Optional[int] = None,
    generations: int = 30,
    seed: int = 1,
    client: Any = None,
    threads: Optional[int] = None,
    checkpoint: Optional[str] = None,
    out: Optional[str] = None,
    name: Optional[str] = None,
) -> OptimizeResult:
    """Minimises (or, with ``maximize=True``, maximises) ``objective`` over ``params``
    (``{key: (lower, upper)}``, or ``(lower, upper, "int")`` for whole numbers) with the
    CMA-ES of ``hopsim optimize`` (docs/optimize.md).

    ``objective(values)`` takes ``{key: value}`` and returns a number: any function of
    one or several runs (e.g. ``Scene.with_overrides(values)`` run by
    :class:`Simulation`). A point whose objective raises, or returns ``None`` or a
    non-finite number, is rejected: penalised for CMA-ES and recorded with the reason.

    Each generation's points are evaluated on ``threads`` local threads (default: all
    cores; hopsim's runs release the GIL), or, with a ``dask.distributed.Client``, as
    one task per point on the cluster; the result is the same either way for a
    deterministic objective. ``seed`` makes the search. With ``checkpoint`` (a file
    path) the search is saved after every generation and, if the file exists, resumed
    from it (the same arguments required): a search stopped at any time loses at most the
    generation under way. With ``out`` (a folder), ``evaluations.csv`` and
    ``convergence.png``/``.svg`` are written there at the end.
    """
    parameters = _parameters(params)
    keys = [p[0] for p in parameters]
    start_values = None
    if start is not None:
        missing = [k for k in keys if k not in start]
        if missing or len(start) != len(keys):
            raise ValueError(f"start must give a value for each of {keys}")
        start_values = [float(start[k]) for k in keys]
    label = name or getattr(objective, "__qualname__", type(objective).__name__)
    search = _hopsim.Search(
        parameters, maximize, start_values, float(sigma), population, int(seed),
        int(generations), f"{label} (Python)",
    )
    if checkpoint is not None and os.path.exists(checkpoint):
        with open(checkpoint, encoding="utf-8") as f:
            search = search.resumed(f.read())
    executor = None
    if client is None:
        executor = ThreadPoolExecutor(max_workers=threads or os.cpu_count() or 1)
    interrupted = True
    try:
        while True:
            points = search.ask()
            if points is None:
                break
            values = [dict(zip(keys, p)) for p in points]
            if client is None:
                outcomes = list(executor.map(lambda v: _evaluate(objective, v), values))
            else:
                futures = client.map(_evaluate, [objective] * len(values), values, pure=False)
                outcomes = client.gather(futures)
            search.tell([tuple(o) for o in outcomes])
            if checkpoint is not None:
                search.write_checkpoint(checkpoint)
        interrupted = False
    finally:
        if executor is not None:
            executor.shutdown(wait=False, cancel_futures=True)
    if out is not None:
        search.write_files(out)
    report = json.loads(search.report_json(interrupted))
    return OptimizeResult(report, search.table_csv(), search.text())
