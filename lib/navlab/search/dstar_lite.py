"""D* Lite: incremental re-planning on an 8-connected cost grid while the agent moves and costs change.

Koenig and Likhachev, "D* Lite", AAAI 2002 — the optimised version (its Fig. 4), with the key modifier
k_m; also "Fast Replanning for Navigation in Unknown Terrain", IEEE T-RO 2005.

The search runs backwards from the goal. Every cell s holds g(s) and the one-step look-ahead
rhs(s) = min over neighbours s' of c(s, s') + g(s') (rhs(goal) = 0); cells with g != rhs sit in a
priority queue under the key [min(g, rhs) + h(s_start, s) + k_m; min(g, rhs)]. When costs change, only
the affected cells' rhs values are repaired and the queue re-processes what they invalidate. When the
agent moves from s_last to s_start, the queue is not re-sorted: k_m grows by h(s_last, s_start), which
keeps every stored key a lower bound (the triangle inequality of the octile heuristic).

Cost model: that of ``grid_astar`` — a step costs its length times the mean of the two cells' costs per
metre, ``inf`` blocks a cell — so a D* Lite path and a from-scratch A* path have equal costs. The
heuristic is the octile distance times the cheapest cost the grid has held since the last restart
(deflated by 1e-7, see DEFLATE); a change to a cheaper cost than that would make it overestimate, so
such a change restarts the search.

Bugs of public ports this avoids: oscillating between two cells (the path follows argmin c + g, and g
strictly decreases along it — a repeated cell raises instead of looping); k_m / operation-order errors
(k_m is brought up to date before any key is computed after a move); false "no path" (the loop runs
until the start is locally consistent and its key is below the queue's top, never just until the
queue looks empty).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from navlab.search import heap
from navlab.search.grid_astar import (
    SQRT2,
    GridPath,
    check_cell,
    check_cost_grid,
    check_resolution,
    octile_scale,
)

# The heuristic is deflated by this fraction. With equal costs k1 = g + h is the same for every cell of
# an optimal path, so the termination test "top key < key(s_start)" would be decided by the k2 tie-break
# inside k1 ties that an ulp of rounding breaks either way; then cells of the start's path can stay
# inconsistent and the path loops. Deflated, each such cell's k1 lies below the start's by at least
# DEFLATE x h(s_start, s), far more than the rounding of the key sums, and h stays admissible.
DEFLATE = 1e-7
# scalars of the compiled state: k_m, heuristic scale, half a straight step, half a diagonal step (metres)
_KM, _HSCALE, _HALF, _HALF_DIAG = range(4)


# The queue is ``heap``'s indexed heap (one entry per cell; key (k1, k2), ties by cell index), travelling as
# one tuple ``queue = (heap, pos, size, key)``: pos[s] < 0 when s is not queued.

@njit(cache=True)
def _queue_set(queue, s, k1, k2):
    """Insert s, or move it to its new key when it is already queued (U.Insert / U.Update)."""
    key = queue[3]
    key[s, 0], key[s, 1] = k1, k2
    heap.insert_or_update(queue, s)


# ---- D* Lite procedures (names as in the paper's Fig. 4) ------------------------------------------------

@njit(cache=True, inline="always")
def _h(a, b, width, h_scale):
    dr, dc = abs(a // width - b // width), abs(a % width - b % width)
    return (max(dr, dc) + (SQRT2 - 1.0) * min(dr, dc)) * h_scale


@njit(cache=True, inline="always")
def _edge(cost, sc, a, b, width):
    """c(a, b) for neighbouring cells: step length times the mean cost (inf if either is blocked)."""
    half = sc[_HALF] if (a - b == width or b - a == width or a - b == 1 or b - a == 1) else sc[_HALF_DIAG]
    return half * (cost[a] + cost[b])


@njit(cache=True)
def _neighbours(width):
    return np.array([-width, width, -1, 1, -width - 1, -width + 1, width - 1, width + 1])


@njit(cache=True)
def _best_successor(cost, g, sc, s, width):
    """min over the 8 neighbours s' of c(s, s') + g(s'), and the argmin. Equal sums go to the smaller
    g(s'): the move that leaves the least cost to go, so the agent takes a free diagonal rather than two
    straight steps (the tie of gonum's dynamic D* Lite test that a first-found rule gets wrong)."""
    best, arg = np.inf, -1
    for step in _neighbours(width):
        t = s + step
        value = _edge(cost, sc, s, t, width) + g[t]
        if value < best or (value == best and value < np.inf and g[t] < g[arg]):
            best, arg = value, t
    return best, arg


@njit(cache=True)
def _update_vertex(g, rhs, queue, sc, start, width, u):
    if g[u] != rhs[u]:
        m = min(g[u], rhs[u])
        _queue_set(queue, u, m + _h(start, u, width, sc[_HSCALE]) + sc[_KM], m)
    elif queue[1][u] >= 0:  # queued (pos[u] >= 0)
        heap.remove(queue, u)


@njit(cache=True)
def _compute_shortest_path(cost, g, rhs, queue, sc, start, goal, width):
    """ComputeShortestPath() of the optimised D* Lite; returns the number of cells expanded."""
    top, _, size, key = queue
    expansions = 0
    steps = _neighbours(width)
    while size[0] > 0:
        u = top[0]
        m_start = min(g[start], rhs[start])
        k_start1 = m_start + sc[_KM]
        top_below = key[u, 0] < k_start1 or (key[u, 0] == k_start1 and key[u, 1] < m_start)
        if not (top_below or rhs[start] > g[start]):
            break
        m = min(g[u], rhs[u])
        k_new1 = m + _h(start, u, width, sc[_HSCALE]) + sc[_KM]
        if key[u, 0] < k_new1 or (key[u, 0] == k_new1 and key[u, 1] < m):
            _queue_set(queue, u, k_new1, m)
            continue
        expansions += 1
        if g[u] > rhs[u]:  # over-consistent: settle u and relax its predecessors
            g[u] = rhs[u]
            heap.remove(queue, u)
            for step in steps:
                s = u + step
                if s != goal and cost[s] != np.inf:
                    through_u = _edge(cost, sc, s, u, width) + g[u]
                    rhs[s] = min(rhs[s], through_u)
                    _update_vertex(g, rhs, queue, sc, start, width, s)
        else:  # under-consistent: raise u to inf and repair the predecessors whose rhs came through it
            g_old = g[u]
            g[u] = np.inf
            for step in steps:
                s = u + step
                if s != goal and cost[s] != np.inf:
                    if rhs[s] == _edge(cost, sc, s, u, width) + g_old:
                        rhs[s] = _best_successor(cost, g, sc, s, width)[0]
                    _update_vertex(g, rhs, queue, sc, start, width, s)
            if u != goal and rhs[u] == g_old:
                rhs[u] = _best_successor(cost, g, sc, u, width)[0] if cost[u] != np.inf else np.inf
            _update_vertex(g, rhs, queue, sc, start, width, u)
    return expansions


@njit(cache=True)
def _change_costs(cost, g, rhs, queue, sc, start, goal, width, cells, new_costs):
    """Apply cell cost changes one directed edge at a time (the paper's edge-change loop in Main)."""
    steps = _neighbours(width)
    for k in range(cells.size):
        x, new = cells[k], new_costs[k]
        old = cost[x]
        if new == old:
            continue
        cost[x] = new
        for step in steps:
            n = x + step
            c_n = cost[n]
            if c_n == np.inf:  # both edges between x and a blocked n stay inf
                continue
            half = sc[_HALF] if (step == width or step == -width or step == 1 or step == -1) else sc[_HALF_DIAG]
            c_old, c_new = half * (old + c_n), half * (new + c_n)
            for u, v in ((n, x), (x, n)):  # the two directed edges
                if u == goal:
                    continue
                if c_old > c_new:
                    rhs[u] = min(rhs[u], c_new + g[v])
                elif rhs[u] == c_old + g[v]:
                    rhs[u] = _best_successor(cost, g, sc, u, width)[0] if cost[u] != np.inf else np.inf
                _update_vertex(g, rhs, queue, sc, start, width, u)


@njit(cache=True)
def _extract_path(cost, g, sc, start, goal, width):
    """Follow argmin c(s, s') + g(s') from the start; g falls strictly, so a repeated cell is a bug."""
    path = [start]
    total = 0.0
    s = start
    limit = cost.size
    while s != goal:
        value, t = _best_successor(cost, g, sc, s, width)
        if t < 0 or value == np.inf:
            return np.empty(0, np.int64), np.inf
        if len(path) > limit:
            raise RuntimeError("D* Lite path extraction revisited a cell: g is not consistent along the path")
        total += _edge(cost, sc, s, t, width)
        path.append(t)
        s = t
    return np.array(path, dtype=np.int64), total


class DStarLite:
    """D* Lite on a cost grid (per-metre costs, ``inf`` = blocked) from a moving agent to a fixed goal.

    ``plan()`` repairs the search and returns the optimal path from the agent's current cell;
    ``move_to(cell)`` moves the agent; ``update_costs(cells, costs)`` changes cell costs;
    ``expansions`` counts every cell expanded since construction (restarts included).
    """

    def __init__(self, cost: np.ndarray, start, goal, *, resolution: float = 1.0):
        cost = check_cost_grid(cost)
        self.resolution = check_resolution(resolution)
        self.shape = cost.shape
        start, goal = check_cell("start", start, cost), check_cell("goal", goal, cost)
        self._width = cost.shape[1] + 2
        padded = np.full((cost.shape[0] + 2, self._width), np.inf)
        padded[1:-1, 1:-1] = cost
        self._cost = padded.ravel()
        self._start = self._last = self._flat(start)
        self._goal = self._flat(goal)
        self.expansions = 0
        self._restart()

    def _flat(self, cell) -> int:
        return (int(cell[0]) + 1) * self._width + int(cell[1]) + 1

    def _restart(self) -> None:
        """Initialize() of the paper, with the heuristic scaled to the cheapest current cost."""
        n = self._cost.size
        interior = self._cost.reshape(-1, self._width)[1:-1, 1:-1]
        self._sc = np.array([0.0, octile_scale(interior, self.resolution) * (1.0 - DEFLATE),
                             0.5 * self.resolution, 0.5 * SQRT2 * self.resolution])
        self._g, self._rhs = np.full(n, np.inf), np.full(n, np.inf)
        # the queue (heap, pos, size, key) of heap.new_indexed; built once per restart, updated in place
        self._queue = heap.new_indexed(n, 2)
        self._last = self._start
        self._rhs[self._goal] = 0.0
        self._update_vertex(self._goal)

    def _state(self):
        return self._cost, self._g, self._rhs, self._queue, self._sc

    def _update_vertex(self, u: int) -> None:
        _update_vertex(self._g, self._rhs, self._queue, self._sc, self._start, self._width, u)

    def _sync_km(self) -> None:
        """k_m += h(s_last, s_start) before any key is computed for the agent's new cell."""
        if self._last != self._start:
            self._sc[_KM] += float(_h(self._last, self._start, self._width, self._sc[_HSCALE]))
            self._last = self._start

    def move_to(self, cell) -> None:
        """The agent is now at ``cell`` (row, col): any traversable cell, usually the next one of the path."""
        r, c = check_cell("cell", cell, self._cost.reshape(-1, self._width)[1:-1, 1:-1])
        self._start = self._flat((r, c))

    def update_costs(self, cells, costs) -> None:
        """Set the per-metre cost of ``cells`` ((M, 2) int rows/cols) to ``costs`` ((M,), ``inf`` = blocked)."""
        cells = np.asarray(cells)
        costs = np.asarray(costs, dtype=np.float64)
        if cells.ndim != 2 or cells.shape[1] != 2 or not np.issubdtype(cells.dtype, np.integer):
            raise ValueError(f"cells must be an (M, 2) integer array of (row, col), got {cells.dtype} {cells.shape}")
        if costs.shape != (len(cells),):
            raise ValueError(f"costs must have shape ({len(cells)},) to match cells, got {costs.shape}")
        if np.isnan(costs).any() or (costs <= 0).any():
            raise ValueError("costs must be positive (inf = blocked); got NaN or <= 0 values")
        rows, cols = self.shape
        outside = (cells[:, 0] < 0) | (cells[:, 0] >= rows) | (cells[:, 1] < 0) | (cells[:, 1] >= cols)
        if outside.any():
            raise ValueError(f"cell {tuple(cells[outside][0])} is outside the {self.shape} grid")
        flat = (cells[:, 0].astype(np.int64) + 1) * self._width + cells[:, 1] + 1
        finite = costs[np.isfinite(costs)]
        if finite.size and finite.min() * self.resolution < self._sc[_HSCALE]:
            self._cost[flat] = costs  # cheaper than the heuristic assumed: it could overestimate, so restart
            self._restart()
            return
        self._sync_km()
        _change_costs(*self._state(), self._start, self._goal, self._width, flat, costs)

    def plan(self) -> GridPath:
        """The optimal path from the agent's cell to the goal under the current costs (None / inf if none)."""
        self._sync_km()
        found = _compute_shortest_path(*self._state(), self._start, self._goal, self._width)
        self.expansions += int(found)
        flat, total = _extract_path(self._cost, self._g, self._sc, self._start, self._goal, self._width)
        if flat.size == 0:
            return GridPath(None, math.inf, int(found))
        cells = np.stack([flat // self._width, flat % self._width], axis=1) - 1
        return GridPath(cells, float(total), int(found))
