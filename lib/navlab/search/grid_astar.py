"""A* on an 8-connected (or 4-connected) cost grid, compiled with numba.

Hart, Nilsson and Raphael, "A Formal Basis for the Heuristic Determination of Minimum Cost Paths",
IEEE Trans. SSC, 1968.

Each cell carries a cost per metre (>= some positive minimum; ``inf`` blocks it). Moving between two
neighbouring cells costs the step length times the mean of their costs, so a path's cost is the
integral of cost along it and does not depend on which way it is walked. The heuristic is the octile
distance times the cheapest cell cost, which never overestimates: the search returns an optimal path.

The open list is ordered by (f, g, flat index), a total order, so the compiled search pops exactly the
nodes, in exactly the order, of the plain-Python reference (``grid_reference.astar_reference``): the
returned path, its cost bits and the expansion count are the same, which keeps every dataset built on
this planner (the SuReNav demonstrations) byte-identical. The SuReNav experiments call this search
thousands of times; ``benchmarks/grid_astar.py`` times it against scikit-image's ``MCP_Geometric``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from navlab.search import heap

SQRT2 = math.sqrt(2.0)


@dataclass(frozen=True)
class GridPath:
    cells: np.ndarray | None  # (K, 2) int64 (row, col) from start to goal; None when unreachable
    cost: float  # inf when unreachable
    expansions: int


def check_cost_grid(cost) -> np.ndarray:
    """``cost`` as a float64 raster, or one ValueError naming what is wrong with it and the fix."""
    cost = np.asarray(cost, dtype=np.float64)
    if cost.ndim != 2 or cost.size == 0:
        raise ValueError(f"cost must be a non-empty 2-D array, got shape {cost.shape}")
    if np.isnan(cost).any() or np.isneginf(cost).any():  # NaN would read as blocked, -inf as a free lunch
        raise ValueError("cost holds NaN or -inf cells; mark blocked cells with +inf")
    finite = cost[np.isfinite(cost)]
    if finite.size == 0 or finite.min() <= 0:
        raise ValueError("cost must have positive finite values where traversable (got none or <= 0)")
    return cost


def check_resolution(resolution: float) -> float:
    """``resolution`` (metres per cell) as a float, or a ValueError when it is not a positive number."""
    resolution = float(resolution)
    if not (math.isfinite(resolution) and resolution > 0):
        raise ValueError(f"resolution = {resolution}: give the cell size in metres, a finite number > 0")
    return resolution


def check_cell(name: str, cell, cost: np.ndarray) -> tuple[int, int]:
    """``cell`` as (row, col) inside ``cost`` and on a traversable cell, or a ValueError saying which."""
    r, c = (int(v) for v in cell)
    if not (0 <= r < cost.shape[0] and 0 <= c < cost.shape[1]):
        raise ValueError(f"{name} {(r, c)} is outside the {cost.shape} grid")
    if not np.isfinite(cost[r, c]):
        raise ValueError(f"{name} {(r, c)} lies in a blocked cell (infinite cost); choose a traversable cell")
    return r, c


def octile_scale(cost: np.ndarray, resolution: float) -> float:
    """Heuristic cost per cell of octile distance: the cheapest traversable cost per metre x resolution."""
    return float(cost[np.isfinite(cost)].min()) * resolution


@njit(cache=True)
def _search(flat_cost, width, start_i, goal_i, half_straight, half_diagonal, diagonal, h_scale, h_diagonal):
    """A* over the row-major padded raster (a border of inf cells replaces the bounds checks).

    The open list is an indexed binary heap of cells keyed by (f, g), ties by flat index (``heap.before``):
    a cell whose g drops moves up in place instead of being pushed again, so the heap never holds stale
    entries (3x faster than lazy deletion on the benchmark maps). The cells come out in the same order as
    from the reference's lazy heapq. The heap's layout and order are ``heap``'s indexed heap, but its pop
    and decrease-key are written out here: calling ``heap.pop_top`` / ``heap.insert_or_decrease`` per cell
    made this search 20-30% slower on the ``benchmarks/grid_astar.py`` maps (the calls, inlined or not, put
    reference-count updates of the heap arrays into the innermost loop: 16 NRT_incref calls in its IR, not
    2). Column 1 of ``key`` is g itself.
    """
    n = flat_cost.size
    steps = np.array([-width, width, -1, 1, -width - 1, -width + 1, width - 1, width + 1])
    halves = np.array([half_straight] * 4 + [half_diagonal] * 4)
    n_moves = 8 if diagonal else 4
    key = np.full((n, 2), np.inf)  # (f, g) per cell; allocated here, not by heap.new_indexed: 5% faster
    parent = np.full(n, -1, np.int64)
    pos = np.full(n, -1, np.int32)  # heap slot of an open cell; -1 never opened, -2 closed
    queue = np.empty(n, np.int32)
    gr, gc = goal_i // width, goal_i % width
    dr, dc = abs(start_i // width - gr), abs(start_i % width - gc)
    key[start_i, 0], key[start_i, 1] = (max(dr, dc) + h_diagonal * min(dr, dc)) * h_scale, 0.0
    queue[0], pos[start_i], size = start_i, 0, 1
    expansions = 0
    while size > 0:
        i = queue[0]
        pos[i] = -2
        size -= 1
        if size > 0:  # move the last cell to the root and sift it down
            item, p = queue[size], 0
            while 2 * p + 1 < size:
                child = 2 * p + 1
                if child + 1 < size and heap.before(key, queue[child + 1], queue[child]):
                    child += 1
                if not heap.before(key, queue[child], item):
                    break
                queue[p] = queue[child]
                pos[queue[p]] = p
                p = child
            queue[p], pos[item] = item, p
        expansions += 1
        if i == goal_i:
            break
        g_here, c_here = key[i, 1], flat_cost[i]
        for m in range(n_moves):
            j = i + steps[m]
            c_next = flat_cost[j]
            if c_next == np.inf or pos[j] == -2:
                continue
            g_next = g_here + halves[m] * (c_here + c_next)
            if g_next < key[j, 1]:
                parent[j] = i
                dr, dc = abs(j // width - gr), abs(j % width - gc)
                key[j, 0], key[j, 1] = g_next + (max(dr, dc) + h_diagonal * min(dr, dc)) * h_scale, g_next
                k = pos[j]
                if k < 0:  # newly opened: start at the end
                    k = size
                    size += 1
                while k > 0 and heap.before(key, j, queue[(k - 1) >> 1]):  # sift up
                    queue[k] = queue[(k - 1) >> 1]
                    pos[queue[k]] = k
                    k = (k - 1) >> 1
                queue[k], pos[j] = j, k
    return key[:, 1], parent, pos[goal_i] == -2, expansions


def padded_problem(cost: np.ndarray, start, goal, resolution: float):
    """Checked inputs on the grid framed by a border of blocked cells (it replaces the bounds checks; row-major
    flat indices keep their order, so ties break as on the unframed grid), with start's and goal's flat index:
    ``(cost, resolution, padded, width, start_i, goal_i)``."""
    cost = check_cost_grid(cost)
    resolution = check_resolution(resolution)
    start, goal = check_cell("start", start, cost), check_cell("goal", goal, cost)
    width = cost.shape[1] + 2
    padded = np.full((cost.shape[0] + 2, width), np.inf)
    padded[1:-1, 1:-1] = cost
    return cost, resolution, padded, width, (start[0] + 1) * width + start[1] + 1, (goal[0] + 1) * width + goal[1] + 1


def plan(cost: np.ndarray, start, goal, *, resolution: float = 1.0, diagonal: bool = True) -> GridPath:
    """Optimal path from ``start`` to ``goal`` (row, col) over ``cost`` (per metre, ``inf`` = blocked)."""
    cost, resolution, padded, width, start_i, goal_i = padded_problem(cost, start, goal, resolution)
    # octile distance (Manhattan when 4-connected) times the cheapest cost per metre: admissible
    g, parent, reached, expansions = _search(
        padded.ravel(), width, start_i, goal_i, resolution * 0.5, resolution * 0.5 * SQRT2, bool(diagonal),
        octile_scale(cost, resolution), SQRT2 - 1.0 if diagonal else 1.0)
    if not reached:
        return GridPath(None, math.inf, int(expansions))
    chain = [goal_i]
    while parent[chain[-1]] != -1:
        chain.append(int(parent[chain[-1]]))
    flat = np.array(chain[::-1], dtype=np.int64)
    cells = np.stack([flat // width, flat % width], axis=1) - 1
    return GridPath(cells, float(g[goal_i]), int(expansions))
