"""A* on an 8-connected (or 4-connected) cost grid.

Hart, Nilsson and Raphael, "A Formal Basis for the Heuristic Determination of Minimum Cost Paths",
IEEE Trans. SSC, 1968.

Each cell carries a cost per metre (>= some positive minimum; ``inf`` blocks it). Moving between two
neighbouring cells costs the step length times the mean of their costs, so a path's cost is the
integral of cost along it and does not depend on which way it is walked. The heuristic is the octile
distance times the cheapest cell cost, which never overestimates: the search returns an optimal path.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numpy as np

_STRAIGHT = ((-1, 0), (1, 0), (0, -1), (0, 1))
_DIAGONAL = ((-1, -1), (-1, 1), (1, -1), (1, 1))


@dataclass(frozen=True)
class GridPath:
    cells: np.ndarray | None  # (K, 2) int64 (row, col) from start to goal; None when unreachable
    cost: float  # inf when unreachable
    expansions: int


def _check_cell(name: str, cell, cost: np.ndarray) -> tuple[int, int]:
    r, c = (int(v) for v in cell)
    if not (0 <= r < cost.shape[0] and 0 <= c < cost.shape[1]):
        raise ValueError(f"{name} {(r, c)} is outside the {cost.shape} grid")
    if not np.isfinite(cost[r, c]):
        raise ValueError(f"{name} {(r, c)} lies in a blocked cell (infinite cost); choose a traversable cell")
    return r, c


def plan(cost: np.ndarray, start, goal, *, resolution: float = 1.0, diagonal: bool = True) -> GridPath:
    """Optimal path from ``start`` to ``goal`` (row, col) over ``cost`` (per metre, ``inf`` = blocked)."""
    cost = np.asarray(cost, dtype=np.float64)
    if cost.ndim != 2:
        raise ValueError(f"cost must be a 2-D array, got shape {cost.shape}")
    if np.isnan(cost).any() or np.isneginf(cost).any():  # NaN would read as blocked, -inf as a free lunch
        raise ValueError("cost holds NaN or -inf cells; mark blocked cells with +inf")
    finite = cost[np.isfinite(cost)]
    if finite.size == 0 or finite.min() <= 0:
        raise ValueError("cost must have positive finite values where traversable (got none or <= 0)")
    if not (isinstance(resolution, int | float) and math.isfinite(resolution) and resolution > 0):
        raise ValueError(f"resolution = {resolution!r}: give the cell size in metres, a finite number > 0")
    start, goal = _check_cell("start", start, cost), _check_cell("goal", goal, cost)
    rows, cols = cost.shape
    # A border of blocked cells replaces the bounds checks; row-major flat indices keep their order, so
    # heap ties break as on the unpadded grid. Plain lists, not numpy, in the loop: it is scalar work.
    width = cols + 2
    padded = np.full((rows + 2, width), np.inf)
    padded[1:-1, 1:-1] = cost
    flat_cost = padded.ravel().tolist()
    moves = [(dr * width + dc, resolution * 0.5) for dr, dc in _STRAIGHT]
    if diagonal:
        moves += [(dr * width + dc, resolution * 0.5 * math.sqrt(2.0)) for dr, dc in _DIAGONAL]
    # octile distance (Manhattan when 4-connected) times the cheapest cost per metre: admissible
    h_scale = float(finite.min()) * resolution
    h_diagonal = math.sqrt(2.0) - 1.0 if diagonal else 1.0
    gr, gc = goal[0] + 1, goal[1] + 1
    start_i, goal_i = (start[0] + 1) * width + start[1] + 1, gr * width + gc
    inf = math.inf
    g = [inf] * len(flat_cost)
    parent = [-1] * len(flat_cost)
    closed = bytearray(len(flat_cost))
    g[start_i] = 0.0
    dr, dc = abs(start[0] + 1 - gr), abs(start[1] + 1 - gc)
    frontier = [((max(dr, dc) + h_diagonal * min(dr, dc)) * h_scale, 0.0, start_i)]
    expansions = 0
    while frontier:
        _, g_here, i = heapq.heappop(frontier)
        if closed[i]:
            continue
        closed[i] = 1
        expansions += 1
        if i == goal_i:
            break
        c_here = flat_cost[i]
        for step, half_step in moves:
            j = i + step
            c_next = flat_cost[j]
            if c_next == inf or closed[j]:
                continue
            g_next = g_here + half_step * (c_here + c_next)
            if g_next < g[j]:
                g[j] = g_next
                parent[j] = i
                r, c = divmod(j, width)
                dr, dc = abs(r - gr), abs(c - gc)
                heapq.heappush(frontier, (g_next + (max(dr, dc) + h_diagonal * min(dr, dc)) * h_scale, g_next, j))
    if not closed[goal_i]:
        return GridPath(None, inf, expansions)
    chain = [goal_i]
    while parent[chain[-1]] != -1:
        chain.append(parent[chain[-1]])
    cells = np.array([divmod(i, width) for i in reversed(chain)], dtype=np.int64) - 1
    return GridPath(cells, g[goal_i], expansions)
