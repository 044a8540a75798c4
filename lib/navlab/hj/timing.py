"""Table VII of the HJ-search paper: the time of one heuristic or pruner call at the paper's input sizes
(35 successor states per heuristic call, 140 segment samples per pruner call), 10,000 calls each.

The inputs are real: the successors and segment samples of lattice expansions from random free states
of the room, so the look-ups touch the grid the way a search does. Each call is the batched entry point
the search and the simulator use (``Heuristic.__call__``, ``StaticPruner.__call__``); inside the search
the same compiled look-ups run without even the Python call.
"""

from __future__ import annotations

import math
import time

import numpy as np

from navlab.search.dubins_lattice import successor_samples
from navlab.search.lattice_fields import heuristic_loop, static_prune_loop


def expansion_inputs(planner, n_states: int, n_samples: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(n_states, 4) successor states and (n_samples / S, S, 4) segment samples of expansions from random
    free states at random lattice speeds."""
    rng = np.random.default_rng(seed)
    room, spec, table = planner.room, planner.spec, planner.table
    segs = []
    while sum(len(s) for s in segs) * spec.samples_per_step < max(n_samples, n_states * spec.samples_per_step):
        x, y = rng.uniform(0, room.width), rng.uniform(0, room.height)
        if room.signed_distance(np.array([x]), np.array([y]), planner.robot.radius_m)[0] <= 0.2:
            continue
        v = spec.speeds[rng.integers(0, spec.speed_levels)]
        segs.append(successor_samples(spec, table, np.array([x, y, v, rng.uniform(-math.pi, math.pi)])))
    segs = np.concatenate(segs)
    return np.ascontiguousarray(segs[:n_states, -1]), np.ascontiguousarray(segs[:n_samples // spec.samples_per_step])


def time_calls(fn, args, calls: int) -> float:
    """Seconds for ``calls`` back-to-back calls of ``fn(*args)`` (after one warm-up call)."""
    fn(*args)
    start = time.perf_counter()
    for _ in range(calls):
        fn(*args)
    return time.perf_counter() - start


def in_search_seconds(component, arg, calls: int) -> tuple[float, float, float]:
    """``calls`` evaluations of ``arg`` by the compiled loop the search runs (no Python calls): (wall
    seconds, CPU seconds of this process, states evaluated per call). A pruner stops checking a segment at
    its first failing sample, as the search does, so it may evaluate fewer states than it is handed."""
    if hasattr(component, "humans"):
        raise ValueError("in_search_seconds times heuristics and static pruners")
    if arg.ndim == 2:
        args = (component.kind, component.field, component.par, arg)
        heuristic_loop(*args, 1)  # compile / warm up
        wall, cpu = time.perf_counter(), time.process_time()
        heuristic_loop(*args, calls)
        evaluated = float(arg.shape[0])
    else:
        args = (component.kind, component.field, component.lower, component.par, arg)
        static_prune_loop(*args, 1)
        wall, cpu = time.perf_counter(), time.process_time()
        evaluated = static_prune_loop(*args, calls)[1] / calls
    return time.perf_counter() - wall, time.process_time() - cpu, evaluated


def table7_timings(planner, goal_xy, calls: int, n_states: int, n_samples: int, seed: int) -> list[dict]:
    """Our rows of Table VII: total seconds for ``calls`` batched Python calls, per call (µs) and per state
    (ns), and the same evaluations inside the compiled search loop (``in_search_*``: wall and CPU time,
    per state it evaluated)."""
    states, segments = expansion_inputs(planner, n_states, n_samples, seed)
    tol = planner.p.goal_tolerance_anastar_m
    rows = []
    for name, fn, arg, n in (
        ("TTR heuristic", planner.heuristic("TTR", goal_xy, tol), states, len(states)),
        ("Dist heuristic", planner.heuristic("Dist", goal_xy, tol), states, len(states)),
        ("BRT pruner", planner.pruner("BRT"), segments, segments.shape[0] * segments.shape[1]),
        ("OBS pruner", planner.pruner("OBS"), segments, segments.shape[0] * segments.shape[1]),
    ):
        total = time_calls(fn, (arg,), calls)
        wall, cpu, evaluated = in_search_seconds(fn, arg, calls)
        rows.append({"component": name, "states": int(n), "total_s": total, "per_call_us": total / calls * 1e6,
                     "per_state_ns": total / calls / n * 1e9, "in_search_total_s": wall,
                     "in_search_evaluated_states": evaluated,
                     "in_search_per_state_ns": wall / calls / evaluated * 1e9,
                     "in_search_cpu_per_state_ns": cpu / calls / evaluated * 1e9})
    return rows
