"""Plain-Python A* on the Dubins lattice (heapq + dict), the reference the compiled search is checked and
timed against; and the plain-Python integrator and first step the compiled ``dubins_lattice.integrate`` and
``first_step`` replaced (bit for bit the same floats, tests/test_hj_planner.py; timed in benchmarks/hj_planner.py).

Same lattice, same duplicate detection (one node per snapped cell, replaced and reopened when its g
improves), same goal test and step cost as ``lattice_search``; the heuristic and the pruner are any
batched callables (e.g. ``reach.lookup``'s numpy look-ups), called once per expansion with all
successors, as a straightforward Python planner would. Readable top to bottom; no numba.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable

import numpy as np

from navlab.search.dubins_lattice import LatticeSpec, primitive_table, successor_samples


def astar_reference(spec: LatticeSpec, bounds, start, goal_xy, tolerance: float, max_speed: float,
                    heuristic: Callable[[np.ndarray], np.ndarray],
                    prune: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
                    max_expansions: int = 10**6) -> tuple[float, int]:
    """(cost, expansions) of A* from ``start`` to the goal disc; cost is inf when none is found.

    ``heuristic``: (N, 4) states -> (N,) seconds; ``prune``: the parent (4,) and its (N, S, 4) segments ->
    (N,) True = drop (an OBS pruner's ``swept`` check needs the parent).
    The step cost is ``dt`` (time).
    """
    if spec.snap_states:
        raise ValueError("astar_reference follows the continuous-state lattice; use snap_states=False")
    start = np.asarray(start, np.float64)
    if start.shape != (4,) or not np.isfinite(start).all():  # as lattice_search.search
        raise ValueError(f"start must be a finite (x, y, v, θ), got {start!r}")
    table = primitive_table(spec)
    (_, x1), (_, y1) = bounds
    bin_w = 2 * math.pi / spec.heading_bins

    def cell(s):
        return (math.floor(s[0] / spec.cell_m), math.floor(s[1] / spec.cell_m), round(s[2] / spec.dv),
                round(s[3] / bin_w) % spec.heading_bins)

    c0 = cell(start)
    g = {c0: 0.0}
    state = {c0: start}
    h0 = float(heuristic(start[None])[0])
    heap = [(h0, -0.0, c0)]
    expansions = 0
    while heap:
        _, neg_g, c = heapq.heappop(heap)
        if -neg_g != g[c]:
            continue  # stale
        s = state[c]
        if math.hypot(s[0] - goal_xy[0], s[1] - goal_xy[1]) <= tolerance and abs(s[2]) <= max_speed + 1e-9:
            return g[c], expansions
        if expansions >= max_expansions:
            break
        expansions += 1
        samples = successor_samples(spec, table, s)
        samples[:, -1, 3] = (samples[:, -1, 3] + math.pi) % (2 * math.pi) - math.pi
        ends = samples[:, -1]
        inside = (ends[:, 0] >= 0) & (ends[:, 0] < x1) & (ends[:, 1] >= 0) & (ends[:, 1] < y1)
        keep = inside & ~prune(s, samples) if prune is not None else inside
        ng = g[c] + spec.dt
        candidates = [(i, cell(ends[i])) for i in np.flatnonzero(keep)]
        candidates = [(i, nc) for i, nc in candidates if ng < g.get(nc, math.inf)]
        if not candidates:
            continue
        hs = heuristic(ends[[i for i, _ in candidates]])
        for (i, nc), h in zip(candidates, hs, strict=True):
            if ng < g.get(nc, math.inf):  # two primitives of one expansion may land in the same cell
                g[nc], state[nc] = ng, ends[i].copy()
                heapq.heappush(heap, (ng + float(h), -ng, nc))
    return math.inf, expansions


def integrate_reference(state, a: float, omega: float, duration: float, n: int,
                        v_range: tuple[float, float]) -> np.ndarray:
    """``dubins_lattice.integrate`` as the plain-Python loop it was: (n, 4) states after each sub-step."""
    x, y, v, th = (float(s) for s in state)
    h = duration / n
    out = np.empty((n, 4))
    for i in range(n):
        v1 = min(max(v + a * h, v_range[0]), v_range[1])
        th1 = th + omega * h
        vm, tm = 0.5 * (v + v1), th + 0.5 * omega * h
        x += h * vm * math.cos(tm)
        y += h * vm * math.sin(tm)
        v, th = v1, th1
        out[i] = (x, y, v, th)
    return out


def first_step_rows_reference(spec: LatticeSpec, v: float, controls: np.ndarray) -> np.ndarray:
    """``dubins_lattice.first_step``'s rows (P, S, 4) for ``controls`` from speed ``v``, one Python call per
    control (before the end speeds are put on their levels)."""
    s, m = spec.samples_per_step, spec.micro_steps
    return np.stack([integrate_reference(np.array([0.0, 0.0, v, 0.0]), a, w, spec.dt, s * m, spec.v_range)[m - 1::m]
                     for a, w in controls])
