"""HJ-guided lattice search: look-ups and expansions per second, ours beside references in the same run.

1. TTR heuristic (35 states per call) and static-BRT pruner (140 segment samples per call), 10,000 calls:
   ours (compiled batched call) vs scipy's RegularGridInterpolator on the same grid, and per state vs the
   paper's Table VII (18.7 µs per TTR call, 24.7 µs per BRT call).
2. Lattice A* with the TTR heuristic and BRT pruner on: expansions per second of the compiled search vs
   the plain-Python heapq reference (numpy look-ups through reach.lookup) on the same tasks.

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
from navlab.reach.lookup import to_goal_frame
from navlab.reach.planning import Planner
from navlab.reach.precompute import build_hj_grids
from navlab.reach.timing import expansion_inputs, in_search_seconds, time_calls
from navlab.search.lattice_reference import astar_reference
from navlab.search.lattice_search import Goal, search

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
    args = parser.parse_args()
    params = load_params(args.profile)
    build_hj_grids(params, "unused", args.artifacts, progress=False, log=lambda m: None)
    planner = Planner(params, args.artifacts, "simulation", costs=False, margin=0.05, log=lambda m: None)
    goal = (6.0, 2.7)
    states, segments = expansion_inputs(planner, 35, 140, seed=0)
    ttr_ref, brt_ref = rgi(planner._ttr.stored), rgi(planner._brt.stored)

    def ttr_scipy(s):
        local = to_goal_frame(s, np.asarray(goal))
        local[:, 3] %= 2 * math.pi  # RGI's θ axis runs over [−π, π] with the repeated slice
        local[:, 3] -= math.pi
        return ttr_ref(local)

    def brt_scipy(seg):
        return (brt_ref(seg.reshape(-1, 4)) <= 0.05).reshape(seg.shape[:2]).any(axis=1)

    ours_h, ours_p = planner.heuristic("TTR", goal, 0.15), planner.pruner("BRT")
    print(f"profile {args.profile}: TTR grid {planner._ttr.grid.shape}, BRT grid {planner._brt.grid.shape}")
    for label, ours, ref, arg, n in (("TTR", ours_h, ttr_scipy, states, 35), ("BRT", ours_p, brt_scipy, segments, 140)):
        t_ours = time_calls(ours, (arg,), args.calls) / args.calls * 1e6
        t_ref = time_calls(ref, (arg,), max(args.calls // 10, 10)) / max(args.calls // 10, 10) * 1e6
        t_in = in_search_seconds(ours, arg, args.calls) / args.calls * 1e6
        print(f"{label} ({n} states/call): ours as a Python call {t_ours:.2f} µs/call, inside the compiled search "
              f"{t_in:.2f} µs ({t_in / n * 1e3:.1f} ns/state); RegularGridInterpolator {t_ref:.1f} µs/call "
              f"(ratio {t_ref / t_ours:.1f}x per call, {t_ref / t_in:.1f}x in-search); paper Table VII "
              f"{PAPER_US[label]} µs/call: ours {PAPER_US[label] / t_ours:.1f}x (call) / {PAPER_US[label] / t_in:.1f}x "
              f"(in-search) cheaper per state")

    rng = np.random.default_rng(0)
    spec, room = planner.spec, planner.room
    goal_obj = Goal(goal, 0.2, params.hj.planner.goal_max_speed)
    tot = {"ours": [0.0, 0], "ref": [0.0, 0]}
    brt_lookup, ttr_lookup = planner._brt, planner._ttr
    for k in range(args.tasks):
        start = np.array([1.0, 1.0 + 0.4 * k, 0.0, rng.uniform(-math.pi, math.pi)])
        t0 = time.perf_counter()
        ours = search(spec, room.bounds, start, goal_obj, ours_h, static=ours_p, table=planner.table,
                      max_expansions=args.max_expansions)
        t1 = time.perf_counter()
        cost, exp = astar_reference(spec, room.bounds, start, goal, 0.2, goal_obj.max_speed,
                                    lambda s: ttr_lookup(s, np.asarray(goal)),
                                    lambda seg: (brt_lookup(seg.reshape(-1, 4)) <= 0.05).reshape(
                                        seg.shape[:2]).any(axis=1), max_expansions=args.max_expansions)
        t2 = time.perf_counter()
        tot["ours"][0] += t1 - t0
        tot["ours"][1] += ours.expansions
        tot["ref"][0] += t2 - t1
        tot["ref"][1] += exp
        print(f"task {k}: cost ours {ours.cost:.2f} / reference {cost:.2f}; expansions {ours.expansions} / {exp}; "
              f"{t1 - t0:.3f} s / {t2 - t1:.3f} s")
    rate = {k: v[1] / v[0] for k, v in tot.items()}
    print(f"lattice A* with TTR + BRT: ours {rate['ours']:.3g} expansions/s, plain-Python heapq reference "
          f"{rate['ref']:.3g} expansions/s, ratio {rate['ours'] / rate['ref']:.1f}x")


if __name__ == "__main__":
    main()
