"""HJ-search Tables I-V on a true state lattice (issue 26 item 2): A* returns Dijkstra's cost whatever the
admissible heuristic.

For every task of params.yaml hj.planner.table1..table5 (start at rest, the tables' headings snapped to the
lattice's 16; Table V: ``hj.planning.random_pairs`` with seed hj.seed) it runs Dijkstra, A* with Dist and
A* with TTR on ``navlab.search.state_lattice`` and prints cost, expansions and search seconds, and whether
both A* costs equal Dijkstra's (|difference| <= 1e-9 s; they must).

TTR admissibility: the goal-frame TTR grid can exceed the lattice's cost-to-go through its interpolation
error. At the goal states themselves (cost-to-go 0) the search sets every h to 0 (``Lattice.heuristic_table``:
interpolating across the goal disc's rim gave TTR up to ~2 s there). Elsewhere, its largest excess δ over
the lattice's exact cost-to-go is measured on the *open* room (the same walls, no obstacles) with the task's
lattice anchoring and goal (``Lattice.cost_to_go``: backward Dijkstra over every lattice state); obstacles
only remove primitives, so cost-to-go in the task's room is >= the open room's and max(TTR − δ, 0) is
admissible in any room. δ and the raw TTR's excess in the task's room are printed (<= 0: admissible).
Table I also prints the costs of the paper-style continuous lattice (``hj.planning.Planner``,
A* + OBS, as notebooks/hj/01_heuristics.ipynb) beside.

Usage: python benchmarks/hj_state_lattice.py [--artifacts artifacts] [--pairs N] [--tables 1 2 3 4 5]
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

import numpy as np

from navlab.core.params import load_params
from navlab.hj.guidance import ttr_heuristic
from navlab.hj.planning import Planner, heading_tasks, random_pairs
from navlab.hj.pruners import clearance_field, field_error
from navlab.maps.rooms import load_room
from navlab.reach.lookup import TTRLookup
from navlab.reach.precompute import load_ttr
from navlab.search.lattice_fields import wrap
from navlab.search.state_lattice import (
    ANGLES,
    Car,
    Clearance,
    Goal,
    Lattice,
    LatticeSettings,
    Primitives,
    build_primitives,
    deflated,
    dist_heuristic,
)

TOLERANCE_S = 1e-9


@dataclass(frozen=True)
class Setup:
    """What every task shares: settings, primitives, the rooms' clearances, the TTR look-up, the goal."""

    settings: LatticeSettings
    primitives: Primitives
    room: Clearance
    open_room: Clearance
    ttr: TTRLookup
    goal_tolerance: float
    goal_speed: float


def clearance(name: str, radius: float) -> Clearance:
    field = clearance_field(load_room(name))
    return Clearance(field, field_error(field), radius)


def run_group(setup: Setup, start_xy, goal_xy, starts) -> list[dict]:
    """One start position and goal with several start states: δ from the open room, then the searches."""
    goal = Goal(tuple(map(float, goal_xy)), setup.goal_tolerance, setup.goal_speed)
    ttr = ttr_heuristic(setup.ttr, goal.xy)
    open_lattice = Lattice(setup.settings, setup.open_room, start_xy, setup.primitives)
    delta = max(open_lattice.excess(ttr, goal, open_lattice.cost_to_go(goal)), 0.0)
    lattice = Lattice(setup.settings, setup.room, start_xy, setup.primitives)
    room_excess = lattice.excess(ttr, goal, lattice.cost_to_go(goal))
    heuristics = {"Dijkstra": None, "Dist": dist_heuristic(goal, setup.settings.car.v_max),
                  "TTR": deflated(ttr, delta)}
    rows = []
    for start in starts:
        row = {"start": start, "goal": goal.xy, "delta": delta, "room_excess": room_excess,
               "heading": math.degrees(ANGLES[int(np.argmin(np.abs(wrap(ANGLES - start[3]))))])}
        for name, h in heuristics.items():
            row[name] = lattice.search(start, goal, h)
        rows.append(row)
    return rows


