"""Discrete Fréchet distance (Eiter & Mannila, "Computing discrete Fréchet distance", 1994; SuReNav Sec. VI-A).

The coupling distance between two polylines: walk both from start to end, each step advancing one or
both, and take the longest leash needed; the dynamic programme is

    ca[i, j] = max(d(p_i, q_j), min(ca[i-1, j], ca[i-1, j-1], ca[i, j-1])).

The common Python libraries are slow (similaritymeasures loops in Python, ~140 ms for 500 points;
frechetdist recurses and overflows near 600 points), so the DP is compiled with numba; a plain
numpy reference sits beside it for the tests. SuReNav reports it normalised by the start-goal
Euclidean distance, so that long and short episodes weigh alike.
"""

from __future__ import annotations

import numba
import numpy as np


def _check(name: str, curve) -> np.ndarray:
    curve = np.ascontiguousarray(curve, dtype=np.float64)
    if curve.ndim != 2 or curve.shape[1] != 2 or len(curve) == 0:
        raise ValueError(f"{name} must be a non-empty (K, 2) array of points, got shape {curve.shape}")
    if not np.isfinite(curve).all():
        raise ValueError(f"{name} holds NaN or infinite coordinates; drop them before measuring")
    return curve


@numba.njit(cache=True, nogil=True)
def _frechet_dp(p: np.ndarray, q: np.ndarray) -> float:
    n, m = p.shape[0], q.shape[0]
    row = np.empty(m)  # one DP row at a time: O(m) memory
    for i in range(n):
        diagonal = 0.0  # ca[i-1, j-1]
        for j in range(m):
            d = np.sqrt((p[i, 0] - q[j, 0]) ** 2 + (p[i, 1] - q[j, 1]) ** 2)
            if i == 0 and j == 0:
                best = 0.0
            elif i == 0:
                best = row[j - 1]
            elif j == 0:
                best = row[0]
            else:
                best = min(row[j], diagonal, row[j - 1])
            diagonal = row[j]
            row[j] = max(d, best)
    return row[m - 1]


def discrete_frechet(p, q) -> float:
    """Discrete Fréchet distance between two (K, 2) point sequences (same units as the points)."""
    return float(_frechet_dp(_check("p", p), _check("q", q)))


def discrete_frechet_reference(p, q) -> float:
    """The same DP as plain Python loops over a numpy distance matrix: the oracle the tests compare against."""
    p, q = _check("p", p), _check("q", q)
    d = np.linalg.norm(p[:, None, :] - q[None, :, :], axis=2)
    ca = np.empty_like(d)
    ca[0] = np.maximum.accumulate(d[0])
    for i in range(1, len(p)):
        ca[i, 0] = max(ca[i - 1, 0], d[i, 0])
        for j in range(1, len(q)):
            ca[i, j] = max(d[i, j], min(ca[i - 1, j], ca[i - 1, j - 1], ca[i, j - 1]))
    return float(ca[-1, -1])


def normalised_frechet(path, demonstration, start, goal) -> float:
    """Fréchet distance divided by the start-goal Euclidean distance (SuReNav Table I)."""
    span = float(np.linalg.norm(np.asarray(goal, float) - np.asarray(start, float)))
    if span <= 0:
        raise ValueError("start and goal coincide: the normalised Fréchet distance is undefined")
    return discrete_frechet(path, demonstration) / span
