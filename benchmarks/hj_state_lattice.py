"""HJ-search Tables I-V on a true state lattice (issue 26 item 2): A* returns Dijkstra's cost whatever the
admissible heuristic.

For every task of params.yaml hj.planner.table1..table5 (start at rest, the tables' headings snapped to the
lattice's 16; Table V: ``hj.planning.random_pairs`` with seed hj.seed) it runs Dijkstra, A* with Dist and
A* with TTR on ``navlab.search.state_lattice`` and prints cost, expansions and search seconds, and whether
both A* costs equal Dijkstra's (|difference| <= 1e-9 s; they must).

TTR admissibility (the TTR grid deflated by δ, h = 0 on goal states): ``navlab.hj.state_lattice_runs``, which
runs the searches (shared with notebooks/hj/01_heuristics.ipynb's Table I rows); δ and the raw TTR's excess in
the task's room are printed (<= 0: admissible).
Table I also prints the costs of the paper-style continuous lattice (``hj.planning.Planner``,
A* + OBS, as notebooks/hj/01_heuristics.ipynb) beside.

Usage: python benchmarks/hj_state_lattice.py [--profile PROFILE] [--artifacts artifacts] [--pairs N] [--tables 1 2 3 4 5]
"""

from __future__ import annotations

import argparse
import math

from navlab.core.params import load_params
from navlab.hj.grids import load_ttr
from navlab.hj.planning import Planner, heading_tasks, random_pairs
from navlab.hj.state_lattice_runs import (
    DIJKSTRA,
    DIST,
    METHODS,
    TTR,
    make_setup,
    run_group,
    run_table,
    same_cost,
    settings_of,
)
from navlab.maps.rooms import load_room
from navlab.search.state_lattice import build_primitives


def continuous_costs(params, artifacts: str, table) -> list[tuple[float, float]]:
    """The paper-style lattice's Table I A* costs (Dist, TTR), as the notebook runs them."""
    planner = Planner(params, artifacts, table.room, costs=False, margin=0.0, log=lambda *a: None)
    return [tuple(planner.run(s, table.goal_xy, h, "OBS", "A*")[0].cost for h in ("Dist", "TTR"))
            for s in heading_tasks(table.start_xy, table.headings_deg)]


def print_rows(title: str, runs: dict[str, list], continuous=None) -> bool:
    print(f"\n{title}")
    print("start (x, y, θ deg -> lattice θ)    | Dijkstra cost exp s   | A*+Dist cost exp s    | A*+TTR cost exp s     "
          "| equal | TTR δ open / excess room" + (" | continuous Dist / TTR" if continuous else ""))
    ok = True
    for n, (d, a, t) in enumerate(zip(runs[DIJKSTRA], runs[DIST], runs[TTR], strict=True)):
        equal = same_cost(d, a) and same_cost(d, t)
        ok &= equal
        s = d.start
        line = (f"({s[0]:.2f}, {s[1]:.2f}, {math.degrees(s[3]):6.1f} -> {d.heading_deg:6.1f}) | "
                + " | ".join(f"{r.cost:7.3f} {r.expansions:6d} {r.seconds:5.2f}" for r in (d, a, t))
                + f" | {'yes' if equal else 'NO'}   | {d.delta:.1e} / {d.room_excess:+.1e}")
        if continuous:
            line += f" | {continuous[n][0]:.3f} / {continuous[n][1]:.3f}"
        print(line)
    return ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--profile", default=None, help="params.yaml's own profile unless given")
    parser.add_argument("--artifacts", default="artifacts")
    parser.add_argument("--pairs", type=int, default=None, help="Table V pairs (default: the profile's)")
    parser.add_argument("--tables", type=int, nargs="*", default=[1, 2, 3, 4, 5])
    args = parser.parse_args()
    params = load_params(args.profile)
    p = params.hj.planner
    settings = settings_of(params)
    primitives = build_primitives(settings)
    print(f"state lattice: cell {settings.cell_m} m, 16 headings, speeds {settings.speeds}, "
          f"{len(primitives.cost)} primitives ({len(primitives.cost) // (16 * len(settings.speeds))} or fewer "
          f"per start heading and speed), collision samples every <= {settings.sample_m} m")
    ttr = load_ttr(params, args.artifacts)
    ok = True
    for n in args.tables:
        table = getattr(p, f"table{n}")
        if n == 5:
            setup = make_setup(params, table.room, ttr, primitives)
            pairs = random_pairs(load_room(table.room), params.hj.grids.robot.radius_m, args.pairs or table.pairs,
                                 table.min_distance_m, params.hj.seed)
            runs = {m: [] for m in METHODS}
            for start, goal in pairs:
                for m, group in run_group(setup, start[:2], goal, [start]).items():
                    runs[m] += group
            ok &= print_rows(f"Table V ({table.room}, {len(pairs)} random pairs)", runs)
            continue
        runs = run_table(params, args.artifacts, table, ttr, primitives).results
        continuous = continuous_costs(params, args.artifacts, table) if n == 1 else None
        ok &= print_rows(f"Table {['I', 'II', 'III', 'IV'][n - 1]} ({table.room}, start {tuple(table.start_xy)}, "
                         f"goal {tuple(table.goal_xy)})", runs, continuous)
    print(f"\nA*+Dist and A*+TTR return Dijkstra's cost on every task: {'yes' if ok else 'NO'}")
    if not ok:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
