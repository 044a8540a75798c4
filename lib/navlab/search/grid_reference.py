"""Reference solvers on a cost grid, against which the compiled grid searches are checked.

``dijkstra_cost`` is scikit-image's MCP_Geometric (Cython Dijkstra) under the same cost model as
``grid_astar`` (step length times the mean cost of the two cells): the independent solver that A*
results are checked against in tests, notebooks and benchmarks. ``astar_reference`` is the same A* as
``grid_astar.plan`` written as plain Python with ``heapq`` (Hart, Nilsson and Raphael 1968): the tests
require the compiled search to return its path, cost and expansion count exactly.
"""

from __future__ import annotations

import heapq
import math

import numpy as np
from skimage.graph import MCP_Geometric

from navlab.search.grid_astar import (
    SQRT2,
    GridPath,
    octile_scale,
    padded_problem,
)

_STRAIGHT = ((-1, 0), (1, 0), (0, -1), (0, 1))
_DIAGONAL = ((-1, -1), (-1, 1), (1, -1), (1, 1))


def dijkstra_cost(cost: np.ndarray, start, goal, *, resolution: float = 1.0) -> float:
    """Optimal cost from ``start`` to ``goal`` over an 8-connected grid (``inf`` when unreachable)."""
    blocked_as_negative = np.where(np.isfinite(cost), cost, -1.0)  # MCP: negative = impassable
    cumulative, _ = MCP_Geometric(blocked_as_negative, fully_connected=True).find_costs([tuple(start)], [tuple(goal)])
    return float(cumulative[tuple(goal)]) * resolution


def astar_reference(cost: np.ndarray, start, goal, *, resolution: float = 1.0, diagonal: bool = True) -> GridPath:
    """``grid_astar.plan`` in plain Python: heap entries (f, g, flat index), lazy deletion."""
    cost, resolution, padded, width, start_i, goal_i = padded_problem(cost, start, goal, resolution)
    flat_cost = padded.ravel().tolist()
    moves = [(dr * width + dc, resolution * 0.5) for dr, dc in _STRAIGHT]
    if diagonal:
        moves += [(dr * width + dc, resolution * 0.5 * SQRT2) for dr, dc in _DIAGONAL]
    h_scale = octile_scale(cost, resolution)
    h_diagonal = SQRT2 - 1.0 if diagonal else 1.0
    gr, gc = divmod(goal_i, width)
    inf = math.inf
    g = [inf] * len(flat_cost)
    parent = [-1] * len(flat_cost)
    closed = bytearray(len(flat_cost))
    g[start_i] = 0.0
    sr, sc = divmod(start_i, width)
    dr, dc = abs(sr - gr), abs(sc - gc)
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
