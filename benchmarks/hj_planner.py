"""HJ-guided lattice search: look-ups and expansions per second, ours beside references in the same run.

1. TTR heuristic (35 states per call) and static-BRT pruner (140 segment samples per call), 10,000 calls:
   ours (compiled batched call) vs scipy's RegularGridInterpolator on the same grid, and per state vs the
   paper's Table VII (18.7 µs per TTR call, 24.7 µs per BRT call).
2. Lattice A* with the TTR heuristic, BRT pruner and swept collision check on: expansions per second of
   the compiled search vs the plain-Python heapq reference (numpy look-ups through reach.lookup) on the
   same tasks.
3. The first step of every re-plan (``dubins_lattice.first_step``: the primitives from the car's measured
   speed, integrated per re-plan): compiled vs the plain-Python loop it replaced (``lattice_reference``), the
   same floats.

Grids are built (or re-used) for ``--profile`` under ``--artifacts``.
Usage: python benchmarks/hj_planner.py [--profile default] [--artifacts artifacts] [--calls 10000]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from navlab.core.params import load_params
from navlab.hj.grids import build_hj_grids
from navlab.hj.planning import Planner
from navlab.hj.timing import expansion_inputs, in_search_seconds, time_calls
from navlab.reach.lookup import to_goal_frame
from navlab.search.dubins_lattice import first_step
from navlab.search.lattice_reference import astar_reference, first_step_rows_reference
from navlab.search.lattice_search import Budget, Goal, Pruners, search

PAPER_US = {"TTR": 18.7, "BRT": 24.7}  # Table VII: 0.187 s and 0.247 s per 10,000 calls


def rgi(stored) -> RegularGridInterpolator:
    """scipy reference on a grid with θ made periodic by repeating its first slice at +π."""
    grid, values = stored.grid, np.asarray(stored.values)
    axes = [grid.axis(d) for d in range(grid.ndim)]
    if grid.periodic[-1]:
        axes[-1] = np.append(axes[-1], axes[-1][0] + 2 * math.pi)
        values = np.concatenate([values, values[..., :1]], axis=-1)
    return RegularGridInterpolator(axes, values, bounds_error=False, fill_value=None)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default="default")
    parser.add_argument("--artifacts", default="artifacts")
    parser.add_argument("--calls", type=int, default=10000)
    parser.add_argument("--tasks", type=int, default=3)
    parser.add_argument("--max-expansions", type=int, default=20000)
    parser.add_argument("--margin", type=float, default=None, help="BRT margin (default: the measured one, cached)")
    args = parser.parse_args()
    params = load_params(args.profile)
    build_hj_grids(params, "unused", args.artifacts, progress=False, log=lambda m: None)
    planner = Planner(params, args.artifacts, "simulation", costs=False, margin=args.margin, log=lambda m: None)
    margin = planner.margin
    goal = (6.0, 2.7)
    states, segments = expansion_inputs(planner, 35, 140, seed=0)
    ttr_ref, brt_ref = rgi(planner._ttr.stored), rgi(planner._brt.stored)

    def ttr_scipy(s):
        local = to_goal_frame(s, np.asarray(goal))
        local[:, 3] %= 2 * math.pi  # RGI's θ axis runs over [−π, π] with the repeated slice
        local[:, 3] -= math.pi
        return ttr_ref(local)

    def brt_scipy(seg):
        return (brt_ref(seg.reshape(-1, 4)) <= margin).reshape(seg.shape[:2]).any(axis=1)

    ours_h, ours_p = planner.heuristic("TTR", goal, 0.15), planner.pruner("BRT")
    print(f"profile {args.profile}: TTR grid {planner._ttr.grid.shape}, BRT grid {planner._brt.grid.shape}, "
          f"BRT margin {margin:.4f}; times are CPU seconds of this process (wall in brackets)")
    for label, ours, ref, arg, n in (("TTR", ours_h, ttr_scipy, states, 35), ("BRT", ours_p, brt_scipy, segments, 140)):
        t_ours = time_calls(ours, (arg,), args.calls) / args.calls * 1e6
        ref_calls = max(args.calls // 10, 10)
        t_ref = time_calls(ref, (arg,), ref_calls) / ref_calls * 1e6
        wall, cpu, evaluated = in_search_seconds(ours, arg, args.calls)
        t_in = cpu / args.calls * 1e6
        per_state = t_in / evaluated * 1e3
        paper_state = PAPER_US[label] / n * 1e3
        print(f"{label} ({n} states/call): compiled loop as the search runs it {t_in:.2f} µs/call "
              f"[{wall / args.calls * 1e6:.2f}], {evaluated:.0f} states evaluated per call, {per_state:.1f} ns/state; "
              f"as a Python call {t_ours:.2f} µs [wall]; RegularGridInterpolator {t_ref:.1f} µs/call [wall] "
              f"(ratio {t_ref / t_ours:.1f}x per Python call); paper Table VII {PAPER_US[label]} µs/call = "
              f"{paper_state:.0f} ns/state: ours {paper_state / per_state:.1f}x cheaper per evaluated state")

    rng = np.random.default_rng(0)
    spec, room = planner.spec, planner.room
    goal_obj = Goal(goal, 0.2, params.hj.planner.goal_max_speed)
    collision = planner.collision("BRT + swept OBS")  # our swept check beside the BRT (a "(ours)" row of the tables)
    search(spec, room.bounds, np.array([1.0, 1.0, 0.0, 0.0]), goal_obj, ours_h,
           pruners=Pruners(static=ours_p, collision=collision), table=planner.table,
           budget=Budget(max_expansions=10))  # compile outside the timing
    tot = {"ours": [0.0, 0.0, 0], "ref": [0.0, 0.0, 0]}
    brt_lookup, ttr_lookup = planner._brt, planner._ttr
    for k in range(args.tasks):
        start = np.array([1.0, 1.0 + 0.4 * k, 0.0, rng.uniform(-math.pi, math.pi)])
        w0, c0 = time.perf_counter(), time.process_time()
        ours = search(spec, room.bounds, start, goal_obj, ours_h,
                      pruners=Pruners(static=ours_p, collision=collision), table=planner.table,
                      budget=Budget(max_expansions=args.max_expansions))
        w1, c1 = time.perf_counter(), time.process_time()
        cost, exp = astar_reference(spec, room.bounds, start, goal, 0.2, goal_obj.max_speed,
                                    lambda s: ttr_lookup(s, np.asarray(goal)),
                                    lambda parent, seg: (brt_lookup(seg.reshape(-1, 4)) <= margin).reshape(
                                        seg.shape[:2]).any(axis=1) | collision.swept(
                                        np.broadcast_to(parent, (len(seg), 4)), seg, np.full(len(seg), spec.dt)),
                                    max_expansions=args.max_expansions)
        w2, c2 = time.perf_counter(), time.process_time()
        for key, wall, cpu, n in (("ours", w1 - w0, c1 - c0, ours.expansions), ("ref", w2 - w1, c2 - c1, exp)):
            tot[key][0] += wall
            tot[key][1] += cpu
            tot[key][2] += n
        print(f"task {k}: cost ours {ours.cost:.2f} / reference {cost:.2f}; expansions {ours.expansions} / {exp}; "
              f"CPU {c1 - c0:.3f} s / {c2 - c1:.3f} s")
    cpu = {k: v[2] / v[1] for k, v in tot.items()}
    wall = {k: v[2] / v[0] for k, v in tot.items()}
    print(f"lattice A* with TTR + BRT: ours {cpu['ours']:.3g} expansions per CPU second ({wall['ours']:.3g} per wall "
          f"second), plain-Python heapq reference {cpu['ref']:.3g} ({wall['ref']:.3g}), ratio "
          f"{cpu['ours'] / cpu['ref']:.0f}x")

    speeds = np.linspace(spec.v_min, spec.v_max, 37)[1:-1]  # off-level speeds, as measured ones are
    first_step(spec, float(speeds[0]))  # compiled (or loaded from numba's cache) before timing
    controls = [first_step(spec, float(v))[1] for v in speeds]
    c0 = time.process_time()
    ours = [first_step(spec, float(v))[0] for v in speeds]
    c1 = time.process_time()
    refs = [first_step_rows_reference(spec, float(v), c) for v, c in zip(speeds, controls)]
    c2 = time.process_time()
    same = all(np.array_equal(o[:, :-1], r[:, :-1]) for o, r in zip(ours, refs))
    print(f"first step ({len(spec.controls)} primitives): compiled {(c1 - c0) / len(speeds) * 1e3:.3f} ms per re-plan, "
          f"plain Python {(c2 - c1) / len(speeds) * 1e3:.3f} ms, ratio {(c2 - c1) / (c1 - c0):.0f}x; same floats: {same}")


if __name__ == "__main__":
    main()
