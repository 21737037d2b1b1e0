"""Linear complementarity problems solved by Lemke's method (docs/lcp.md).

Finds ``z`` with ``w = M z + q``, ``z ≥ 0``, ``w ≥ 0``, ``zᵀw = 0``; every answer carries
an a-posteriori certificate, and the status is ``"solved"`` only when it holds.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Dict, Tuple

import numpy as np

from . import _hopsim

__all__ = ["LcpSolution", "read_dat", "solve"]


@dataclass(frozen=True)
class LcpSolution:
    """The answer of :func:`solve`.

    ``status``: ``"solved"``, ``"ray_termination"``, ``"pivot_limit"`` or
    ``"numerical_breakdown"``. ``z``, ``w``: the solution (the last iterate on a
    failure). ``pivots``: Lemke pivots of all runs of this solve. ``method``:
    ``"trivial"`` (``q ≥ 0``), ``"lemke"``, ``"lemke_alternate_covering"`` or
    ``"enumeration"``. ``certificate``: ``complementarity``, ``most_negative``,
    ``residual`` (in the units of ``w``), the scaled ``tolerance`` they are held to, and
    ``holds``.
    """

    status: str
    z: np.ndarray
    w: np.ndarray
    pivots: int
    method: str
    certificate: Dict[str, Any]

    @property
    def solved(self) -> bool:
        """Whether the status is ``"solved"`` (its certificate holds)."""
        return self.status == "solved"


def _real_array(value: Any, name: str, ndim: int) -> np.ndarray:
    """``value`` as a C-ordered float64 array of ``ndim`` dimensions, or a clear error."""
    try:
        array = np.asarray(value)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{name} is not a rectangular array of numbers: {e}") from None
    if array.dtype.kind not in "fiu":
        raise TypeError(
            f"{name} must hold real numbers (a float or integer dtype), got dtype {array.dtype}"
        )
    if array.ndim != ndim:
        shape = "(n, n)" if ndim == 2 else "(n,)"
        raise ValueError(f"{name} must have shape {shape}, got shape {array.shape}")
    return np.ascontiguousarray(array, dtype=np.float64)


def solve(M: Any, q: Any) -> LcpSolution:
    """Solves the LCP ``w = M z + q, z ≥ 0, w ≥ 0, zᵀw = 0`` by Lemke's method with the
    lexicographic ratio test, retrying with another covering vector and, for small
    ``n``, by enumeration (docs/lcp.md); the GIL is released while it runs. Ctrl-C during
    the solve of a large problem (``n > 64``, solved on a thread of its own) raises
    ``KeyboardInterrupt`` within about 50 ms; the abandoned solve finishes in the
    background and its answer is dropped.

    ``M``: array-like ``(n, n)``; ``q``: array-like ``(n,)``; real numbers (integers are
    converted to float64). Raises ``TypeError`` for another dtype (bool, complex, text,
    objects) and ``ValueError`` for a wrong shape, a ``q`` of another length, or a NaN or
    infinite entry.
    """
    m_array = _real_array(M, "M", 2)
    q_array = _real_array(q, "q", 1)
    rows, cols = m_array.shape
    if rows != cols:
        raise ValueError(f"M must be square, got shape {m_array.shape}")
    if q_array.shape[0] != rows:
        raise ValueError(f"q has {q_array.shape[0]} entries but M is {rows}×{rows}")
    raw = _hopsim.lcp_solve(m_array, q_array)
    return LcpSolution(
        status=raw["status"],
        z=raw["z"],
        w=raw["w"],
        pivots=raw["pivots"],
        method=raw["method"],
        certificate=raw["certificate"],
    )


def read_dat(path: "str | os.PathLike[str]") -> Tuple[np.ndarray, np.ndarray]:
    """``(M, q)`` of a Siconos ``.dat`` LCP file. Raises ``ValueError`` for a file that
    cannot be read or is malformed."""
    m, q, _comment = _hopsim.lcp_read_dat(path)
    return m, q