def continuous_costs(params, artifacts: str, table) -> list[tuple[float, float]]:
    """The paper-style lattice's Table I A* costs (Dist, TTR), as the notebook runs them."""
    planner = Planner(params, artifacts, table.room, costs=False, margin=0.0, log=lambda *a: None)
    return [tuple(planner.run(s, table.goal_xy, h, "OBS", "A*")[0].cost for h in ("Dist", "TTR"))
            for s in heading_tasks(table.start_xy, table.headings_deg)]


def print_rows(title: str, rows: list[dict], continuous=None) -> bool:
    print(f"\n{title}")
    print("start (x, y, θ deg -> lattice θ)    | Dijkstra cost exp s   | A*+Dist cost exp s    | A*+TTR cost exp s     "
          "| equal | TTR δ open / excess room" + (" | continuous Dist / TTR" if continuous else ""))
    ok = True
    for n, row in enumerate(rows):
        d, a, t = row["Dijkstra"], row["Dist"], row["TTR"]
        equal = all(r.found == d.found and (not d.found or abs(r.cost - d.cost) <= TOLERANCE_S) for r in (a, t))
        ok &= equal
        s = row["start"]
        line = (f"({s[0]:.2f}, {s[1]:.2f}, {math.degrees(s[3]):6.1f} -> {row['heading']:6.1f}) | "
                + " | ".join(f"{r.cost:7.3f} {r.expansions:6d} {r.seconds:5.2f}" for r in (d, a, t))
                + f" | {'yes' if equal else 'NO'}   | {row['delta']:.1e} / {row['room_excess']:+.1e}")
        if continuous:
            line += f" | {continuous[n][0]:.3f} / {continuous[n][1]:.3f}"
        print(line)
    return ok


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--artifacts", default="artifacts")
    parser.add_argument("--pairs", type=int, default=None, help="Table V pairs (default: the profile's)")
    parser.add_argument("--tables", type=int, nargs="*", default=[1, 2, 3, 4, 5])
    args = parser.parse_args()
    params = load_params()
    p, robot = params.hj.planner, params.hj.grids.robot
    settings = LatticeSettings(Car.from_params(params))
    primitives = build_primitives(settings)
    print(f"state lattice: cell {settings.cell_m} m, 16 headings, speeds {settings.speeds}, "
          f"{len(primitives.cost)} primitives ({len(primitives.cost) // (16 * len(settings.speeds))} or fewer "
          f"per start heading and speed), collision samples every <= {settings.sample_m} m")
    ttr = load_ttr(params, args.artifacts)
    ok = True
    for n in args.tables:
        table = getattr(p, f"table{n}")
        setup = Setup(settings, primitives, clearance(table.room, robot.radius_m), clearance("open", robot.radius_m),
                      ttr, p.goal_tolerance_astar_m, p.goal_max_speed)
        if n == 5:
            pairs = random_pairs(load_room(table.room), robot.radius_m, args.pairs or table.pairs,
                                 table.min_distance_m, params.hj.seed)
            rows = [row for start, goal in pairs for row in run_group(setup, start[:2], goal, [start])]
            ok &= print_rows(f"Table V ({table.room}, {len(pairs)} random pairs)", rows)
            continue
        starts = heading_tasks(table.start_xy, table.headings_deg)
        rows = run_group(setup, table.start_xy, table.goal_xy, starts)
        continuous = continuous_costs(params, args.artifacts, table) if n == 1 else None
        ok &= print_rows(f"Table {['I', 'II', 'III', 'IV'][n - 1]} ({table.room}, start {tuple(table.start_xy)}, "
                         f"goal {tuple(table.goal_xy)})", rows, continuous)
    print(f"\nA*+Dist and A*+TTR return Dijkstra's cost on every task: {'yes' if ok else 'NO'}")
    if not ok:
        raise SystemExit(1)


if __name__ == "__main__":
    main()
